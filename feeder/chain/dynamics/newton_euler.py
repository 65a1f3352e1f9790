"""The Newton–Euler backward pass over a tree at every sample at once (numpy, world axes).

From the tree's motion (:func:`~feeder.chain.kinematics.tree.tree_motion`, on a moving base
:func:`~feeder.chain.kinematics.tree.on_base`) the pass gives the wrench each joint transmits,
parent on child, about its origin: the rate of momentum of its subtree less gravity and the
external wrenches applied to it. For a body of mass m, centre of gravity c (from the joint's
origin), inertia I about c, angular velocity ω and acceleration ω̇, and origin acceleration a:

    f = m (a + ω̇ × c + ω × (ω × c) − g),     n = I ω̇ + ω × I ω + c × f   (about the origin),

summed from the leaves to the root, each child's wrench moved to its parent's origin. The
wrench's components along the joint's columns are its generalized forces — M q̈ + b − Σ J_eᵀ w_e,
Pinocchio's RNEA to round-off (tests/chain/kinematics/test_tree.py checks it) — and the rest is
what the joint's bearing carries. The pass ends at the base (joint 0): the wrench the mount exerts
on the whole mechanism, its base link included.

:func:`held_wrench` is the same body term for a part of a body (a gripper's payload, a tool)
whose inertia the model has merged into the body that holds it: the wrench that holds it.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..kinematics.tree import TreeMotion, cross, frame_placements


def joint_wrenches(
    model: pin.Model,
    motion: TreeMotion,
    external: list[tuple[int, np.ndarray]] = (),
    inertia: bool = True,
) -> tuple[np.ndarray, np.ndarray]:
    """Backward Newton–Euler pass (module docstring): the wrench each joint transmits, parent on
    child, world axes about the joint's origin — lists by joint id of force (N, 3) [N] and
    moment (N, 3) [N·m] — with the motion's gravity (the model's by default). Entry 0 is the
    mount's: the wrench on the base link from what holds it, about the model's origin.

    Args:
        external: (frame id, world wrench (N, 6) [force, moment about the frame's origin])
            applied to the frame's body.
        inertia: False: the bodies' rates of momentum and weights left out (a statics pass:
            what the external wrenches alone make the joints transmit).
    """
    n, count = motion.origin[0].shape[0], model.njoints
    gravity = model.gravity.linear if motion.gravity is None else motion.gravity
    force = [np.zeros((n, 3)) for _ in range(count)]
    moment = [np.zeros((n, 3)) for _ in range(count)]
    for j in range(count if inertia else 0):  # 0: the base link, moving with the base
        body = model.inertias[j]
        rot = motion.rotation[j]
        lever = (rot.reshape(-1, 3) @ body.lever).reshape(-1, 3)  # origin → CG, world
        w, dw = motion.omega[j], motion.alpha[j]
        a_g = motion.acceleration[j] + cross(dw, lever) + cross(w, cross(w, lever))
        f = body.mass * (a_g - gravity)
        # I ω̇ + ω × I ω with I = R I_local Rᵀ, evaluated in the body's axes.
        to_body = np.swapaxes(rot, 1, 2)
        w_local = np.einsum("nij,nj->ni", to_body, w)
        dw_local = np.einsum("nij,nj->ni", to_body, dw)
        spin = w_local @ body.inertia
        n_local = dw_local @ body.inertia + cross(w_local, spin)
        force[j] = f
        moment[j] = np.einsum("nij,nj->ni", rot, n_local) + cross(lever, f)
    for frame, wrench in external:
        j = model.frames[frame].parentJoint
        _, point = frame_placements(model, motion, frame)
        force[j] = force[j] - wrench[:, :3]
        moment[j] = moment[j] - wrench[:, 3:] - cross(point - motion.origin[j], wrench[:, :3])
    for j in range(count - 1, 0, -1):  # children have larger ids than their parents
        p = model.parents[j]
        force[p] = force[p] + force[j]
        moment[p] = moment[p] + moment[j] + cross(motion.origin[j] - motion.origin[p], force[j])
    return force, moment


def generalized_forces(
    model: pin.Model, motion: TreeMotion, force: list[np.ndarray], moment: list[np.ndarray]
) -> np.ndarray:
    """Each joint's generalized forces (N, nv): its columns' components of the wrench it
    transmits, Lᵀ force + Wᵀ moment (e · moment for a revolute joint, e · force for a prismatic
    one)."""
    tau = np.zeros((force[0].shape[0], model.nv))
    for j in range(1, model.njoints):
        k = model.joints[j].idx_v
        tau[:, k : k + model.joints[j].nv] = np.einsum(
            "nik,ni->nk", motion.linear[j], force[j]
        ) + np.einsum("nik,ni->nk", motion.angular[j], moment[j])
    return tau


def held_wrench(
    motion: TreeMotion, gravity: np.ndarray, joint: int, inertia: pin.Inertia
) -> tuple[np.ndarray, np.ndarray]:
    """The wrench that joint ``joint``'s body exerts on a part of itself that it holds rigidly:
    force m (a_G − g) [N] and moment I_G ω̇ + ω × I_G ω [N·m] about the part's centre of gravity
    G, world axes, (N, 3) each.

    Args:
        motion: The tree's motion (absolute, as the backward pass takes it).
        gravity: Gravity [m/s²] in the motion's axes, (3,) or (N, 3).
        joint: The holding body's joint id.
        inertia: The part's spatial inertia in the joint's frame (mass [kg], centre of gravity
            [m], rotational inertia about it [kg·m²]).
    """
    rotation = motion.rotation[joint]
    lever = np.einsum("nij,j->ni", rotation, inertia.lever)
    w, dw = motion.omega[joint], motion.alpha[joint]
    a_g = motion.acceleration[joint] + cross(dw, lever) + cross(w, cross(w, lever))
    world = rotation @ inertia.inertia @ np.swapaxes(rotation, 1, 2)
    spin = np.einsum("nij,nj->ni", world, w)
    moment = np.einsum("nij,nj->ni", world, dw) + cross(w, spin)
    return inertia.mass * (a_g - gravity), moment
