"""Reaction wrenches: each closure's wrench on its two bodies and every joint's reaction, from the
closure forces of :mod:`feeder.chain.dynamics.inverse` (Newton–Euler over all samples at once,
:mod:`feeder.chain.dynamics.newton_euler`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..kinematics.layout import tree_layout
from ..kinematics.rows import ClosureKinematics
from ..kinematics.tree import TreeMotion
from ..model.closure import ClosedChain
from .newton_euler import generalized_forces, joint_wrenches


@dataclass(frozen=True)
class JointWrench:
    """Wrench that a joint's parent exerts on its child, N samples, world axes.

    Attributes:
        force: Force [N], (N, 3).
        moment: Moment [N·m] about the joint's origin, (N, 3).
        drive: Its generalized forces, the components along the joint's free directions [N or
            N·m]: (N,) for a one-coordinate joint (revolute, continuous, prismatic), (N, nv_j)
            for the others in the order of their velocity (a ball joint's three moments about
            its child's axes, say); the actuator load of an actuated joint, zero for a passive
            one.
        constraint_force: ``force`` less its part along the joint's sliding directions [N]
            (prismatic, planar, translation, free-flyer).
        constraint_moment: ``moment`` less its part about the joint's turning directions [N·m]
            (revolute: its axis; universal: its two axes; ball: all of it).
    """

    force: np.ndarray
    moment: np.ndarray
    drive: np.ndarray
    constraint_force: np.ndarray
    constraint_moment: np.ndarray


@dataclass(frozen=True)
class MountWrench:
    """The wrench that the mount (the vehicle, or the ground) exerts on the mechanism through
    its base link, N samples: the rate of momentum of the whole mechanism, its base link
    included, less gravity and the external loads (closure forces and force elements between
    its own bodies cancel).

    Attributes:
        force: Force [N] in the model's axes (moving with the base), (N, 3).
        moment: Moment [N·m] about the model's origin, the same axes, (N, 3).
        level_force, level_moment: The same in the level axes
            (:mod:`~feeder.chain.model.channels`; equal to the others on a base at rest), (N, 3).
    """

    force: np.ndarray
    moment: np.ndarray
    level_force: np.ndarray
    level_moment: np.ndarray


@dataclass(frozen=True)
class ClosureWrench:
    """The force and moment of one closure on the body of its ``frame_a`` (the opposite acts on
    ``frame_b``'s), N samples.

    Attributes:
        force, moment: World axes [N], [N·m] (moment about frame a's origin), (N, 3).
    """

    force: np.ndarray
    moment: np.ndarray


def closure_wrenches(
    chain: ClosedChain, rows: ClosureKinematics, lam: np.ndarray
) -> tuple[dict[str, ClosureWrench], list[tuple[int, np.ndarray]]]:
    """Each closure's wrench on the body of frame a (world axes) from the closure forces
    λ (N, nc), and the wrenches that :func:`joint_reactions` applies: (frame id, world wrench
    [force, moment about the frame's origin] (N, 6)), on frame a and, opposite, on frame b."""
    out, terms = {}, []
    for cut, span, (a, b), frames in zip(
        chain.cuts, chain.row_slices, chain.frame_ids, rows.frames, strict=True
    ):
        force, moment = cut.wrench(frames, lam[:, span])
        out[cut.label] = ClosureWrench(force, moment)
        wrench = np.hstack([force, moment])
        terms += [(a, wrench), (b, -wrench)]
    return out, terms


def joint_reactions(
    chain: ClosedChain,
    motion: TreeMotion,
    external: list[tuple[int, np.ndarray]],
    rotation: np.ndarray | None,
    wrenches: tuple[np.ndarray, np.ndarray],
) -> tuple[dict[str, JointWrench], MountWrench]:
    """Every joint's reaction wrench (but a free-flyer's, which is zero by definition: it
    transmits no force and no moment), and the mount's, with the wrenches ``external`` ((frame
    id, world wrench (N, 6) about the frame's origin), e.g. from :func:`closure_wrenches`)
    acting on the tree; ``rotation`` (N, 3, 3): the base's axes in the level ones
    (:class:`~feeder.chain.model.base.BaseState`), None for a base at rest; ``wrenches``: the
    tree's Newton–Euler pass of the same motion with the other loads (:func:`~.newton_euler.
    joint_wrenches`, the inverse dynamics' own): the reactions are those plus what
    ``external`` alone makes the joints transmit (a statics pass: the pass is linear in the
    loads)."""
    model = chain.model
    force, moment = joint_wrenches(model, motion, external, inertia=False)
    force, moment = force + wrenches[0], moment + wrenches[1]
    if rotation is None:
        mount = MountWrench(force[0], moment[0], force[0], moment[0])
    else:
        mount = MountWrench(
            force[0],
            moment[0],
            np.einsum("nij,nj->ni", rotation, force[0]),
            np.einsum("nij,nj->ni", rotation, moment[0]),
        )
    layout = tree_layout(model)
    drive = generalized_forces(model, motion, force, moment)
    constraint_force = force - _along_every(motion.linear_columns, force, layout.column_joint)
    constraint_moment = moment - _along_every(motion.angular_columns, moment, layout.column_joint)
    joints = {}
    for j in range(1, model.njoints):
        if model.joints[j].nv == 6:
            continue  # free in every direction (a free-flyer): it transmits no wrench
        own = drive[:, layout.slices[j]]
        joints[model.names[j]] = JointWrench(
            force=force[j],
            moment=moment[j],
            drive=own[:, 0] if own.shape[1] == 1 else own,
            constraint_force=constraint_force[j],
            constraint_moment=constraint_moment[j],
        )
    return joints, mount


def _along_every(columns: np.ndarray, vectors: np.ndarray, owner: np.ndarray) -> np.ndarray:
    """:func:`_along` for every joint at once: the part (njoints, N, 3) of each joint's vector
    of ``vectors`` (njoints, N, 3) in the span of its columns of ``columns`` (N, 3, nv), whose
    owners are ``owner`` (nv,) (:attr:`~feeder.chain.kinematics.layout.TreeLayout.
    column_joint`). The joints with one non-zero column (revolute, prismatic) are projected
    together, those with several one by one."""
    out = np.zeros_like(vectors)
    active = np.flatnonzero((columns != 0.0).any(axis=0).any(axis=0))
    count = np.bincount(owner[active], minlength=vectors.shape[0])
    single = active[count[owner[active]] == 1]
    if single.size:
        joints = owner[single]
        axis = np.moveaxis(np.take(columns, single, axis=2), 2, 0)  # (k, N, 3)
        along = np.einsum("kni,kni->kn", axis, vectors[joints]) / np.einsum(
            "kni,kni->kn", axis, axis
        )
        out[joints] = along[..., None] * axis
    for j in np.flatnonzero(count > 1):
        out[j] = _along(columns[:, :, owner == j], vectors[j])
    return out


def _along(columns: np.ndarray, vector: np.ndarray) -> np.ndarray:
    """The part (N, 3) of ``vector`` (N, 3) in the span of ``columns`` (N, 3, k) (orthogonal
    projection; zero where the columns are zero: a joint that does not turn, or slide)."""
    active = np.abs(columns).max(axis=(0, 1)) > 0.0
    if not active.any():
        return np.zeros_like(vector)
    basis = columns[:, :, active]
    if basis.shape[2] == 1:  # one axis (revolute, prismatic): (e · x) e / (e · e)
        axis = basis[:, :, 0]
        along = np.einsum("ni,ni->n", axis, vector) / np.einsum("ni,ni->n", axis, axis)
        return along[:, None] * axis
    gram = np.swapaxes(basis, 1, 2) @ basis
    weights = np.linalg.solve(gram, np.einsum("nik,ni->nk", basis, vector)[..., None])
    return (basis @ weights)[..., 0]
