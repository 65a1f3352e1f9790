"""Joint-type overrides: a URDF joint replaced by a joint URDF cannot write (a ball, a universal
joint), at the same place, between the same bodies — as the Extended-URDF side-file's
``joint_name`` / ``joint_type`` ask.

=====================  ======================================================================
type                   the joint that replaces the URDF's (in the joint's own axes)
=====================  ======================================================================
``SPHERICAL``          ball joint, unit quaternion (Pinocchio ``JointModelSpherical``)
``SPHERICAL_ZYX``      ball joint, three angles about z, y, x (``JointModelSphericalZYX``)
``UJOINT_ab``          universal joint: about axis a, then about the turned axis b
                       (a ≠ b in X, Y, Z; ``UJOINT_ZY``: z then y; ``JointModelUniversal``)
``FREEFLYER``          free six-degree-of-freedom joint (``JointModelFreeFlyer``)
``PLANAR``             motion in the joint's x–y plane (``JointModelPlanar``)
``FIXED``              the joint locked at 0: its child becomes part of its parent's body
=====================  ======================================================================

The bodies' inertias, the joints' placements and the frames are kept; the replaced joint's limits
are those of its new type (none, or a unit quaternion).
"""

from __future__ import annotations

import difflib
from collections.abc import Mapping

import numpy as np
import pinocchio as pin

from ...exceptions import InputError

_AXES = dict(zip("XYZ", np.eye(3), strict=True))

_FIXED_TYPES = {
    "SPHERICAL": pin.JointModelSpherical,
    "SPHERICAL_ZYX": pin.JointModelSphericalZYX,
    "FREEFLYER": pin.JointModelFreeFlyer,
    "PLANAR": pin.JointModelPlanar,
}

JOINT_TYPES = (*_FIXED_TYPES, "UJOINT_ab", "FIXED")
"""The accepted override types (``UJOINT_ab`` for any pair a ≠ b of X, Y, Z)."""


def joint_model(kind: str) -> pin.JointModel | None:
    """The Pinocchio joint for an override type (None for ``FIXED``).

    Raises:
        InputError: An unknown type (the message lists the accepted ones).
    """
    if kind in _FIXED_TYPES:
        return _FIXED_TYPES[kind]()
    if kind == "FIXED":
        return None
    if (
        kind.startswith("UJOINT_")
        and len(kind) == 9
        and kind[7] in _AXES
        and kind[8] in _AXES
        and kind[7] != kind[8]
    ):
        return pin.JointModelUniversal(_AXES[kind[7]], _AXES[kind[8]])
    raise InputError(f"unknown joint type {kind!r}; accepted: {', '.join(JOINT_TYPES)}")


def replace_joints(model: pin.Model, types: Mapping[str, str], source: str) -> pin.Model:
    """``model`` with the named joints replaced (module docstring).

    Raises:
        InputError: A joint that is not in the model, or an unknown type.
    """
    if not types:
        return model
    for name, kind in types.items():
        if not model.existJointName(name):
            names = list(model.names)[1:]
            near = difflib.get_close_matches(name, names, n=1)
            hint = f"did you mean {near[0]!r}?" if near else f"joints: {names}"
            raise InputError(f"{source}: joint_name {name!r} is not a joint of the model; {hint}")
        joint_model(kind)
    new = pin.Model()
    new.name, new.gravity = model.name, model.gravity
    locked = []
    for j in range(1, model.njoints):
        old, name = model.joints[j], model.names[j]
        replacement = joint_model(types[name]) if name in types else old
        if replacement is None:
            replacement = old
            locked.append(j)
        if replacement is old:
            q, v = slice(old.idx_q, old.idx_q + old.nq), slice(old.idx_v, old.idx_v + old.nv)
            new.addJoint(
                model.parents[j],
                old,
                model.jointPlacements[j],
                name,
                model.effortLimit[v],
                model.velocityLimit[v],
                model.lowerPositionLimit[q],
                model.upperPositionLimit[q],
            )
        else:
            new.addJoint(model.parents[j], replacement, model.jointPlacements[j], name)
        new.appendBodyToJoint(j, model.inertias[j], pin.SE3.Identity())
    for frame in list(model.frames)[1:]:
        new.addFrame(pin.Frame(frame), False)
    if locked:
        new = pin.buildReducedModel(new, locked, pin.neutral(new))
    return new
