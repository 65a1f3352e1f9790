"""Reaction wrenches in every joint of the feeder, and the grip on the payload.

With the pin force λ of :func:`feeder.dynamics.inverse.actuator_loads` applied at the cut (λ on
the piston at ``piston_pin``, −λ on the arm at ``arm_pin``), the generic closed-chain reactions
(:func:`feeder.chain.dynamics.reactions.joint_reactions`, Newton–Euler over all samples, equal to
Pinocchio's RNEA with the pin force as external forces) give the wrench that the parent body
exerts on the child through each joint, world axes, moment about the joint's origin. Its
component along the joint's axis is the joint's generalized force: the actuator load for
``piston_joint`` and ``forearm_joint``, zero for the passive pivots. The rest is the constraint
wrench that the bearing or guide carries:

==================  ================  =====================================================
joint               child             reaction
==================  ================  =====================================================
``cylinder_joint``  cylinder          cylinder–frame trunnion (Fig. 12)
``piston_joint``    piston            piston–cylinder guides: side force and moment about S
``arm_joint``       arm               arm–frame pivot
``forearm_joint``   forearm           forearm–arm hinge (Fig. 11)
==================  ================  =====================================================

The grip is the wrench the forearm exerts on the payload (rigidly held): its force is
m (a_G − g), its moment about the payload's centre of gravity I_G ω̇ + ω × I_G ω, with the
forearm's angular velocity ω and acceleration ω̇ and the centre of gravity's acceleration a_G.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..chain.dynamics.reactions import JointWrench, MountWrench, closure_wrenches
from ..chain.dynamics.reactions import joint_reactions as chain_reactions
from ..chain.kinematics.tree import cross
from ..device.feeder import PAPER_JOINTS
from ..exceptions import InputError
from .inverse import ActuatorLoads
from .models import FeederDynamics

JOINT_NAMES = ("cylinder_frame", "piston_cylinder", "arm_frame", "forearm_arm")
"""Names of the four joint reactions, in the order of the paper's joints (φ1, r2, φ3, φ4)."""


@dataclass(frozen=True)
class JointReactions:
    """Reaction wrenches of every joint along a cycle.

    Attributes:
        joints: :data:`JOINT_NAMES` → :class:`JointWrench`.
        closure_force: Force [N] the piston exerts on the arm at the pin, world, shape (N, 3)
            (= −λ of :class:`~feeder.dynamics.inverse.ActuatorLoads`).
        grip_force: Force [N] the forearm exerts on the payload, world, shape (N, 3); zero
            before the grip.
        grip_moment: Its moment [N·m] about the payload's centre of gravity, world, (N, 3).
        mount: The wrench the vehicle exerts on the device through its frame, about the world
            origin B (:class:`~feeder.chain.dynamics.reactions.MountWrench`: in the level world
            axes and in the device's axes moving with the hull).
    """

    joints: dict[str, JointWrench]
    closure_force: np.ndarray
    grip_force: np.ndarray
    grip_moment: np.ndarray
    mount: MountWrench


def joint_reactions(dyn: FeederDynamics, loads: ActuatorLoads) -> JointReactions:
    """Reaction wrenches of every joint and the grip, with the pin force applied at the cut.

    The generic closed-chain reactions
    (:func:`feeder.chain.dynamics.reactions.joint_reactions`) of the device's model (with or
    without the payload, by the grip flag), all samples of a run at once; the grip from the
    forearm's motion (module docstring).

    Args:
        dyn: The device's dynamics models.
        loads: The inverse dynamics (:func:`~feeder.dynamics.inverse.actuator_loads`) of a motion;
            its checked motion ``loads.motion`` is the one used here.
    """
    n = loads.motion.q.shape[0]
    if sum(run.stop - run.start for run, *_ in loads.runs) != n:
        raise InputError("these loads lack their kinematics: compute them with actuator_loads")
    fields = ("force", "moment", "drive", "constraint_force", "constraint_moment")
    wrenches = {
        name: {f: np.empty((n,) if f == "drive" else (n, 3)) for f in fields}
        for name in JOINT_NAMES
    }
    grip_force, grip_moment = np.zeros((n, 3)), np.zeros((n, 3))
    mount_fields = [f.name for f in dataclasses.fields(MountWrench)]
    mounts = {f: np.empty((n, 3)) for f in mount_fields}
    forearm = dyn.joint_ids[3]
    for run, flag, kinematics, rows in loads.runs:
        chain = dyn.cases[flag].dynamics
        _, terms = closure_wrenches(chain.chain, rows, loads.closure_force[run])
        rotation = None if loads.base is None else loads.base.rotation[run]
        joints, mount = chain_reactions(chain.chain, kinematics, terms, rotation)
        for f in mount_fields:
            mounts[f][run] = getattr(mount, f)
        for name, joint in zip(JOINT_NAMES, PAPER_JOINTS, strict=True):
            for f in fields:
                wrenches[name][f][run] = getattr(joints[joint], f)
        if flag:
            grip_force[run], grip_moment[run] = _grip(dyn, kinematics, forearm)
    return JointReactions(
        joints={name: JointWrench(**values) for name, values in wrenches.items()},
        closure_force=-loads.closure_force,
        grip_force=grip_force,
        grip_moment=grip_moment,
        mount=MountWrench(**mounts),
    )


def _grip(dyn: FeederDynamics, kinematics, forearm: int) -> tuple[np.ndarray, np.ndarray]:
    """Force m (a_G − g) [N] and moment I_G α + ω × I_G ω [N·m] about the payload's centre of
    gravity, world axes, (N, 3) each, from the forearm's batched motion."""
    payload = dyn.payload_inertia
    gravity = (
        dyn.cases[1].model.gravity.linear if kinematics.gravity is None else kinematics.gravity
    )
    rotation = kinematics.rotation[forearm]
    lever = np.einsum("nij,j->ni", rotation, payload.lever)
    w, dw = kinematics.omega[forearm], kinematics.alpha[forearm]
    a_g = kinematics.acceleration[forearm] + cross(dw, lever) + cross(w, cross(w, lever))
    inertia = rotation @ payload.inertia @ np.swapaxes(rotation, 1, 2)
    spin = np.einsum("nij,nj->ni", inertia, w)
    moment = np.einsum("nij,nj->ni", inertia, dw) + cross(w, spin)
    return payload.mass * (a_g - gravity), moment
