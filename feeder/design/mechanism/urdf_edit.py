"""The URDF of a mechanism with its design variables set: a joint's origin (x, y, z [m], roll,
pitch, yaw [rad] of ``<origin xyz rpy>``), a body's mass [kg] (its inertia tensor scaled with
it) or a body's length scale [-] (its centre of mass and the origins of the joints it carries
scaled by s, its inertia tensor by s², its mass kept), edited in memory with ElementTree.

A frame (a link fixed to its parent, as the frames a closure or a force element names) is moved
through the origin of the joint that carries it: ``body_pin.x`` is the x of the origin of the
joint whose child is the link ``body_pin``. Every value is the model's own number before the
edit: a mass of 3000 kg set to 2500 kg, an origin's x set to 1.4 m. The edits apply in the
design file's order: a link's scale multiplies the origins of the joints it carries as they
are then (after an origin variable listed before it, before one listed after).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass

from ...exceptions import InputError

COMPONENTS = {"x": 0, "y": 1, "z": 2, "roll": 3, "pitch": 4, "yaw": 5}
"""An origin's components: x, y, z of ``xyz`` [m], roll, pitch, yaw of ``rpy`` [rad]."""

INERTIA = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")


@dataclass(frozen=True)
class Target:
    """What one design variable changes in the URDF.

    Attributes:
        kind: ``origin`` (a joint's origin component), ``mass`` or ``scale`` (a link's).
        name: The joint's name (``origin``) or the link's.
        component: The origin's component (:data:`COMPONENTS`); "" for a mass or scale.
    """

    kind: str
    name: str
    component: str = ""

    @property
    def unit(self) -> str:
        """``m``, ``rad``, ``kg`` or ``-`` (a scale)."""
        if self.kind == "mass":
            return "kg"
        if self.kind == "scale":
            return "-"
        return "m" if COMPONENTS[self.component] < 3 else "rad"


def parse(text: str, where: str) -> ET.Element:
    """The URDF's root element.

    Raises:
        InputError: Not XML (``where`` names the file).
    """
    try:
        return ET.fromstring(text)
    except ET.ParseError as exc:
        raise InputError(f"{where}: not a readable URDF: {exc}") from exc


def _joints(root: ET.Element) -> dict[str, ET.Element]:
    return {j.get("name", ""): j for j in root.findall("joint")}


def _links(root: ET.Element) -> dict[str, ET.Element]:
    return {link.get("name", ""): link for link in root.findall("link")}


def carrier(root: ET.Element, link: str) -> str | None:
    """The joint whose child is ``link``, or None (the root link)."""
    for name, joint in _joints(root).items():
        child = joint.find("child")
        if child is not None and child.get("link") == link:
            return name
    return None


def names(root: ET.Element) -> tuple[list[str], list[str]]:
    """The joints' and links' names, in the file's order."""
    return list(_joints(root)), list(_links(root))


def _numbers(element: ET.Element | None, key: str, count: int) -> list[float]:
    if element is None or element.get(key) is None:
        return [0.0] * count
    return [float(v) for v in element.get(key, "").split()]


def _origin(joint: ET.Element) -> ET.Element:
    origin = joint.find("origin")
    if origin is None:
        origin = ET.SubElement(joint, "origin", {"xyz": "0 0 0", "rpy": "0 0 0"})
    return origin


def _text(values: list[float]) -> str:
    return " ".join(repr(float(v)) for v in values)


def value(root: ET.Element, target: Target) -> float:
    """The model's value of ``target`` [its unit] (a scale is 1)."""
    if target.kind == "scale":
        return 1.0
    if target.kind == "mass":
        inertial = _links(root)[target.name].find("inertial")
        mass = None if inertial is None else inertial.find("mass")
        return 0.0 if mass is None else float(mass.get("value", "0"))
    k = COMPONENTS[target.component]
    origin = _joints(root)[target.name].find("origin")
    return _numbers(origin, "xyz" if k < 3 else "rpy", 3)[k % 3]


def _set(root: ET.Element, target: Target, number: float) -> None:
    if target.kind == "origin":
        origin = _origin(_joints(root)[target.name])
        k = COMPONENTS[target.component]
        key = "xyz" if k < 3 else "rpy"
        values = _numbers(origin, key, 3)
        values[k % 3] = number
        origin.set(key, _text(values))
        return
    link = _links(root)[target.name]
    inertial = link.find("inertial")
    if target.kind == "mass":
        mass = inertial.find("mass")
        _scale_inertia(inertial, number / float(mass.get("value")))
        mass.set("value", repr(float(number)))
        return
    if inertial is not None:
        origin = inertial.find("origin")
        if origin is not None:
            origin.set("xyz", _text([number * v for v in _numbers(origin, "xyz", 3)]))
        _scale_inertia(inertial, number**2)
    for joint in _joints(root).values():
        parent = joint.find("parent")
        if parent is not None and parent.get("link") == target.name:
            origin = _origin(joint)
            origin.set("xyz", _text([number * v for v in _numbers(origin, "xyz", 3)]))


def _scale_inertia(inertial: ET.Element, factor: float) -> None:
    tensor = inertial.find("inertia")
    if tensor is not None:
        for key in INERTIA:
            tensor.set(key, repr(float(tensor.get(key, "0")) * factor))


def edited(text: str, targets: list[Target] | tuple[Target, ...], values) -> str:
    """The URDF ``text`` with each target set to its value [its unit] (module docstring), as
    text. The model's numbers are read once: two targets on one origin each set their own
    component."""
    root = ET.fromstring(text)
    for target, number in zip(targets, values, strict=True):
        _set(root, target, float(number))
    return ET.tostring(root, encoding="unicode", xml_declaration=True)
