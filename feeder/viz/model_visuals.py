"""The bodies of a user's model (``feeder view MODEL``, ``report.html``) as the scene draws them
(:class:`~feeder.viz.scene.MechanismScene` ``visuals`` and ``body_legend``), with their legend.

Bodies: the URDF's visuals — meshes (STL, DAE, OBJ; ``package://``, ``file://`` and relative
paths resolved inside the model's folder, :func:`~feeder.chain.readers.urdf.mesh_path`) or
primitives — with their materials' colours. A visual whose mesh file is not found, lies outside
the model's folder or does not load is left out, with one warning per kind naming the files
(:func:`model_bodies`; the legend names the bodies left out). A model without visuals (an MJCF or
SDF file, a URDF whose links have none, or none of whose mesh files are usable) is drawn as a
stick figure: a ball at every joint and a rod from each joint to its children's joints and to
the closure frames on its body.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pinocchio as pin
from lxml import etree

from ..chain.readers.model_files import inside_folder, mesh_references
from ..chain.readers.urdf import mesh_path, parse_xml_file
from ..exceptions import FeederWarning, ModelFolderError, UrdfError
from ..study.view import MechanismView
from .legend import LegendEntry, material_css, note

_STICK_COLOR = (0.55, 0.60, 0.68, 1.0)  # RGBA of a stick figure's balls and rods
_STICK_SHARE = 0.015  # a stick figure's rod radius per metre of the mechanism's extent
_LEGEND_NAMES = 4  # links named in one legend entry before "and k more"

LEFT_OUT = {
    "missing": "not found beside the model",
    "outside": "outside the model's folder, not read (copy them into it)",
    "unreadable": "not readable as meshes (STL, DAE, OBJ)",
}
"""Why a visual's mesh file is not drawn, by kind, as the warning says it."""


def model_bodies(view: MechanismView) -> tuple[pin.GeometryModel, tuple[LegendEntry, ...]]:
    """The bodies to draw and their legend: the URDF's visuals or, without any, a stick figure
    (the legend names the links whose visuals are left out).

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
            return visuals, _visuals_legend(model, visuals, left_out)
    return _stick_figure(view), _stick_legend(left_out)


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


def _stick_legend(left_out: Sequence[str]) -> tuple[LegendEntry, ...]:
    """The stick figure's entry, saying why the model is drawn so."""
    why = "their mesh files are missing or unusable" if left_out else "the model has no visuals"
    label = f"bodies as a stick figure ({why}): a ball at each joint"
    return (LegendEntry(material_css(_STICK_COLOR), "body", label),)


def _visuals_legend(
    model: pin.Model, visuals: pin.GeometryModel, left_out: Sequence[str]
) -> tuple[LegendEntry, ...]:
    """One entry per colour drawn, naming the links of that colour, and a note naming the links
    ``left_out`` (their mesh files not found or not usable, :data:`LEFT_OUT`)."""
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
        entries.append(note(f"not drawn (mesh files missing or unusable): {_names(left_out)}"))
    return tuple(entries)


def _names(names: Sequence[str]) -> str:
    """The first :data:`_LEGEND_NAMES` of ``names`` and how many more."""
    shown = ", ".join(names[:_LEGEND_NAMES])
    if len(names) > _LEGEND_NAMES:
        shown += f" and {len(names) - _LEGEND_NAMES} more"
    return shown
