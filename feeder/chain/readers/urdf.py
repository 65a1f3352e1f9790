"""Strict URDF reading: parse, check the tree and every inertia, then build the Pinocchio model.

Pinocchio and yourdfpy are lenient (yourdfpy silently recovers broken XML; Pinocchio accepts a
negative mass or a non-physical inertia, zeroes a mass it cannot parse, and turns a zero joint axis
into a motion that is not a rotation), so every URDF is checked here first and refused with a
:class:`~feeder.exceptions.UrdfError` or :class:`~feeder.exceptions.InertiaError` that names the
file and the element.

A document type declaration is refused outright: lxml would expand an internal entity
(``<mass value="&m;"/>``) for the checks while Pinocchio's parser does not, and drops the body's
inertia instead, so the checked model and the built one would differ. URDF needs no DTD.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pinocchio as pin
from lxml import etree

from ...exceptions import InertiaError, InputError, ModelFolderError, UrdfError
from ...inertia import check_inertia
from ...validation import check_file, check_path
from ..model.closure import ClosedChain, Closure
from .bodies import check_bodies
from .model_files import inside_folder

_JOINT_TYPES = {"revolute", "continuous", "prismatic", "fixed", "floating", "planar"}
_AXIS_JOINT_TYPES = {"revolute", "continuous", "prismatic", "planar"}
"""Joint types whose ``<axis>`` Pinocchio uses (fixed and floating joints ignore it, and some
exporters write ``0 0 0`` there)."""
AXIS_MIN_NORM = 1e-6
"""Smallest accepted length of a joint axis [-]. Pinocchio normalises the axis; a zero axis gives
a joint "rotation" that is not a rotation (det ≠ 1) and a vector of ~1e-300 underflows to zero
inside it. An axis typed in a URDF is a direction of length ~1; one shorter than this is a zero
with round-off, not a direction."""
_PARSER = etree.XMLParser(
    recover=False, resolve_entities=False, no_network=True, load_dtd=False, remove_comments=True
)


def parse_xml(data: bytes, source: str, root_tag: str) -> etree._Element:
    """The root element of a robot description (URDF ``robot`` or SDF ``sdf``), parsed strictly.

    Raises:
        UrdfError: Malformed XML, a document type declaration (its entities would be read
            differently by Pinocchio's own parser), or another root element.
    """
    try:
        root = etree.fromstring(data, _PARSER)
    except etree.XMLSyntaxError as exc:
        raise UrdfError(f"{source}: malformed XML: {exc}") from exc
    info = root.getroottree().docinfo
    if info.doctype or info.internalDTD is not None:
        raise UrdfError(
            f"{source}: a document type declaration ({info.doctype or '<!DOCTYPE>'}) is not "
            f"allowed in a <{root_tag}> file: its entities would not be read as written"
        )
    if root.tag != root_tag:
        raise UrdfError(f"{source}: root element is <{root.tag}>, expected <{root_tag}>")
    return root


def parse_xml_file(path: Path, kind: str, root_tag: str) -> etree._Element:
    """The root element of the robot description file at ``path`` (``kind`` names the format in
    the messages), read and parsed strictly (:func:`parse_xml`).

    Raises:
        UrdfError: The file does not exist, cannot be read, or does not parse strictly.
    """
    check_file(f"{kind} file", path, UrdfError)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise UrdfError(f"cannot read {kind} file {path}: {exc}") from exc
    return parse_xml(data, str(path), root_tag)


def read_urdf(path: str | Path) -> str:
    """Return the text of the URDF file at ``path``.

    Raises:
        InputError: ``path`` is not text or a path.
        UrdfError: The file does not exist or cannot be read.
    """
    path = check_file("URDF file", path, UrdfError)
    try:
        return path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise UrdfError(f"cannot read URDF file {path}: {exc}") from exc


def _floats(element: etree._Element, attribute: str, count: int, where: str) -> np.ndarray:
    text = element.get(attribute)
    try:
        values = np.array([float(x) for x in (text or "").split()])
    except ValueError:
        values = np.array([])
    if values.size != count or not np.all(np.isfinite(values)):
        raise UrdfError(f"{where}: attribute {attribute}={text!r} is not {count} finite numbers")
    return values


def check_urdf(xml: str, source: str = "<string>") -> etree._Element:
    """Parse ``xml`` strictly and check the kinematic tree and every link's inertia.

    Args:
        xml: URDF text.
        source: File name for the messages.

    Returns:
        The parsed ``<robot>`` element.

    Raises:
        UrdfError: Malformed XML, a document type declaration, a tree that is not a tree
            (unknown links, several parents or roots, unknown joint type), a number that is not
            finite, or a moving joint's axis that is not a direction.
        InertiaError: A link whose mass or inertia no rigid body can have.
        InputError: ``xml`` is not text.
    """
    if not isinstance(xml, str):
        raise InputError(f"the URDF must be given as text (str), got {xml!r}")
    root = parse_xml(xml.encode("utf-8"), source, "robot")
    links = [link.get("name") for link in root.findall("link")]
    if not links or None in links or len(set(links)) != len(links):
        raise UrdfError(f"{source}: links must exist and have unique names, got {links}")
    parent_of: dict[str, str] = {}
    for joint in root.findall("joint"):
        name, kind = joint.get("name"), joint.get("type")
        if name is None or kind not in _JOINT_TYPES:
            raise UrdfError(f"{source}: joint {name!r} has no name or unknown type {kind!r}")
        parent, child = joint.find("parent"), joint.find("child")
        if parent is None or child is None:
            raise UrdfError(f"{source}: joint {name!r} lacks <parent> or <child>")
        for end in (parent.get("link"), child.get("link")):
            if end not in links:
                raise UrdfError(f"{source}: joint {name!r} refers to unknown link {end!r}")
        if child.get("link") in parent_of:
            raise UrdfError(f"{source}: link {child.get('link')!r} has two parent joints")
        parent_of[child.get("link")] = parent.get("link")
    roots = [link for link in links if link not in parent_of]
    if len(roots) != 1:
        raise UrdfError(f"{source}: the links must form one tree, found roots {roots}")
    _check_numbers(root, source)
    for link in root.findall("link"):
        _check_inertial(link, source)
    return root


def _check_numbers(root: etree._Element, source: str) -> None:
    """Every origin, axis and joint limit must be finite numbers, a joint's lower limit not above
    its upper, and the axis of a moving joint a direction: Pinocchio would otherwise drop the
    element, zero a mass or build a non-rotation silently."""
    for owner in (*root.findall("link"), *root.findall("joint")):
        where = f"{source}: {owner.tag} {owner.get('name')!r}"
        for origin in owner.iter("origin"):
            for attribute in ("xyz", "rpy"):
                if origin.get(attribute) is not None:
                    _floats(origin, attribute, 3, f"{where}, <{origin.getparent().tag}> origin")
        for axis in owner.findall("axis"):
            xyz = _floats(axis, "xyz", 3, f"{where}, axis")
            if owner.get("type") in _AXIS_JOINT_TYPES and not np.linalg.norm(xyz) >= AXIS_MIN_NORM:
                raise UrdfError(
                    f"{where}: axis xyz={axis.get('xyz')!r} is not a direction (length below "
                    f"{AXIS_MIN_NORM:g})"
                )
        for limit in owner.findall("limit"):
            for attribute in ("lower", "upper", "effort", "velocity"):
                if limit.get(attribute) is not None:
                    _floats(limit, attribute, 1, f"{where}, limit")
            if limit.get("lower") is not None and limit.get("upper") is not None:
                lower, upper = (float(limit.get(key)) for key in ("lower", "upper"))
                if lower > upper:
                    raise UrdfError(
                        f"{where}: limit lower={lower:g} is above upper={upper:g}: swap them"
                    )


def _check_inertial(link: etree._Element, source: str) -> None:
    inertial = link.find("inertial")
    name = link.get("name")
    if inertial is None:
        return
    where = f"{source}: link {name!r}"
    mass_element, inertia_element = inertial.find("mass"), inertial.find("inertia")
    if mass_element is None or inertia_element is None:
        raise UrdfError(f"{where}: <inertial> needs <mass> and <inertia>")
    try:
        mass = float(mass_element.get("value"))
        i = {k: float(inertia_element.get(k)) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
    except (TypeError, ValueError) as exc:
        raise InertiaError(name, f"unparsable mass or inertia in {source}: {exc}") from exc
    tensor = np.array(
        [
            [i["ixx"], i["ixy"], i["ixz"]],
            [i["ixy"], i["iyy"], i["iyz"]],
            [i["ixz"], i["iyz"], i["izz"]],
        ]
    )
    check_inertia(name, mass, tensor)


def build_model(xml: str, source: str = "<string>") -> pin.Model:
    """Check ``xml`` (:func:`check_urdf`) and build its Pinocchio model (fixed base).

    Raises:
        UrdfError, InertiaError: See :func:`check_urdf`; also Pinocchio's own refusals.
    """
    check_urdf(xml, source)
    try:
        model = pin.buildModelFromXML(xml)
    except (ValueError, RuntimeError) as exc:
        raise UrdfError(f"{source}: Pinocchio cannot build the model: {exc}") from exc
    check_bodies(model, source)
    return model


def load_closed_chain(
    urdf: str | Path, closures: Sequence[Closure | Sequence[str]]
) -> ClosedChain:
    """Load a URDF file strictly and close its loops.

    Args:
        urdf: Path of the URDF file (fixed base; meshes are not needed).
        closures: :class:`Closure` s, or pairs of frame names (point closures).

    Raises:
        UrdfError: Missing or malformed file.
        InertiaError: A non-physical link inertia.
        ClosureFrameError: A closure frame that is not in the model.
        InputError: ``urdf`` not text or a path, ``closures`` not closures or name pairs, a
            pair of frames on the same body, or the same pair twice (in either order).
    """
    xml = read_urdf(urdf)
    return ClosedChain(build_model(xml, str(urdf)), closures)


def mesh_path(uri: str, urdf: str | Path) -> Path:
    """The file a URDF mesh ``filename`` names, resolved inside the URDF's folder
    (:mod:`~feeder.chain.readers.model_files`): ``package:///NAME`` (Onshape exports),
    ``package://PKG/NAME`` (looked up beside the URDF as ``NAME``, then as ``PKG/NAME``),
    ``file:///abs/path``, or a path relative to the URDF's folder.

    Raises:
        InputError: ``uri`` not text, ``urdf`` not text or a path.
        ModelFolderError: No candidate is a file inside the folder, and one lies outside it (it
            is not read, nor even looked for).
        UrdfError: The file does not exist (the message names the URI and where it looked).
    """
    if not isinstance(uri, str):
        raise InputError(f"the mesh URI must be text, got {uri!r}")
    folder = check_path("the URDF file", urdf).parent
    if uri.startswith("package://"):
        rest = uri[len("package://") :].lstrip("/")
        names = [rest]
        if "/" in rest:
            names.insert(0, rest.split("/", 1)[1])
    elif uri.startswith("file://"):
        names = [uri[len("file://") :]]
    else:
        names = [uri]
    candidates, outside = [], None
    for name in names:
        try:
            candidates.append(inside_folder(Path(name), folder, f"mesh {uri!r} of {urdf}"))
        except ModelFolderError as exc:
            outside = exc
    for candidate in candidates:
        if candidate.is_file():
            return candidate
    if outside is not None:
        raise outside
    raise UrdfError(
        f"mesh {uri!r} of {urdf} not found (looked for {', '.join(map(str, candidates))})"
    )
