"""Reaction wrenches in every joint of the feeder, and the grip on the payload.

With the pin force λ of :func:`feeder.dynamics.inverse.actuator_loads` applied as external forces
(λ on the piston at ``piston_pin``, −λ on the arm at ``arm_pin``), Pinocchio's recursive
Newton–Euler algorithm ``rnea(model, data, q, v, a, fext)`` returns in ``data.f[j]`` the wrench
that the parent body exerts on the child through joint j, in joint j's frame, about its origin.
Its component along the joint's motion subspace S (``S·f``) is the joint's generalized force:
the actuator load for ``piston_joint`` and ``forearm_joint``, zero for the passive pivots. The
rest is the constraint wrench that the bearing or guide carries. Everything here is turned into
world axes, moments about the joint origin:

==================  ================  =====================================================
joint               child             reaction
==================  ================  =====================================================
``cylinder_joint``  cylinder          cylinder–frame trunnion (Fig. 12)
``piston_joint``    piston            piston–cylinder guides: side force and moment about S
``arm_joint``       arm               arm–frame pivot
``forearm_joint``   forearm           forearm–arm hinge (Fig. 11)
==================  ================  =====================================================

The grip is the wrench the forearm exerts on the payload, f = Y (a − g) + v ×* Y v with the
payload's spatial inertia Y and the forearm joint's spatial velocity v and acceleration a − g
(Pinocchio's ``data.v``, ``data.a_gf``), expressed at the payload's centre of gravity: its
force is m (a_G − g), its moment I_G ω̇ + ω × I_G ω.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from .inverse import ActuatorLoads
from .models import FeederDynamics, gripped_runs

JOINT_NAMES = ("cylinder_frame", "piston_cylinder", "arm_frame", "forearm_arm")
"""Names of the four joint reactions, in the order of the paper's joints (φ1, r2, φ3, φ4)."""


@dataclass(frozen=True)
class JointWrench:
    """Wrench that a joint's parent exerts on its child, N samples, world axes.

    Attributes:
        force: Force [N], shape (N, 3).
        moment: Moment [N·m] about the joint origin, shape (N, 3).
        drive: Generalized force along the joint's axis [N or N·m], shape (N,): the actuator
            load of an actuated joint, zero for a passive one.
        constraint_force: ``force`` less its component along a prismatic joint's axis [N].
        constraint_moment: ``moment`` less its component about a revolute joint's axis [N·m].
    """

    force: np.ndarray
    moment: np.ndarray
    drive: np.ndarray
    constraint_force: np.ndarray
    constraint_moment: np.ndarray


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
    """

    joints: dict[str, JointWrench]
    closure_force: np.ndarray
    grip_force: np.ndarray
    grip_moment: np.ndarray


def _cross_dual(velocity: np.ndarray, momentum: np.ndarray) -> np.ndarray:
    """Spatial cross product v ×* h for stacked 6-vectors [linear, angular], shape (N, 6)."""
    out = np.empty_like(momentum)
    out[:, :3] = np.cross(velocity[:, 3:], momentum[:, :3])
    out[:, 3:] = np.cross(velocity[:, 3:], momentum[:, 3:]) + np.cross(
        velocity[:, :3], momentum[:, :3]
    )
    return out


def _closure_wrenches(
    dyn: FeederDynamics, rotations: np.ndarray, closure_force: np.ndarray
) -> list[tuple[int, np.ndarray]]:
    """External wrenches from λ on the piston and −λ on the arm, in their joints' frames.

    Args:
        rotations: Joint orientations (N, 4, 3, 3) (:meth:`FeederDynamics.joint_rotations`).
        closure_force: λ, world frame, (N, 3).

    Returns:
        For ``piston_pin`` then ``arm_pin``: (the frame's parent joint id, wrench (N, 6)
        [linear, angular] in that joint's frame, about its origin).
    """
    model = dyn.cases[1].model
    wrenches = []
    for frame_id, sign in zip(dyn.closure_frames, (1.0, -1.0), strict=True):
        frame = model.frames[frame_id]
        rotation = rotations[:, dyn.joint_ids.index(frame.parentJoint)]
        local = sign * (closure_force[:, None, :] @ rotation)[:, 0]
        point = frame.placement.translation
        wrenches.append((frame.parentJoint, np.hstack([local, np.cross(point, local)])))
    return wrenches


def joint_reactions(dyn: FeederDynamics, loads: ActuatorLoads) -> JointReactions:
    """Reaction wrenches of every joint from RNEA with the pin force as external forces.

    Args:
        dyn: The device's dynamics models.
        loads: The inverse dynamics (:func:`~feeder.dynamics.inverse.actuator_loads`) of a motion;
            its checked motion ``loads.motion`` is the one used here.
    """
    q, v, a, gripped = loads.motion.q, loads.motion.v, loads.motion.a, loads.motion.gripped
    n = q.shape[0]
    qp, vp, ap = dyn.to_pinocchio(q), dyn.to_pinocchio(v), dyn.to_pinocchio(a)
    rotations = dyn.joint_rotations(q)
    (piston_id, piston_ext), (arm_id, arm_ext) = _closure_wrenches(
        dyn, rotations, loads.closure_force
    )
    # Per sample: the four joint wrenches, then the forearm's velocity and acceleration − g.
    local = np.empty((n, 6, 6))
    forearm_id = dyn.joint_ids[3]
    rnea = pin.rnea
    for start, stop, flag in gripped_runs(gripped):
        case = dyn.cases[flag]
        model, data = case.model, case.data
        fext = pin.StdVec_Force()
        for _ in range(model.njoints):
            fext.append(pin.Force.Zero())
        on_piston, on_arm = fext[piston_id], fext[arm_id]
        # ``.vector`` of Pinocchio's forces and motions is a live view into ``data``: taken
        # once, it shows every later rnea's result without a per-sample Python call.
        views = tuple(data.f[j].vector for j in dyn.joint_ids) + (
            data.v[forearm_id].vector,
            data.a_gf[forearm_id].vector,
        )
        for k in range(start, stop):
            on_piston.vector = piston_ext[k]
            on_arm.vector = arm_ext[k]
            rnea(model, data, qp[k], vp[k], ap[k], fext)
            local[k] = views

    joints = {}
    for i, name in enumerate(JOINT_NAMES):
        axis = dyn.motion_subspaces[dyn.joint_ids[i]]
        drive = local[:, i] @ axis
        constraint = local[:, i] - drive[:, None] * axis
        # Columns: force, moment, constraint force, constraint moment; rotated in one product.
        stacked = np.stack(
            [local[:, i, :3], local[:, i, 3:], constraint[:, :3], constraint[:, 3:]], axis=2
        )
        world = rotations[:, i] @ stacked
        joints[name] = JointWrench(
            force=world[..., 0],
            moment=world[..., 1],
            drive=drive,
            constraint_force=world[..., 2],
            constraint_moment=world[..., 3],
        )

    inertia = dyn.payload_inertia.matrix()
    forearm_velocity = local[:, 4] * gripped[:, None]
    grip = local[:, 5] @ inertia.T * gripped[:, None] + _cross_dual(
        forearm_velocity, forearm_velocity @ inertia.T
    )
    grip_moment = grip[:, 3:] - np.cross(dyn.payload_inertia.lever, grip[:, :3])
    world = rotations[:, 3] @ np.stack([grip[:, :3], grip_moment], axis=2)
    return JointReactions(
        joints=joints,
        closure_force=-loads.closure_force,
        grip_force=world[..., 0],
        grip_moment=world[..., 1],
    )
