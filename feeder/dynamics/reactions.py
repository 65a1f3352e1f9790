"""Reaction wrenches in every joint of the feeder, and the grip on the payload: the paper's names
over the reactions of the chain's inverse dynamics.

With the pin force λ of :func:`feeder.dynamics.inverse.actuator_loads` applied at the cut (λ on
the piston at ``piston_pin``, −λ on the arm at ``arm_pin``), the closed chain's inverse dynamics
(:func:`feeder.chain.inverse_dynamics`: Newton–Euler over all samples,
:mod:`feeder.chain.dynamics.newton_euler`, equal to Pinocchio's RNEA with the pin force as
external forces) gives the wrench that the parent body exerts on the child through each joint,
world axes, moment about the joint's origin (:class:`~feeder.chain.results.JointWrench`). Its
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

The grip is the wrench the forearm exerts on the payload (rigidly held,
:meth:`~feeder.chain.results.ChainLoads.held_wrench`): its force is m (a_G − g), its moment
about the payload's centre of gravity I_G ω̇ + ω × I_G ω, with the forearm's angular velocity ω and
acceleration ω̇ and the centre of gravity's acceleration a_G.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..chain.results import JointWrench, MountWrench
from ..device.feeder import PAPER_JOINTS
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
            origin B (:class:`~feeder.chain.results.MountWrench`: in the level world axes and in
            the device's axes moving with the hull).
    """

    joints: dict[str, JointWrench]
    closure_force: np.ndarray
    grip_force: np.ndarray
    grip_moment: np.ndarray
    mount: MountWrench


def pin_reactions(dyn: FeederDynamics, loads: ActuatorLoads) -> JointReactions:
    """Reaction wrenches of every joint and the grip, with the pin force applied at the cut.

    The joints' and the mount's wrenches of the chain's inverse dynamics
    (:attr:`ActuatorLoads.runs`) under the paper's names, and the grip from the forearm's motion
    there (module docstring).

    Args:
        dyn: The device's dynamics models.
        loads: The inverse dynamics (:func:`~feeder.dynamics.inverse.actuator_loads`) of a motion.
    """
    n = loads.motion.q.shape[0]
    grip_force, grip_moment = np.zeros((n, 3)), np.zeros((n, 3))
    for run in loads.runs:
        if run.gripped:
            wrench = run.loads.held_wrench(dyn.joint_ids[3], dyn.payload_inertia)
            grip_force[run.samples], grip_moment[run.samples] = wrench
    joints = {
        name: JointWrench(
            *(
                loads.joined(lambda chain, j=joint, f=f.name: getattr(chain.joints[j], f))
                for f in dataclasses.fields(JointWrench)
            )
        )
        for name, joint in zip(JOINT_NAMES, PAPER_JOINTS, strict=True)
    }
    mount = MountWrench(
        *(
            loads.joined(lambda chain, f=f.name: getattr(chain.mount, f))
            for f in dataclasses.fields(MountWrench)
        )
    )
    return JointReactions(
        joints=joints,
        closure_force=-loads.closure_force,
        grip_force=grip_force,
        grip_moment=grip_moment,
        mount=mount,
    )
