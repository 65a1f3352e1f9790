"""The MeshCat scene of a feeding cycle (:mod:`feeder.viz.scene` with the device's own parts):
the device's visuals, the barrel axis, the payload's path and the force arrows, animated over
the cycle, device coordinates (y up). On a vehicle (a :class:`~feeder.chain.model.base.BaseMotion`)
all of them ride on the hull's moving node, :data:`~feeder.viz.scene.BASE`."""

from __future__ import annotations

import math

import meshcat.geometry as mg
import numpy as np
import pinocchio as pin
from lxml import etree
from pinocchio.visualize import MeshcatVisualizer

from ..chain.model.base import BaseMotion
from ..device.feeder import Feeder
from ..motion.cycle import CycleKinematics
from .scene import (
    ARROW_LENGTH,
    BASE,
    ON_TOP,
    Arrows,
    DrawnScene,
    ForceSeries,
    LegendEntry,
    base_placements,
    css,
    draw_scene,
    geometry_placements,
    geometry_sphere,
    homogeneous,
    joint_placements,
    material_css,
    sphere_centres,
    up_of,
    y_onto,
)

STAGES = (
    "the empty forearm swings to the conveyor",
    "the forearm swings back with the payload",
    "the arm lifts the payload to the barrel",
)
"""What happens in each stage of the cycle (REFERENCE.md, section "The feeding cycle")."""

DEVICE = f"{BASE}/device"
"""The device's bodies' node (Pinocchio's visual model under ``visuals``)."""
_BARREL_COLOR, _PATH_COLOR = 0xCC2222, 0xD4A017
_LINK_NUMBERS = {"cylinder": 1, "piston": 2, "arm": 3, "forearm": 4}  # the paper's numbering
_BARREL_RADIUS, _BARREL_BEHIND, _BARREL_AHEAD = 0.006, 0.4, 0.8  # [m] around the rammed CG


def _device_legend(feeder: Feeder) -> list[LegendEntry]:
    """The URDF's visual materials, once each, in the order of the file."""
    entries: dict[str, LegendEntry] = {}
    for material in etree.fromstring(feeder.urdf.encode("utf-8")).iter("material"):
        color = material.find("color")
        if color is None or material.get("name") in entries:
            continue
        name = material.get("name")
        if name == "projectile":
            label = f"payload ({feeder.params.payload_name})"
        elif name == "pin":
            label = "pins"
        elif name in _LINK_NUMBERS:
            label = f"{name} (link {_LINK_NUMBERS[name]})"
        else:
            label = name
        entries[name] = LegendEntry(material_css(color.get("rgba").split()), "body", label)
    return list(entries.values())


def _placements(
    feeder: Feeder, visual_model: pin.GeometryModel, cycle: CycleKinematics
) -> np.ndarray:
    """World placements (N, n_geometries, 4, 4) of the visual geometries over the cycle.

    Before the grip (payload = 0) the payload's geometries stay where they are gripped."""
    model = feeder.model
    out = geometry_placements(joint_placements(model, feeder.to_pinocchio(cycle.q)), visual_model)
    on_payload = np.array(
        [model.frames[g.parentFrame].name == "projectile" for g in visual_model.geometryObjects]
    )
    gripped = out[int(np.argmax(cycle.gripped))]
    waiting = cycle.gripped == 0
    out[np.ix_(waiting, on_payload)] = gripped[on_payload]
    return out


def _draw_references(vis, cycle: CycleKinematics) -> np.ndarray:
    """Draw the barrel axis and the payload's path; return the axis' ends (2, 3) [m]."""
    direction = np.array([-math.cos(cycle.elevation), math.sin(cycle.elevation), 0.0])
    rammed = cycle.payload_position[-1]
    ends = np.array([rammed - _BARREL_BEHIND * direction, rammed + _BARREL_AHEAD * direction])
    barrel = vis[f"{BASE}/barrel_axis"]
    barrel.set_object(
        mg.Cylinder(_BARREL_BEHIND + _BARREL_AHEAD, _BARREL_RADIUS),
        mg.MeshLambertMaterial(color=_BARREL_COLOR),
    )
    barrel.set_transform(homogeneous(y_onto(direction), ends.mean(axis=0)))
    path = cycle.payload_position[cycle.gripped == 1].T.astype(np.float32)
    vis[f"{BASE}/payload_path"].set_object(
        mg.Line(mg.PointsGeometry(path), mg.LineBasicMaterial(color=_PATH_COLOR, depthTest=False))
    )
    vis[f"{BASE}/payload_path"].set_property("renderOrder", ON_TOP)
    return ends


def draw_cycle(
    viz: MeshcatVisualizer,
    feeder: Feeder,
    cycle: CycleKinematics,
    forces: dict[str, ForceSeries],
    base: BaseMotion | None = None,
) -> DrawnScene:
    """Draw and animate the cycle in ``viz``, with the arrows of ``forces`` (device axes) and on
    the vehicle's moving hull of ``base`` (None: standing level); return the arrows' scale and
    the legend."""
    vis = viz.viewer
    viz.loadViewerModel(rootNodeName=DEVICE)
    geometries = viz.visual_model.geometryObjects
    nodes = [viz.getViewerNodeName(g, pin.GeometryType.VISUAL) for g in geometries]
    placements = _placements(feeder, viz.visual_model, cycle)
    ends = _draw_references(vis, cycle)
    centres, radii = zip(*(geometry_sphere(g) for g in geometries), strict=True)
    points = sphere_centres(placements, np.array(centres))
    tracks = {node: placements[:, k] for k, node in enumerate(nodes)}
    gravity = feeder.model.gravity.linear
    state = None if base is None else base.state(cycle.t, gravity)
    parts = draw_scene(
        vis, cycle.t, tracks, points, np.array(radii), Arrows(forces, {}), up_of(gravity),
        fixed=ends, base=base_placements(state), length=ARROW_LENGTH,
    )  # fmt: skip
    triad = "axes at the cylinder pivot B" if base is None else "level axes at B at rest"
    legend = _device_legend(feeder) + [
        LegendEntry(
            css(_BARREL_COLOR), "line", f"barrel axis at ε = {math.degrees(cycle.elevation):g}°"
        ),
        LegendEntry(
            css(_PATH_COLOR), "line", "payload path (its centre of gravity, once gripped)"
        ),
        *parts.legend,
    ]
    return DrawnScene(
        newtons_per_metre=parts.newtons_per_metre,
        moment_scale=0.0,
        arrow_length=parts.arrow_length,
        legend=tuple(legend),
        boundaries=tuple(float(b) for b in cycle.spec.boundaries),
        stages=STAGES,
        slow_motion=parts.slow_motion,
        axes=f"{triad}: x red, y green (up), z blue",
    )
