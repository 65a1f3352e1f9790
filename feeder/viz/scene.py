"""The MeshCat scene of a feeding cycle: the device's visuals, the barrel axis, the payload's
path, force arrows to one scale, the floor grid and the camera, animated over the cycle.

The scene lives under the node ``feeder`` in device coordinates (y up), turned onto MeshCat's
z-up world and centred on the device, whose centre is the camera's orbit target. The force
arrows and the payload's path are drawn unlit, over the bodies (no depth test, rendered last):
they start at points inside the bodies (a pivot, a centre of gravity) and would otherwise be
hidden at most poses. Every colour drawn has an entry in :attr:`DrawnCycle.legend`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import meshcat
import meshcat.animation
import meshcat.geometry as mg
import meshcat.transformations as mtf
import numpy as np
import pinocchio as pin
from lxml import etree
from pinocchio.visualize import MeshcatVisualizer

from ..device.feeder import Feeder
from ..motion.cycle import CycleKinematics

FRAME_RATE = 40.0
"""Animation key frames per second of cycle time [1/s]; the 1 kHz cycle is subsampled."""

ARROW_LENGTH = 0.45
"""Drawn length [m] of the largest force over the cycle; all arrows share one scale [N/m]. A
third of the device's size, so that a force a tenth of the largest is still drawn 45 mm long
(tests/viz/test_viewer.py checks that every such arrow shows on screen at every stage)."""

CAMERA_AZIMUTH, CAMERA_ELEVATION = math.radians(35.0), math.radians(25.0)
"""Default view direction [rad]: from the +z side, turned towards +x, looking down."""

CAMERA_FOV = math.radians(75.0)
"""MeshCat's default camera: vertical field of view [rad]."""

ForceSeries = tuple[np.ndarray, np.ndarray]
"""(force, point): forces [N] and their application points [m] in the device's world frame
(x horizontal, y up), each (N, 3), one row per cycle sample."""

_ROOT = "feeder"
_DEVICE = f"{_ROOT}/device"
_ANIMATION = "animation"
_BARREL_COLOR, _PATH_COLOR, _GRID_COLOR = 0xCC2222, 0xD4A017, 0x8A8F99
_BACKGROUND = ((0.93, 0.94, 0.95), (0.62, 0.65, 0.70))  # MeshCat gradient, top and bottom RGB
_GRID_STEP = 0.1  # [m] floor grid squares
ARROW_COLORS = (0x8E24AA, 0x00ACC1, 0xD81B60, 0x00C853, 0xFF6D00, 0x3949AB)
"""Colours of the force arrows, in the order the forces are given: none is a device colour."""
_ARROW_RADIUS, _HEAD_LENGTH, _HEAD_RADIUS = 0.010, 0.06, 0.025  # [m]
_ON_TOP = 10  # render order of the arrows and the path: after the bodies, over them
_LINK_NUMBERS = {"cylinder": 1, "piston": 2, "arm": 3, "forearm": 4}  # the paper's numbering
_INVISIBLE = 1e-6  # scale of a zero-length arrow part (a zero scale makes a singular matrix)
_FRAME_FILL = 0.9  # the scene's extent fills at most this share of the camera's view
_BARREL_RADIUS, _BARREL_BEHIND, _BARREL_AHEAD = 0.006, 0.4, 0.8  # [m] around the rammed CG
# Device (y up) → MeshCat world (z up): a quarter turn about x.
_DEVICE_TO_MESHCAT = mtf.rotation_matrix(math.pi / 2.0, [1.0, 0.0, 0.0])


@dataclass(frozen=True)
class LegendEntry:
    """One colour of the scene and what it shows.

    Attributes:
        color: CSS colour, ``#rrggbb``.
        mark: How it is drawn: ``"body"``, ``"line"`` or ``"arrow"``.
        label: What it is.
    """

    color: str
    mark: str
    label: str


@dataclass(frozen=True)
class DrawnCycle:
    """What :func:`draw_cycle` drew.

    Attributes:
        newtons_per_metre: Scale of the force arrows [N/m] (0 without forces).
        legend: Every colour of the scene with what it shows.
        boundaries: Stage boundaries (0, T1, T1 + T2, T) [s]: the animation's time line.
    """

    newtons_per_metre: float
    legend: tuple[LegendEntry, ...]
    boundaries: tuple[float, ...]


def _css(color: int) -> str:
    return f"#{color:06x}"


def _device_legend(feeder: Feeder) -> list[LegendEntry]:
    """The URDF's visual materials, once each, in the order of the file."""
    entries: dict[str, LegendEntry] = {}
    for material in etree.fromstring(feeder.urdf.encode("utf-8")).iter("material"):
        color = material.find("color")
        if color is None or material.get("name") in entries:
            continue
        r, g, b = (int(255 * float(x)) for x in color.get("rgba").split()[:3])  # as Pinocchio
        name = material.get("name")
        if name == "projectile":
            label = f"payload ({feeder.params.payload_name})"
        elif name == "pin":
            label = "pins"
        elif name in _LINK_NUMBERS:
            label = f"{name} (link {_LINK_NUMBERS[name]})"
        else:
            label = name
        entries[name] = LegendEntry(f"#{r:02x}{g:02x}{b:02x}", "body", label)
    return list(entries.values())


def _homogeneous(rotation: np.ndarray, translation: np.ndarray) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3] = rotation
    out[:3, 3] = translation
    return out


def _y_onto(direction: np.ndarray) -> np.ndarray:
    """A rotation (3, 3) turning the y axis onto the unit vector ``direction``."""
    y = np.array([0.0, 1.0, 0.0])
    axis = np.cross(y, direction)
    sine, cosine = np.linalg.norm(axis), float(y @ direction)
    if sine < 1e-9:
        return np.eye(3) if cosine > 0.0 else np.diag([1.0, -1.0, -1.0])
    return pin.AngleAxis(math.atan2(sine, cosine), axis / sine).matrix()


def _geometry_radius(geometry_object: pin.GeometryObject) -> float:
    """Radius [m] of a sphere about the geometry's origin that contains it (box or cylinder)."""
    shape = geometry_object.geometry
    if hasattr(shape, "halfSide"):
        return float(np.linalg.norm(shape.halfSide))
    return float(math.hypot(shape.radius, shape.halfLength))


def _placements(
    feeder: Feeder, visual_model: pin.GeometryModel, cycle: CycleKinematics, samples: np.ndarray
) -> np.ndarray:
    """World placements (len(samples), n_geometries, 4, 4) of the visual geometries.

    Before the grip (payload = 0) the payload's geometries stay where they are gripped."""
    model = feeder.model
    data, visual_data = model.createData(), pin.GeometryData(visual_model)
    on_payload = np.array(
        [model.frames[g.parentFrame].name == "projectile" for g in visual_model.geometryObjects]
    )

    def at(i: int) -> np.ndarray:
        pin.forwardKinematics(model, data, feeder.to_pinocchio(cycle.q[i]))
        pin.updateGeometryPlacements(model, data, visual_model, visual_data)
        return np.array([placement.homogeneous for placement in visual_data.oMg])

    gripped = at(int(np.argmax(cycle.gripped)))
    out = np.empty((samples.size, len(visual_model.geometryObjects), 4, 4))
    for k, i in enumerate(samples):
        out[k] = at(i)
        if not cycle.gripped[i]:
            out[k, on_payload] = gripped[on_payload]
    return out


def _arrows(force: np.ndarray, point: np.ndarray, newtons_per_metre: float) -> dict:
    """Placements of one force's arrow at n samples; ``force``, ``point`` (n, 3) [N], [m].

    The arrow starts at the point and is ``|force| / newtons_per_metre`` long; its head is at
    most a third of it. Shaft and head are MeshCat cylinders along y, of unit height and of
    height :data:`_HEAD_LENGTH`, scaled by ``shaft_scale`` and ``head_scale``.

    Returns:
        ``shaft``, ``head``: rigid placements (n, 4, 4); ``shaft_scale``, ``head_scale``:
        scale factors (n, 3); ``tip``: arrow tips (n, 3) [m].
    """
    magnitude = np.linalg.norm(force, axis=1)
    length = magnitude / newtons_per_metre if newtons_per_metre > 0.0 else 0.0 * magnitude
    direction = np.where(magnitude[:, None] > 0.0, force, [0.0, 1.0, 0.0])
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    head = np.clip(length / (3.0 * _HEAD_LENGTH), _INVISIBLE, 1.0)
    shaft = np.maximum(length - head * _HEAD_LENGTH, _INVISIBLE)
    rotations = [_y_onto(d) for d in direction]
    shaft_centres = point + direction * (shaft / 2.0)[:, None]
    head_centres = point + direction * (length - head * _HEAD_LENGTH / 2.0)[:, None]
    return {
        "shaft": np.array(
            [_homogeneous(*rc) for rc in zip(rotations, shaft_centres, strict=True)]
        ),
        "head": np.array([_homogeneous(*rc) for rc in zip(rotations, head_centres, strict=True)]),
        "shaft_scale": np.column_stack([np.ones_like(shaft), shaft, np.ones_like(shaft)]),
        "head_scale": np.repeat(head[:, None], 3, axis=1),
        "tip": point + direction * length[:, None],
    }


def _floor_grid(low: np.ndarray, high: np.ndarray) -> mg.LineSegments:
    """Square grid of :data:`_GRID_STEP` on the horizontal plane under the box ``low``–``high``
    (device frame, [m]), one step wider on every side."""
    xs = np.arange(math.floor(low[0] / _GRID_STEP) - 1, math.ceil(high[0] / _GRID_STEP) + 2)
    zs = np.arange(math.floor(low[2] / _GRID_STEP) - 1, math.ceil(high[2] / _GRID_STEP) + 2)
    xs, zs = xs * _GRID_STEP, zs * _GRID_STEP
    ends = [((x, zs[0]), (x, zs[-1])) for x in xs] + [((xs[0], z), (xs[-1], z)) for z in zs]
    points = np.array([(x, low[1], z) for segment in ends for x, z in segment], dtype=np.float32)
    return mg.LineSegments(mg.PointsGeometry(points.T), mg.LineBasicMaterial(color=_GRID_COLOR))


def _camera_position(points: np.ndarray, reach: np.ndarray) -> np.ndarray:
    """Camera position (3,) [m] relative to the orbit centre, device axes: along the default
    view direction, at the smallest distance at which every sphere (centres ``points`` (n, 3)
    relative to the orbit centre, radii ``reach`` (n,)) is inside the field of view."""
    view = np.array(
        [
            math.sin(CAMERA_AZIMUTH) * math.cos(CAMERA_ELEVATION),
            math.sin(CAMERA_ELEVATION),
            math.cos(CAMERA_AZIMUTH) * math.cos(CAMERA_ELEVATION),
        ]
    )
    up = np.array([0.0, 1.0, 0.0]) - math.sin(CAMERA_ELEVATION) * view
    up /= np.linalg.norm(up)
    right = np.cross(up, view)
    lateral = np.maximum(np.abs(points @ right), np.abs(points @ up)) + reach
    half_width = math.tan(CAMERA_FOV / 2.0) * _FRAME_FILL
    return view * float(np.max(points @ view + lateral / half_width))


def _frame_scene(vis: meshcat.Visualizer, points: np.ndarray, reach: np.ndarray) -> None:
    """Centre the scene on the box around every drawn sphere (centres ``points`` (n, 3),
    radii ``reach`` (n,), device frame [m]), which the camera orbits; floor grid under it."""
    low = (points - reach[:, None]).min(axis=0)
    high = (points + reach[:, None]).max(axis=0)
    centre = (low + high) / 2.0
    device_to_world = _DEVICE_TO_MESHCAT @ _homogeneous(np.eye(3), -centre)
    vis[_ROOT].set_transform(device_to_world)
    vis["/Axes"].set_transform(device_to_world)  # MeshCat's triad: device axes at B
    vis["/Grid"].set_property("visible", False)  # 20 m wide: replaced by a floor to scale
    vis[f"{_ROOT}/floor"].set_object(_floor_grid(low, high))
    vis["/Background"].set_property("top_color", _BACKGROUND[0])
    vis["/Background"].set_property("bottom_color", _BACKGROUND[1])
    # The camera lives in MeshCat's "rotated" frame, whose axes are the device's.
    vis["/Cameras/default/rotated/<object>"].set_property(
        "position", _camera_position(points - centre, reach).tolist()
    )


def _draw_references(vis: meshcat.Visualizer, cycle: CycleKinematics) -> np.ndarray:
    """Draw the barrel axis and the payload's path; return the axis' ends (2, 3) [m]."""
    direction = np.array([-math.cos(cycle.elevation), math.sin(cycle.elevation), 0.0])
    rammed = cycle.payload_position[-1]
    ends = np.array([rammed - _BARREL_BEHIND * direction, rammed + _BARREL_AHEAD * direction])
    barrel = vis[f"{_ROOT}/barrel_axis"]
    barrel.set_object(
        mg.Cylinder(_BARREL_BEHIND + _BARREL_AHEAD, _BARREL_RADIUS),
        mg.MeshLambertMaterial(color=_BARREL_COLOR),
    )
    barrel.set_transform(_homogeneous(_y_onto(direction), ends.mean(axis=0)))
    path = cycle.payload_position[cycle.gripped == 1].T.astype(np.float32)
    vis[f"{_ROOT}/payload_path"].set_object(
        mg.Line(mg.PointsGeometry(path), mg.LineBasicMaterial(color=_PATH_COLOR, depthTest=False))
    )
    vis[f"{_ROOT}/payload_path"].set_property("renderOrder", _ON_TOP)
    return ends


def draw_cycle(
    viz: MeshcatVisualizer, feeder: Feeder, cycle: CycleKinematics, forces: dict[str, ForceSeries]
) -> DrawnCycle:
    """Draw and animate the cycle in ``viz``; return the arrows' scale and the legend."""
    vis = viz.viewer
    viz.loadViewerModel(rootNodeName=_DEVICE)
    step = max(1, round(cycle.spec.rate / FRAME_RATE))
    samples = np.unique(np.append(np.arange(0, cycle.t.size, step), cycle.t.size - 1))
    geometries = viz.visual_model.geometryObjects
    nodes = [viz.getViewerNodeName(g, pin.GeometryType.VISUAL) for g in geometries]
    placements = _placements(feeder, viz.visual_model, cycle, samples)
    points = [placements[:, :, :3, 3].reshape(-1, 3), _draw_references(vis, cycle)]
    reach = [np.tile([_geometry_radius(g) for g in geometries], samples.size), np.zeros(2)]

    peak = max((float(np.linalg.norm(f, axis=1).max()) for f, _ in forces.values()), default=0.0)
    newtons_per_metre = peak / ARROW_LENGTH
    legend = _device_legend(feeder) + [
        LegendEntry(
            _css(_BARREL_COLOR), "line", f"barrel axis at ε = {math.degrees(cycle.elevation):g}°"
        ),
        LegendEntry(
            _css(_PATH_COLOR), "line", "payload path (its centre of gravity, once gripped)"
        ),
        LegendEntry(_css(_GRID_COLOR), "line", f"floor grid, {_GRID_STEP:g} m squares"),
    ]
    arrows = {}
    for k, (name, (force, point)) in enumerate(forces.items()):
        node = f"{_ROOT}/forces/{name}"
        color = ARROW_COLORS[k % len(ARROW_COLORS)]
        legend.append(LegendEntry(_css(color), "arrow", name))
        material = mg.MeshBasicMaterial(color=color, depthTest=False)
        vis[f"{node}/shaft"].set_object(mg.Cylinder(1.0, _ARROW_RADIUS), material)
        vis[f"{node}/head"].set_object(
            mg.Cylinder(_HEAD_LENGTH, radiusTop=0.0, radiusBottom=_HEAD_RADIUS), material
        )
        for part in ("shaft", "head"):
            vis[f"{node}/{part}"].set_property("renderOrder", _ON_TOP)
        arrows[node] = _arrows(force[samples], point[samples], newtons_per_metre)
        points += [point[samples], arrows[node]["tip"]]
        reach += [np.zeros(samples.size), np.full(samples.size, _HEAD_RADIUS)]
    _frame_scene(vis, np.concatenate(points), np.concatenate(reach))

    animation = meshcat.animation.Animation(default_framerate=FRAME_RATE)
    for k, i in enumerate(samples):
        with animation.at_frame(vis, cycle.t[i] * FRAME_RATE) as frame:
            for node, placement in zip(nodes, placements[k], strict=True):
                frame[node].set_transform(placement)
            for node, arrow in arrows.items():
                for part in ("shaft", "head"):
                    frame[f"{node}/{part}"].set_transform(arrow[part][k])
                    frame[f"{node}/{part}"].set_property(
                        "scale", "vector3", arrow[f"{part}_scale"][k].tolist()
                    )
    # Kept on a node of its own, created last: MeshCat sends a scene node by node in creation
    # order, so the animation comes after every set_transform (Pinocchio's included) and a
    # late transform cannot undo a pause at a chosen time.
    vis[_ANIMATION].set_animation(animation, play=True, repetitions=1)
    return DrawnCycle(
        newtons_per_metre, tuple(legend), tuple(float(b) for b in cycle.spec.boundaries)
    )
