"""URDF of a feeding device, generated from its :class:`~.parameters.FeederParameters`.

The URDF is the device's open kinematic tree (REFERENCE.md names):

    frame ─ cylinder_joint (revolute z, φ1) ─ cylinder ─ piston_joint (prismatic x, r2) ─ piston
          │                                                                └ piston_pin (fixed)
          └ arm_joint (revolute z, φ3) ─ arm ─ forearm_joint (revolute y, φ4) ─ forearm
                                          └ arm_pin (fixed)                 └ projectile_joint
                                                                              (fixed) ─ projectile

The loop is cut at the rod-eye pin: the frames ``piston_pin`` and ``arm_pin`` coincide when the
loop is assembled; the closure itself is added in code (:mod:`feeder.chain.model.closure`). Visual
geometry is made of URDF primitives only, so the file needs no meshes.

Regenerate the shipped files with ``feeder urdf --out urdf``.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path

from ..exceptions import InputError
from ..files import write_text
from .builtin import DEVICES
from .loop import check_device
from .parameters import FeederParameters, LinkInertia

_COLORS = {
    "frame": (0.35, 0.37, 0.40, 1.0),
    "cylinder": (0.20, 0.35, 0.60, 1.0),
    "piston": (0.80, 0.80, 0.82, 1.0),
    "arm": (0.85, 0.55, 0.10, 1.0),
    "forearm": (0.30, 0.55, 0.25, 1.0),
    "projectile": (0.55, 0.50, 0.25, 1.0),
    "pin": (0.10, 0.10, 0.10, 1.0),
}
_ALONG_X = (0.0, math.pi / 2.0, 0.0)  # rpy turning a URDF cylinder's z axis onto x
_ALONG_Y = (-math.pi / 2.0, 0.0, 0.0)  # ... onto y
_EFFORT, _VELOCITY = 1.0e5, 10.0  # [N or N·m], [m/s or rad/s]: generous, not modelled


def _fmt(values: tuple[float, ...] | list[float]) -> str:
    return " ".join(repr(float(v)) for v in values)


def _origin(parent: ET.Element, xyz=(0.0, 0.0, 0.0), rpy=(0.0, 0.0, 0.0)) -> None:
    ET.SubElement(parent, "origin", xyz=_fmt(xyz), rpy=_fmt(rpy))


def _visual(
    link: ET.Element, shape: str, size: dict[str, str], xyz, rpy=(0.0, 0.0, 0.0), color: str = ""
) -> None:
    visual = ET.SubElement(link, "visual")
    _origin(visual, xyz, rpy)
    ET.SubElement(ET.SubElement(visual, "geometry"), shape, size)
    name = color or link.get("name")
    material = ET.SubElement(visual, "material", name=name)
    ET.SubElement(material, "color", rgba=_fmt(_COLORS[name]))


def _box(link, size, xyz, color=""):
    _visual(link, "box", {"size": _fmt(size)}, xyz, color=color)


def _cylinder(link, radius, length, xyz, rpy, color=""):
    _visual(
        link,
        "cylinder",
        {"radius": repr(float(radius)), "length": repr(float(length))},
        xyz,
        rpy,
        color,
    )


def _inertial(link: ET.Element, inertia: LinkInertia, com: tuple[float, float, float]) -> None:
    inertial = ET.SubElement(link, "inertial")
    _origin(inertial, com)
    ET.SubElement(inertial, "mass", value=repr(float(inertia.mass)))
    ixx, iyy, izz = inertia.moments
    ET.SubElement(
        inertial,
        "inertia",
        ixx=repr(float(ixx)),
        ixy="0.0",
        ixz="0.0",
        iyy=repr(float(iyy)),
        iyz="0.0",
        izz=repr(float(izz)),
    )


def _joint(robot, name, kind, parent, child, xyz, axis=None, limits=None) -> None:
    joint = ET.SubElement(robot, "joint", name=name, type=kind)
    _origin(joint, xyz)
    ET.SubElement(joint, "parent", link=parent)
    ET.SubElement(joint, "child", link=child)
    if axis is not None:
        ET.SubElement(joint, "axis", xyz=_fmt(axis))
    if limits is not None:
        ET.SubElement(
            joint,
            "limit",
            lower=repr(float(limits[0])),
            upper=repr(float(limits[1])),
            effort=repr(_EFFORT),
            velocity=repr(_VELOCITY),
        )


def _payload_visuals(link: ET.Element, p: FeederParameters) -> None:
    """Projectile: body and a stepped ogive; charge: a case with its rim. Axis = link y."""
    length, radius = p.payload_length, p.payload_diameter / 2.0
    base = -0.4 * length  # the centre of gravity sits 40 % of the length above the base
    if p.payload_name == "projectile":
        body = 0.6 * length
        _cylinder(link, radius, body, (0.0, base + body / 2.0, 0.0), _ALONG_Y)
        step = (length - body) / 3.0
        for i, scale in enumerate((0.85, 0.6, 0.3)):
            y = base + body + (i + 0.5) * step
            _cylinder(link, scale * radius, step, (0.0, y, 0.0), _ALONG_Y)
    else:
        _cylinder(link, radius, length, (0.0, base + length / 2.0, 0.0), _ALONG_Y)
        _cylinder(link, 1.08 * radius, 0.02, (0.0, base + 0.01, 0.0), _ALONG_Y, "pin")


def barrel_length(p: FeederParameters) -> float:
    """Visual length [m] of the cylinder barrel from B: it ends 40 mm short of the rod-eye pin
    at the retracted end stop."""
    return p.r2_min + p.d2 - 0.04


def piston_head_offset(p: FeederParameters) -> float:
    """Distance [m] from the piston frame (S) back to the piston head, chosen so that the head
    stays 15 mm inside the barrel at the extended end stop."""
    return p.r2_max - barrel_length(p) + 0.015


def urdf_string(p: FeederParameters) -> str:
    """The URDF of the device described by ``p``, as XML text (deterministic).

    Raises:
        InputError, InertiaError, UnreachablePoseError: ``p`` fails
            :func:`~feeder.device.loop.check_device`.
    """
    check_device(p)
    robot = ET.Element("robot", name=f"{p.name}_feeder")

    frame = ET.SubElement(robot, "link", name="frame")
    _box(frame, (0.10, 0.06, 0.12), (0.0, -0.03, 0.0))
    _box(frame, (0.10, 0.06, 0.12), (p.L1, p.L2 - 0.03, 0.0))
    _cylinder(frame, 0.012, 0.14, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), "pin")
    _cylinder(frame, 0.015, 0.14, (p.L1, p.L2, 0.0), (0.0, 0.0, 0.0), "pin")

    cylinder = ET.SubElement(robot, "link", name="cylinder")
    _inertial(cylinder, p.cylinder, (p.l1, 0.0, 0.0))
    barrel = barrel_length(p)
    _cylinder(cylinder, p.bore_diameter / 2.0 + 0.008, barrel, (barrel / 2.0, 0.0, 0.0), _ALONG_X)
    _cylinder(cylinder, 0.022, 0.05, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    _joint(
        robot,
        "cylinder_joint",
        "revolute",
        "frame",
        "cylinder",
        (0.0, 0.0, 0.0),
        (0, 0, 1),
        (p.phi1_min, p.phi1_max),
    )

    piston = ET.SubElement(robot, "link", name="piston")
    _inertial(piston, p.piston, (0.0, 0.0, 0.0))
    head = piston_head_offset(p)
    rod = p.d2 + head
    _cylinder(piston, p.rod_diameter / 2.0, rod, (p.d2 - rod / 2.0, 0.0, 0.0), _ALONG_X)
    _cylinder(piston, p.bore_diameter / 2.0, 0.03, (-head, 0.0, 0.0), _ALONG_X)
    _cylinder(piston, 0.02, 0.04, (p.d2, 0.0, 0.0), (0.0, 0.0, 0.0))
    _joint(
        robot,
        "piston_joint",
        "prismatic",
        "cylinder",
        "piston",
        (0.0, 0.0, 0.0),
        (1, 0, 0),
        (p.r2_min, p.r2_max),
    )
    ET.SubElement(robot, "link", name="piston_pin")
    _joint(robot, "piston_pin_joint", "fixed", "piston", "piston_pin", (p.d2, 0.0, 0.0))

    arm = ET.SubElement(robot, "link", name="arm")
    _inertial(arm, p.arm, (p.l3, 0.0, 0.0))
    _box(arm, (p.a1 + 0.06, 0.06, 0.04), (p.a1 / 2.0, 0.0, 0.0))
    _cylinder(arm, 0.035, 0.06, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
    _joint(
        robot,
        "arm_joint",
        "revolute",
        "frame",
        "arm",
        (p.L1, p.L2, 0.0),
        (0, 0, 1),
        (p.phi3_min, p.phi3_max),
    )
    arm_pin = ET.SubElement(robot, "link", name="arm_pin")
    _cylinder(arm_pin, 0.012, 0.08, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), "pin")
    _joint(robot, "arm_pin_joint", "fixed", "arm", "arm_pin", (p.d3, 0.0, 0.0))

    forearm = ET.SubElement(robot, "link", name="forearm")
    _inertial(forearm, p.forearm, (p.e, -p.d, 0.0))
    _cylinder(forearm, 0.03, 0.08, (0.0, 0.0, 0.0), _ALONG_Y)
    _box(forearm, (p.e5, 0.04, 0.03), (p.e5 / 2.0, -p.d, p.z5 / 2.0))
    tray_z = p.z5 - math.copysign(p.payload_diameter / 2.0 + 0.01, p.z5)
    _box(forearm, (0.12, 0.6 * p.payload_length, 0.012), (p.e5, p.h5, tray_z))
    _joint(
        robot,
        "forearm_joint",
        "revolute",
        "arm",
        "forearm",
        (p.a1, -p.f, p.c),
        (0, 1, 0),
        (-p.phi4_limit, p.phi4_limit),
    )

    payload = ET.SubElement(robot, "link", name="projectile")
    _inertial(payload, p.payload, (0.0, 0.0, 0.0))
    _payload_visuals(payload, p)
    _joint(robot, "projectile_joint", "fixed", "forearm", "projectile", (p.e5, p.h5, p.z5))

    ET.indent(robot)
    header = (
        f"<!-- Generated by feeder from FeederParameters(name={p.name!r}); do not edit: change "
        "the parameters and run: feeder urdf. SI units. -->\n"
    )
    return '<?xml version="1.0"?>\n' + header + ET.tostring(robot, encoding="unicode") + "\n"


def write_urdfs(directory: str | Path) -> list[Path]:
    """Write ``<device>_feeder.urdf`` for every built-in device into ``directory``, atomically.

    Raises:
        InputError: The folder cannot be created or written.
    """
    directory = Path(directory)
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot write the URDF files into {directory}: {exc}") from exc
    return [
        write_text(directory / f"{name}_feeder.urdf", urdf_string(params))
        for name, params in DEVICES.items()
    ]
