"""The URDF of an SDF model's spanning tree, and the cut links and closures of its loops.

**Joints in the URDF.** revolute and prismatic keep their position limits, which must contain
the SDF's pose (0): limits that exclude it belong to another zero than the file's, and are
refused unless the caller drops every position limit (``limits=False``). A continuous joint, a
joint without limits (SDF's default ±1e16 counts as none: :data:`NO_LIMIT`) or one read with
``limits=False`` becomes a revolute (not Pinocchio's two-coordinate continuous joint) or
prismatic joint with lower = upper = 0, which :mod:`feeder.chain.assembly` reads as "no limit".
Effort and velocity limits that the SDF leaves unset (its default −1) become :data:`UNLIMITED`;
damping and friction are kept; springs (``spring_stiffness``) have no URDF form and are dropped,
so a spring joint is a free joint here (Cassie's shin and heel springs). Each URDF link frame is
the SDF frame of the joint that reaches it (its SDF link frame when the joint has no pose, as in
Cassie), the root's is its SDF link frame.

**Loops.** Every joint left out of the tree (:mod:`feeder.chain.readers.sdf_tree`) closes a loop
and is cut: two massless links, ``<joint>_cut_a`` fixed to the joint's parent link and
``<joint>_cut_b`` fixed to its child link, both at the joint frame (they coincide at q = 0), and
a closure between them: ``revolute`` (about the joint's axis, in both frames' axes) for a
revolute or continuous joint, ``point`` for a ball joint, ``weld`` for a fixed joint
(:data:`~feeder.chain.readers.sdf_tree.CUT_KINDS`).

**Inertials.** SDF's defaults apply: a link without ``<inertial>`` has a mass of 1 kg and an
inertia of 1 kg·m² about each axis (as in Gazebo), a missing ``<mass>`` is 1 kg, a missing
``<ixx>``, ``<iyy>``, ``<izz>`` is 1 kg·m² and a missing product of inertia 0.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
from lxml import etree

from ...exceptions import UrdfError
from ..model.closure import Closure
from .sdf_frames import pose_value
from .sdf_model import SdfJoint, SdfLink, SdfModel, read_numbers
from .sdf_tree import CUT_KINDS, Edge

NO_LIMIT = 1e16
"""Joint position limit [rad or m] at or beyond which an SDF bound means "none": SDF's own
default for ``<lower>``/``<upper>`` is ∓1e16."""

UNLIMITED = float(np.finfo(float).max)
"""Effort [N·m or N] and velocity [rad/s or m/s] limit written for an SDF joint that sets none
(SDF's −1): the largest double, Pinocchio's own default for "no limit" (URDF needs a number)."""


def _text(values) -> str:
    return " ".join(repr(float(x)) for x in np.ravel(values))


def _origin(parent: etree._Element, placement: pin.SE3) -> None:
    etree.SubElement(
        parent,
        "origin",
        xyz=_text(placement.translation),
        rpy=_text(pin.rpy.matrixToRpy(placement.rotation)),
    )


def _child_number(element: etree._Element | None, tag: str, default: float, where: str) -> float:
    found = None if element is None else element.find(tag)
    if found is None:
        return default
    return float(read_numbers(found, 1, where)[0])


def _urdf_inertial(urdf_link: etree._Element, link: SdfLink, model: SdfModel, frame: pin.SE3):
    """The link's inertial in its URDF frame ``frame`` (placement in the model frame)."""
    where = f"{model.source}: link {link.name!r}, inertial"
    inertial = link.inertial
    pose = pin.SE3.Identity()
    if inertial is not None:
        pose_element = inertial.find("pose")
        if pose_element is not None and (pose_element.get("relative_to") or "").strip():
            raise UrdfError(f"{where}: relative_to on an inertial pose is not supported")
        pose, _ = pose_value(pose_element, where, model.version)
    mass = _child_number(inertial, "mass", 1.0, where)
    tensor = None if inertial is None else inertial.find("inertia")
    moments = {
        k: _child_number(tensor, k, 1.0 if k in ("ixx", "iyy", "izz") else 0.0, where)
        for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
    }
    element = etree.SubElement(urdf_link, "inertial")
    _origin(element, frame.inverse() * model.placements[link.name] * pose)
    etree.SubElement(element, "mass", value=repr(mass))
    etree.SubElement(element, "inertia", {k: repr(v) for k, v in moments.items()})


def _urdf_joint(
    robot: etree._Element, edge: Edge, model: SdfModel, origin: pin.SE3, limits: bool
) -> None:
    joint = edge.joint
    where = f"{model.source}: joint {joint.name!r}"
    axis_element = joint.element.find("axis")
    limit = None if axis_element is None else axis_element.find("limit")
    lower = _child_number(limit, "lower", -NO_LIMIT, f"{where}, limit")
    upper = _child_number(limit, "upper", NO_LIMIT, f"{where}, limit")
    limited = (
        limits
        and joint.type in ("revolute", "prismatic")
        and (lower > -NO_LIMIT or upper < NO_LIMIT)
    )
    if limited and not (lower > -NO_LIMIT and upper < NO_LIMIT):
        raise UrdfError(f"{where}: a one-sided limit [{lower:g}, {upper:g}] is not supported")
    if limited and not lower <= 0.0 <= upper:
        raise UrdfError(
            f"{where}: the SDF's pose (joint at 0) is outside the joint's limits "
            f"[{lower:g}, {upper:g}]: the limits do not belong to the pose the file draws, which "
            "is the only one known to close the loops; read with limits=False to drop the "
            "position limits"
        )
    kind = "revolute" if joint.type == "continuous" else joint.type
    element = etree.SubElement(robot, "joint", name=joint.name, type=kind)
    etree.SubElement(element, "parent", link=edge.urdf_parent)
    etree.SubElement(element, "child", link=edge.urdf_child)
    _origin(element, origin)
    if kind == "fixed":
        return
    etree.SubElement(element, "axis", xyz=_text(-joint.axis if edge.reversed else joint.axis))
    rates = {}
    for tag in ("effort", "velocity"):
        value = _child_number(limit, tag, -1.0, f"{where}, limit")
        rates[tag] = repr(value) if value >= 0.0 else repr(UNLIMITED)
    bounds = {"lower": repr(lower), "upper": repr(upper)} if limited else {}
    etree.SubElement(element, "limit", {**bounds, **rates})
    dynamics = None if axis_element is None else axis_element.find("dynamics")
    values = {}
    for tag in ("damping", "friction"):
        value = _child_number(dynamics, tag, 0.0, f"{where}, dynamics")
        if value < 0.0:
            raise UrdfError(f"{where}: <{tag}> {value:g} is negative")
        values[tag] = repr(value)
    etree.SubElement(element, "dynamics", values)


def write_tree(
    model: SdfModel, root: str, edges: list[Edge], limits: bool
) -> tuple[etree._Element, dict[str, pin.SE3]]:
    """The URDF ``<robot>`` of the spanning tree ``edges`` grown from ``root`` (every link with
    its inertial, every tree joint, in the order taken), and each link's URDF frame in the model
    frame (module docstring); ``limits``: keep the joints' position limits."""
    frame = {root: model.placements[root]}
    robot = etree.Element("robot", name=model.name)
    urdf_links = {root: etree.SubElement(robot, "link", name=root)}
    _urdf_inertial(urdf_links[root], model.links[root], model, frame[root])
    for edge in edges:
        child = edge.urdf_child
        frame[child] = edge.joint.placement
        urdf_links[child] = etree.SubElement(robot, "link", name=child)
        _urdf_inertial(urdf_links[child], model.links[child], model, frame[child])
        origin = frame[edge.urdf_parent].inverse() * frame[child]
        _urdf_joint(robot, edge, model, origin, limits)
    return robot, frame


def write_cut(
    robot: etree._Element,
    joint: SdfJoint,
    frame: dict[str, pin.SE3],
    names: set[str],
    model: SdfModel,
) -> Closure:
    """Cut the loop joint ``joint``: add its two cut links, fixed to its links, to ``robot``
    (``frame``: the URDF link frames of :func:`write_tree`) and return the closure between them
    (module docstring). ``names``: the link and joint names already used, updated with the new
    ones.

    Raises:
        UrdfError: A name the cut needs is already used.
    """
    ends = {}
    for side, link in (("a", joint.parent), ("b", joint.child)):
        name = f"{joint.name}_cut_{side}"
        for generated in (name, f"{name}_fixed"):
            if generated in names:
                raise UrdfError(
                    f"{model.source}: cutting joint {joint.name!r} needs the name "
                    f"{generated!r}, which the model already uses"
                )
        names.update((name, f"{name}_fixed"))
        etree.SubElement(robot, "link", name=name)
        element = etree.SubElement(robot, "joint", name=f"{name}_fixed", type="fixed")
        etree.SubElement(element, "parent", link=link)
        etree.SubElement(element, "child", link=name)
        _origin(element, frame[link].inverse() * joint.placement)
        ends[side] = name
    axis = tuple(float(x) for x in joint.axis)
    return Closure(
        ends["a"], ends["b"], CUT_KINDS[joint.type], axis=axis, axis_b=axis, name=joint.name
    )
