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

from ..kinematics.layout import RowSum, tree_layout
from ..kinematics.tree import TreeMotion, apply_each, cross


def joint_wrenches(
    model: pin.Model,
    motion: TreeMotion,
    external: list[tuple[int, np.ndarray]] = (),
    inertia: bool = True,
) -> tuple[np.ndarray, np.ndarray]:
    """Backward Newton–Euler pass (module docstring): the wrench each joint transmits, parent on
    child, world axes about the joint's origin — force [N] and moment [N·m], (njoints, N, 3)
    each, indexed by joint id — with the motion's gravity (the model's by default). Entry 0 is
    the mount's: the wrench on the base link from what holds it, about the model's origin. Every
    body's term is computed at once, and the sums run one depth of the tree at a time, deepest
    first (:attr:`~feeder.chain.kinematics.layout.TreeLayout.backward`).

    Args:
        external: (frame id, world wrench (N, 6) [force, moment about the frame's origin])
            applied to the frame's body.
        inertia: False: the bodies' rates of momentum and weights left out (a statics pass:
            what the external wrenches alone make the joints transmit).
    """
    n = motion.origin.shape[1]
    if inertia:  # every body, the base link's (joint 0, moving with the base) included
        force, moment = _body_terms(model, motion)
    else:
        force, moment = np.zeros((2, model.njoints, n, 3))
    if external:
        _apply_external(model, motion, external, force, moment)
    for children, parents in tree_layout(model).backward:
        arm = motion.origin[children] - motion.origin[parents.index]
        parents.add(moment, moment[children] + cross(arm, force[children]))
        parents.add(force, force[children])
    return force, moment


def _apply_external(
    model: pin.Model,
    motion: TreeMotion,
    external: list[tuple[int, np.ndarray]],
    force: np.ndarray,
    moment: np.ndarray,
) -> None:
    """Subtract the external wrenches from their bodies' terms (force, moment: (njoints, N, 3),
    about the joints' origins), each moved to its joint's origin (one product per term) and
    summed per joint."""
    frames = [frame for frame, _ in external]
    joints = np.array([model.frames[frame].parentJoint for frame in frames])
    shifts = np.array([model.frames[frame].placement.translation for frame in frames])
    wrench = np.stack([w for _, w in external])  # (terms, N, 6)
    lever = apply_each(motion.rotation[joints], shifts)  # joint → frame, world (terms, N, 3)
    turning = wrench[..., 3:] + cross(lever, wrench[..., :3])  # about the joint's origin
    into = RowSum.of(joints)
    into.add(force, -wrench[..., :3])
    into.add(moment, -turning)


def _body_terms(model: pin.Model, motion: TreeMotion) -> tuple[np.ndarray, np.ndarray]:
    """Every body's f = m (a_G − g) and n = I ω̇ + ω × I ω + c × f about its joint's origin
    (module docstring), world axes, (njoints, N, 3) each."""
    gravity = model.gravity.linear if motion.gravity is None else motion.gravity
    bodies = model.inertias
    mass = np.array([body.mass for body in bodies])[:, None, None]
    local = np.array([body.lever for body in bodies])  # origin → CG, joint axes (njoints, 3)
    rotational = np.array([body.inertia for body in bodies])  # about the CG (njoints, 3, 3)
    rot = motion.rotation
    lever = apply_each(rot, local)  # origin → CG, world
    w, dw = motion.omega, motion.alpha
    a_g = motion.acceleration + cross(dw, lever) + cross(w, cross(w, lever))
    force = mass * (a_g - gravity)
    # I ω̇ + ω × I ω with I = R I_local Rᵀ, evaluated in the body's axes
    w_local = np.einsum("knji,knj->kni", rot, w)
    dw_local = np.einsum("knji,knj->kni", rot, dw)
    spin = w_local @ rotational  # rotational inertia symmetric: (I ω)ᵀ = ωᵀ I
    n_local = dw_local @ rotational + cross(w_local, spin)
    return force, np.einsum("knij,knj->kni", rot, n_local) + cross(lever, force)


def generalized_forces(
    model: pin.Model, motion: TreeMotion, force: np.ndarray, moment: np.ndarray
) -> np.ndarray:
    """Each joint's generalized forces (N, nv): its columns' components of the wrench it
    transmits, Lᵀ force + Wᵀ moment (e · moment for a revolute joint, e · force for a prismatic
    one), every column at once (``force``, ``moment``: :func:`joint_wrenches`'s)."""
    owner = tree_layout(model).column_joint
    return np.einsum("nik,kni->nk", motion.linear_columns, force[owner]) + np.einsum(
        "nik,kni->nk", motion.angular_columns, moment[owner]
    )


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
