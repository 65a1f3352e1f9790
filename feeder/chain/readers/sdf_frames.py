"""SDF's pose frame semantics: every link's and joint's frame, and every joint's axis, in the
model frame of an SDF model at q = 0.

Units m and rad; rotations as roll-pitch-yaw about fixed x, y, z, as in URDF. A link's ``<pose>``
is its frame in the model frame, a joint's ``<pose>`` is the joint frame in its *child* link's
frame, an ``<inertial>``'s ``<pose>`` is the centre-of-mass frame in the link's frame (the
inertia tensor [kg·m²] is in that frame's axes); SDF 1.7's ``relative_to`` names another frame (a
link, a joint, a ``<frame>`` or ``__model__``). A joint's axis is in the joint frame, except in
SDF 1.4 and with ``<use_parent_model_frame>true`` (1.5, 1.6), where it is in the model frame, and
in SDF 1.7 with ``<xyz expressed_in="...">``. SDF poses are the assembled configuration with
every joint at zero, so the built model's q = 0 is the SDF's pose and closes every loop.

Refused with a :class:`~feeder.exceptions.UrdfError` naming the file and the element: a
``<pose frame="...">`` naming a frame (SDF 1.5/1.6 left its meaning undefined), ``relative_to``
before SDF 1.7, an unknown or ambiguous frame name, poses that refer to each other in a cycle, an
axis that is not a direction.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
from lxml import etree

from ...exceptions import UrdfError
from .sdf_model import MODEL_FRAME, SdfModel, read_flag, read_numbers
from .urdf import AXIS_MIN_NORM


def pose_value(pose: etree._Element | None, where: str, version: str) -> tuple[pin.SE3, str]:
    """A ``<pose>``'s transform and the frame it is relative to ("" for the default)."""
    if pose is None:
        return pin.SE3.Identity(), ""
    if (pose.get("frame") or "").strip():
        raise UrdfError(
            f"{where}: <pose frame={pose.get('frame')!r}> is not supported (SDF 1.5/1.6 left "
            "its meaning undefined); use SDF 1.7's relative_to"
        )
    relative_to = (pose.get("relative_to") or "").strip()
    if relative_to and version != "1.7":
        raise UrdfError(
            f"{where}: <pose relative_to={relative_to!r}> needs SDF 1.7, the file is {version}"
        )
    v = read_numbers(pose, 6, f"{where} pose", default=[0.0] * 6)
    return pin.SE3(pin.rpy.rpyToMatrix(*v[3:]), v[:3]), relative_to


def place(model: SdfModel) -> None:
    """Every link's frame and every joint's frame (and axis) in the model frame at q = 0."""
    # Each pose and the frame it is relative to: a name from the file, or the default's key
    # (a joint may share its child link's name before SDF 1.7).
    raw: dict[tuple[str, str], tuple[pin.SE3, str | tuple[str, str]]] = {}
    for link in model.links.values():
        pose, relative_to = pose_value(
            link.pose, f"{model.source}: link {link.name!r}", model.version
        )
        raw[("link", link.name)] = (pose, relative_to or ("model", ""))
    for joint in model.joints:
        pose, relative_to = pose_value(
            joint.element.find("pose"), f"{model.source}: joint {joint.name!r}", model.version
        )
        raw[("joint", joint.name)] = (pose, relative_to or ("link", joint.child))
    for name, frame in model.frames.items():
        pose, relative_to = pose_value(
            frame.find("pose"), f"{model.source}: frame {name!r}", model.version
        )
        attached = (frame.get("attached_to") or "").strip()
        raw[("frame", name)] = (pose, relative_to or attached or ("model", ""))
    placed: dict[tuple[str, str], pin.SE3] = {}

    def key_of(name: str, where: str) -> tuple[str, str]:
        if name == MODEL_FRAME:
            return ("model", "")
        keys = [key for key in (("link", name), ("joint", name), ("frame", name)) if key in raw]
        if len(keys) != 1:
            problem = "is ambiguous (several elements share it)" if keys else "is not a frame"
            raise UrdfError(f"{model.source}: {where}: frame name {name!r} {problem}")
        return keys[0]

    def resolve(key: tuple[str, str], path: tuple[tuple[str, str], ...]) -> pin.SE3:
        if key == ("model", ""):
            return pin.SE3.Identity()
        if key in placed:
            return placed[key]
        if key in path:
            cycle = " → ".join(f"{kind} {name!r}" for kind, name in (*path, key))
            raise UrdfError(f"{model.source}: the poses refer to each other in a cycle: {cycle}")
        pose, relative_to = raw[key]
        if isinstance(relative_to, str):
            relative_to = key_of(relative_to, f"{key[0]} {key[1]!r}")
        base = resolve(relative_to, (*path, key))
        placed[key] = base * pose
        return placed[key]

    for key in raw:
        resolve(key, ())
    model.placements = {name: placed[("link", name)] for name in model.links}
    for joint in model.joints:
        joint.placement = placed[("joint", joint.name)]
        axis = joint.element.find("axis")
        if joint.type in ("fixed", "ball"):
            continue
        where = f"{model.source}: joint {joint.name!r}, axis"
        xyz = None if axis is None else axis.find("xyz")
        vector = read_numbers(xyz, 3, where, default=[0.0, 0.0, 1.0])
        norm = float(np.linalg.norm(vector))
        if not norm >= AXIS_MIN_NORM:
            raise UrdfError(f"{where}: {vector.tolist()} is not a direction")
        expressed_in = ""
        if model.version == "1.4":
            expressed_in = MODEL_FRAME
        elif model.version in ("1.5", "1.6"):
            if axis is not None and read_flag(axis.find("use_parent_model_frame"), where):
                expressed_in = MODEL_FRAME
        else:
            if axis is not None and axis.find("use_parent_model_frame") is not None:
                raise UrdfError(
                    f"{where}: <use_parent_model_frame> was removed in SDF 1.7; use "
                    '<xyz expressed_in="__model__">'
                )
            if xyz is not None:
                expressed_in = (xyz.get("expressed_in") or "").strip()
        if expressed_in:
            frame = resolve(key_of(expressed_in, f"joint {joint.name!r} axis"), ())
            vector = joint.placement.rotation.T @ frame.rotation @ vector
        joint.axis = vector / norm
