"""The MeshCat scene of a user's mechanism (:mod:`feeder.viz.scene` with a mechanism's parts):
its bodies, its closure cuts and its load arrows, animated over its motion.

Bodies: the URDF's visuals — meshes (STL, DAE, OBJ; ``package://``, ``file://`` and relative
paths resolved inside the model's folder, :func:`~feeder.chain.readers.urdf.mesh_path`) or
primitives — with their materials' colours. A visual whose mesh file is not found, lies outside
the model's folder or does not load is left out, with one warning per kind naming the files
(:func:`visual_model`; the legend names the bodies left out). A model without visuals (an MJCF or
SDF file, a URDF whose links have none, or none of whose mesh files are usable) is drawn as a
stick figure: a ball at every joint and a rod from each joint to its children's joints and to
the closure frames on its body.

Arrows, from the loads table of :class:`~feeder.study.view.MechanismView`: each actuated
joint's drive load at the joint's origin (a prismatic joint's force along its axis; a revolute
joint's moment as a vector along its axis, right-hand rule, to a scale of its own), the
reaction force (parent on child) of the joints picked, by default the
:data:`DEFAULT_REACTIONS` with the largest peak force, and the mount's force on the mechanism
(:data:`MOUNT_FORCE`) at the model's origin. The closure cuts are marked by balls at each cut's
first frame.

On a vehicle (the mechanism file's ``[base]``) the bodies, cuts and arrows ride on the base's
moving node (:data:`~feeder.viz.scene.BASE`) over a flat box, the hull, that shows its motion;
every arrow's vector is in the model's moving axes (the mount's from its
``mount_force_vehicle_x|y|z`` columns).
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from pathlib import Path

import meshcat.geometry as mg
import numpy as np
import pinocchio as pin
from lxml import etree
from pinocchio.visualize import MeshcatVisualizer

from ..chain.kinematics.joints import joint_axes, kind_of
from ..chain.readers.model_files import inside_folder, mesh_references
from ..chain.readers.urdf import mesh_path, parse_xml_file
from ..exceptions import FeederWarning, InputError, ModelFolderError, UrdfError
from ..study.analyze import column_stem
from ..study.view import MechanismView
from .scene import (
    BASE,
    ON_TOP,
    Arrows,
    DrawnScene,
    ForceSeries,
    LegendEntry,
    attached,
    base_placements,
    css,
    draw_scene,
    extent_of,
    geometry_placements,
    geometry_sphere,
    joint_placements,
    material_css,
    sphere_centres,
    up_of,
)

DEFAULT_REACTIONS = 3
"""Joints whose reaction force is drawn when the user picks none: those of largest peak."""

BODIES = f"{BASE}/mechanism"
"""The bodies' node (Pinocchio's visual model under ``visuals``)."""
MOUNT_FORCE = "mount force (vehicle or ground on mechanism) [N]"
"""The name (and legend label) of the mount's arrow."""
_CUTS = f"{BASE}/cuts"
_CUT_COLOR = 0xE53935
_CUT_SHARE = 0.012  # a cut marker's radius per metre of the mechanism's extent
_STICK_COLOR = (0.55, 0.60, 0.68, 1.0)  # RGBA of a stick figure's balls and rods
_STICK_SHARE = 0.015  # a stick figure's rod radius per metre of the mechanism's extent
ROUND_OFF = 1e-9
"""A drive load below this share of the largest reaction force (times the mechanism's size for a
moment) is round-off, not drawn: the loads come from solves whose relative error is ~1e-12 of
the largest load (condition numbers up to ~1e3 on the shipped mechanisms)."""
_LEGEND_NAMES = 4  # links named in one legend entry before "and k more"

LEFT_OUT = {
    "missing": "not found beside the model",
    "outside": "outside the model's folder, not read (copy them into it)",
    "unreadable": "not readable as meshes (STL, DAE, OBJ)",
}
"""Why a visual's mesh file is not drawn, by kind, as the warning says it."""


def visual_model(view: MechanismView) -> tuple[pin.GeometryModel, str, tuple[str, ...]]:
    """The bodies to draw, what they are, and the links whose visuals are left out: the URDF's
    visuals or, without any, a stick figure.

    A visual whose mesh file is not found, lies outside the model's folder (or names a texture
    or material file outside it, :mod:`~feeder.chain.readers.model_files`) or does not load
    (garbage bytes, an empty file) is left out, with one
    :class:`~feeder.exceptions.FeederWarning` per kind naming the files: the loads need no
    meshes, so a report is still worth drawing without them, as it is for a missing mesh; and a
    file outside the folder is never opened, so no secret can reach the page."""
    model, path = view.chain.model, view.spec.model
    left_out: tuple[str, ...] = ()
    if view.spec.model_format == "urdf":
        root = parse_xml_file(path, "URDF", "robot")
        problems, left_out = _resolve_meshes(root, path)
        for kind, uris in problems.items():
            if uris:
                warnings.warn(
                    f"{path}: {len(uris)} mesh file(s) {LEFT_OUT[kind]}, their visuals not drawn "
                    f"(the loads need no meshes): {', '.join(uris)}",
                    FeederWarning,
                    stacklevel=2,
                )
        xml = etree.tostring(root, encoding="unicode")
        visuals = pin.buildGeomFromUrdfString(model, xml, pin.GeometryType.VISUAL)
        if visuals.ngeoms:
            return visuals, "visuals", left_out
    return _stick_figure(view), "stick figure", left_out


def _resolve_meshes(
    root: etree._Element, urdf: Path
) -> tuple[dict[str, list[str]], tuple[str, ...]]:
    """Point every ``<mesh>`` of a ``<visual>`` or ``<collision>`` of the URDF ``root`` at its
    file's absolute path and remove the element if its mesh is not drawn (:data:`LEFT_OUT`; a
    collision's mesh, which is never read, only if it is not found or lies outside the folder);
    return the URIs of the visuals left out by kind and the links they belong to, each once, in
    the file's order."""
    problems: dict[str, dict[str, None]] = {kind: {} for kind in LEFT_OUT}
    links: dict[str, None] = {}
    for mesh in list(root.iter("mesh")):
        owner = next(mesh.iterancestors("visual", "collision"), None)
        if owner is None:  # not a body's shape: Pinocchio reads no other mesh
            continue
        uri = mesh.get("filename")
        path, problem = _mesh_file(uri, urdf, read=owner.tag == "visual")
        if problem is None:
            mesh.set("filename", str(path))
            continue
        link = owner.getparent()
        link.remove(owner)
        if owner.tag == "visual":
            problems[problem][uri] = None
            links[link.get("name")] = None
    return {kind: list(uris) for kind, uris in problems.items()}, tuple(links)


def _mesh_file(uri: str, urdf: Path, read: bool) -> tuple[Path | None, str | None]:
    """The mesh file ``uri`` of the URDF ``urdf`` names, or why it is not drawn (a key of
    :data:`LEFT_OUT`); if ``read``, the files it names must lie inside the model's folder too,
    and it must load (with Pinocchio's mesh loader, coal's assimp)."""
    import coal

    try:
        path = mesh_path(uri, urdf)
        if read:
            for reference in mesh_references(path):
                inside_folder(reference, urdf.parent, f"file {reference.name!r} of mesh {uri!r}")
    except ModelFolderError:
        return None, "outside"
    except UrdfError:
        return None, "missing"
    except OSError:
        return None, "unreadable"
    if read:  # loaded twice (Pinocchio's cached loader is not shared): ~10 ms per CAD mesh
        try:
            coal.MeshLoader().load(str(path))
        except ValueError:  # assimp cannot read it: "File is empty", "Failed to determine …"
            return None, "unreadable"
    return path, None


def _stick_figure(view: MechanismView) -> pin.GeometryModel:
    """A ball at every joint and a rod from each joint to its children's joints and to the
    closure frames on its body (at the assembled pose, in the joint's frame)."""
    import coal

    model = view.chain.model
    data = model.createData()
    pin.forwardKinematics(model, data, view.q[0])
    pin.updateFramePlacements(model, data)
    origins = np.array([data.oMi[j].translation for j in range(model.njoints)])
    extent = float(np.ptp(origins, axis=0).max()) if model.njoints > 1 else 1.0
    radius = _STICK_SHARE * (extent or 1.0)
    geometry = pin.GeometryModel()

    def add(name: str, joint: int, placement: pin.SE3, shape) -> None:
        item = pin.GeometryObject(name, joint, placement, shape)
        item.meshColor = np.array(_STICK_COLOR)
        item.overrideMaterial = True
        geometry.addGeometryObject(item)

    def rod(name: str, joint: int, end: np.ndarray) -> None:
        """A rod in joint ``joint``'s frame from its origin to ``end`` (3,) [m], local."""
        length = float(np.linalg.norm(end))
        if length < radius:
            return
        z = end / length  # coal's cylinders lie along z
        helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        x = np.cross(helper, z)
        x /= np.linalg.norm(x)
        rotation = np.column_stack([x, np.cross(z, x), z])
        add(name, joint, pin.SE3(rotation, end / 2.0), coal.Cylinder(radius * 0.6, length))

    for j in range(1, model.njoints):
        add(f"joint_{model.names[j]}", j, pin.SE3.Identity(), coal.Sphere(radius * 1.4))
        parent = model.parents[j]
        rod(f"rod_{model.names[j]}", parent, data.oMi[parent].actInv(origins[j]))
    for closure in view.chain.closures:
        for name in (closure.frame_a, closure.frame_b):
            frame = model.frames[model.getFrameId(name)]
            rod(f"rod_{name}", frame.parentJoint, frame.placement.translation)
    return geometry


def _body_legend(
    model: pin.Model, visuals: pin.GeometryModel, kind: str, left_out: Sequence[str] = ()
) -> list[LegendEntry]:
    """One entry per colour drawn, naming the links of that colour, and a note naming the links
    ``left_out`` (their mesh files not found or not usable, :data:`LEFT_OUT`)."""
    if kind == "stick figure":
        why = (
            "their mesh files are missing or unusable" if left_out else "the model has no visuals"
        )
        return [
            LegendEntry(
                material_css(_STICK_COLOR),
                "body",
                f"bodies as a stick figure ({why}): a ball at each joint",
            )
        ]
    links: dict[str, list[str]] = {}
    for item in visuals.geometryObjects:
        own = item.meshPath.lower().endswith(".dae") and not item.overrideMaterial
        color = "own" if own else material_css(item.meshColor)
        name = model.frames[item.parentFrame].name
        if name not in links.setdefault(color, []):
            links[color].append(name)
    entries = []
    for color, names in links.items():
        shown = _names(names)
        if color == "own":
            entries.append(LegendEntry("#ffffff", "body", f"{shown} (the mesh's own colours)"))
        else:
            entries.append(LegendEntry(color, "body", shown))
    if left_out:
        entries.append(
            LegendEntry(
                "", "note", f"not drawn (mesh files missing or unusable): {_names(left_out)}"
            )
        )
    return entries


def _names(names: Sequence[str]) -> str:
    """The first :data:`_LEGEND_NAMES` of ``names`` and how many more."""
    shown = ", ".join(names[:_LEGEND_NAMES])
    if len(names) > _LEGEND_NAMES:
        shown += f" and {len(names) - _LEGEND_NAMES} more"
    return shown


def reaction_peaks(view: MechanismView) -> dict[str, float]:
    """Peak reaction force [N] of every joint with a reaction in the view's table."""
    model = view.chain.model
    peaks = {}
    for name in list(model.names)[1:]:
        keys = [f"{column_stem(name)}_force_{axis}" for axis in "xyz"]
        if all(key in view.columns for key in keys):
            force = np.column_stack([view.columns[key] for key in keys])
            peaks[name] = float(np.linalg.norm(force, axis=1).max())
    return peaks


def pick_reactions(view: MechanismView, reactions: Sequence[str] | None) -> list[str]:
    """The joints whose reaction force is drawn: ``reactions`` as given (checked), or the
    :data:`DEFAULT_REACTIONS` of largest peak force.

    Raises:
        InputError: A name that is not a joint with a reaction in the table.
    """
    peaks = reaction_peaks(view)
    if reactions is None:
        ranked = sorted(peaks, key=peaks.get, reverse=True)
        return [name for name in ranked[:DEFAULT_REACTIONS] if peaks[name] > 0.0]
    unknown = [name for name in reactions if name not in peaks]
    if unknown:
        raise InputError(
            f"no reaction of joint(s) {unknown} to draw; joints: {sorted(peaks) or 'none'}"
        )
    return list(dict.fromkeys(reactions))


def _arrows(
    view: MechanismView, joints: np.ndarray, peaks: dict[str, float], reactions: list[str]
) -> tuple[Arrows, list[str]]:
    """The drive loads, the picked reactions and the mount's force (if the table has it) as
    arrow series (module docstring), model axes, from the joints' placements (N, njoints, 4, 4)
    and the reactions' peaks [N]; and the actuated joints whose drive load is zero (round-off:
    not drawn)."""
    model, columns = view.chain.model, view.columns
    origins, rotations = joints[:, :, :3, 3], joints[:, :, :3, :3]
    axes = joint_axes(model)
    forces: dict[str, ForceSeries] = {}
    moments: dict[str, ForceSeries] = {}
    force_scale = max(peaks.values(), default=0.0)
    lever = float(np.ptp(origins.reshape(-1, 3), axis=0).max())
    zero = []
    for name in list(model.names)[1:]:
        tau = columns.get(f"tau_{column_stem(name)}")
        if tau is None:
            continue
        j = model.getJointId(name)
        prismatic = kind_of(model.joints[j]) == "prismatic"
        if np.abs(tau).max() <= ROUND_OFF * force_scale * (1.0 if prismatic else lever):
            zero.append(name)
            continue
        vector = tau[:, None] * (rotations[:, j] @ axes[j][0])
        if prismatic:
            forces[f"drive force of {name} [N]"] = (vector, origins[:, j])
        else:
            moments[f"drive moment of {name} [N·m]"] = (vector, origins[:, j])
    for name in reactions:
        j = model.getJointId(name)
        force = np.column_stack([columns[f"{column_stem(name)}_force_{axis}"] for axis in "xyz"])
        forces[f"reaction force in {name} [N]"] = (force, origins[:, j])
    mount = [f"mount_force_vehicle_{axis}" for axis in "xyz"]
    if all(key in columns for key in mount):
        force = np.column_stack([columns[key] for key in mount])
        forces[MOUNT_FORCE] = (force, np.zeros_like(force))
    return Arrows(forces, moments), zero


def _cut_tracks(vis, view: MechanismView, joints: np.ndarray, radius: float) -> dict:
    """Draw a ball at each closure's first frame; return their placements (N, 4, 4), from the
    joints' placements (N, njoints, 4, 4)."""
    model = view.chain.model
    tracks = {}
    material = mg.MeshBasicMaterial(color=_CUT_COLOR, depthTest=False)
    for closure in view.chain.closures:
        node = f"{_CUTS}/{closure.label}"
        vis[node].set_object(mg.Sphere(radius), material)
        vis[node].set_property("renderOrder", ON_TOP)
        frame = model.frames[model.getFrameId(closure.frame_a)]
        tracks[node] = attached(joints, frame.parentJoint, frame.placement)
    return tracks


def draw_mechanism(
    viz: MeshcatVisualizer,
    view: MechanismView,
    kind: str,
    reactions: list[str],
    left_out: Sequence[str] = (),
) -> DrawnScene:
    """Draw and animate the mechanism's view in ``viz`` (its visual model loaded from
    :func:`visual_model`, of ``kind``, the visuals of the links ``left_out`` not drawn) with the
    reactions of ``reactions`` (picked by :func:`pick_reactions`); return the scales and the
    legend."""
    vis = viz.viewer
    viz.loadViewerModel(rootNodeName=BODIES)
    model = view.chain.model
    geometries = viz.visual_model.geometryObjects
    nodes = [viz.getViewerNodeName(g, pin.GeometryType.VISUAL) for g in geometries]
    joints = joint_placements(model, view.q)
    placements = geometry_placements(joints, viz.visual_model)
    centres, radii = zip(*(geometry_sphere(g) for g in geometries), strict=True)
    points, reach = sphere_centres(placements, np.array(centres)), np.array(radii)
    tracks = {node: placements[:, k] for k, node in enumerate(nodes)}
    tracks |= _cut_tracks(vis, view, joints, _CUT_SHARE * extent_of(points, reach))
    arrows, zero = _arrows(view, joints, reaction_peaks(view), reactions)
    up = up_of(model.gravity.linear)
    parts = draw_scene(
        vis, view.t, tracks, points, reach, arrows, up, base=base_placements(view.base)
    )
    triad = "axes" if view.base is None else "level axes (the base at rest)"
    legend = [*_body_legend(model, viz.visual_model, kind, left_out)]
    if view.chain.closures:
        cuts = ", ".join(closure.label for closure in view.chain.closures)
        legend.append(LegendEntry(css(_CUT_COLOR), "body", f"closure cuts: {cuts}"))
    legend += parts.legend
    if zero:
        legend.append(LegendEntry("", "note", f"zero drive load (round-off): {', '.join(zero)}"))
    return DrawnScene(
        newtons_per_metre=parts.newtons_per_metre,
        moment_scale=parts.moment_scale,
        arrow_length=parts.arrow_length,
        legend=tuple(legend),
        boundaries=(float(view.t[0]), float(view.t[-1])),
        stages=(),
        slow_motion=parts.slow_motion,
        axes=f"{triad} at the model's origin: x red, y green, z blue; {view.note}",
    )
