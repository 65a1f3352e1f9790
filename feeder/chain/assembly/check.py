"""A partition's pose check (:meth:`~feeder.chain.assembly.partition.Partition.check_pose`):
the rank, idle-motion and gain tests of :mod:`feeder.chain.assembly.partition` at one pose, and
their result, :class:`PoseCheck` — the closure Jacobian, the truncated pseudo-inverse of its
dependent columns, the velocity gain and the idle motions, with the rates that follow from them.

The functions take the :class:`~feeder.chain.assembly.partition.Partition` (its public
attributes) and a :class:`~feeder.chain.kinematics.pose.ChainPose`; nothing is remembered
between two checks but what the caller passes back (``previous``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..kinematics.pose import ChainPose
from . import refusals
from .newton import POSITION_TOLERANCE
from .rank import (
    IDLE_TOLERANCE,
    locked_motions,
    moved_joints,
    rank_tolerance,
    truncated_inverse,
    velocity_gain,
)


@dataclass(frozen=True, eq=False)
class PoseCheck:
    """A checked pose (module docstring).

    Attributes:
        pose: The pose, its kinematics run once (:class:`~feeder.chain.kinematics.pose.
            ChainPose`).
        independent, dependent: The partition's velocity indices (n_ind,), (n_dep,).
        jacobian: The closure Jacobian J (nc, nv) at the pose, world axes.
        inverse: J_dep⁺ (n_dep, nc), the pseudo-inverse of J's dependent columns with their
            singular values at or below the rank tolerance dropped (idle motions get no share:
            the rates below are minimum-norm in them).
        gain: The velocity gain ‖S_dep⁻¹ J_dep⁺ J_ind S_ind‖₂ [–]
            (:mod:`feeder.chain.assembly.partition`), at most the partition's ``max_gain``.
        idle_count: The number k of idle motions (the rank deficiency of J's dependent columns,
            every such motion tested, or vouched for by an earlier check, to move no point);
            :meth:`idle_motions` gives them.
    """

    pose: ChainPose
    independent: np.ndarray
    dependent: np.ndarray
    jacobian: np.ndarray
    inverse: np.ndarray
    gain: float
    idle_count: int

    @property
    def q(self) -> np.ndarray:
        """The configuration (nq,), read-only."""
        return self.pose.q

    def idle_motions(self) -> np.ndarray:
        """The idle motions (k, nv): an orthonormal basis of the joint rates that keep the loops
        closed with the independent joints locked (empty when k = 0)."""
        if not self.idle_count:
            return np.zeros((0, self.jacobian.shape[1]))
        return locked_motions(self.jacobian, self.dependent, rank_tolerance(self.jacobian))[1]

    def tangent(self) -> np.ndarray:
        """∂q_dep/∂x (n_dep, n_ind): the closure's tangent, −J_dep⁺ J_ind."""
        return -self.inverse @ self.jacobian[:, self.independent]

    def step(self, dx: np.ndarray) -> np.ndarray:
        """The tangent step (nv,) for a step ``dx`` (n_ind,) of the independent coordinates:
        ``dx`` at their columns, −J_dep⁺ J_ind dx at the dependent ones (a continuation's
        first-order predictor)."""
        delta = np.zeros(self.jacobian.shape[1])
        delta[self.independent] = dx
        delta[self.dependent] = -self.inverse @ (self.jacobian[:, self.independent] @ dx)
        return delta

    def velocity(self, v_independent: np.ndarray) -> np.ndarray:
        """The velocity (nv,) with independent components ``v_independent`` (n_ind,) and
        J q̇ = 0 (unchecked inputs:
        :meth:`~feeder.chain.assembly.partition.Partition.velocity` checks them)."""
        v = np.zeros(self.jacobian.shape[1])
        v[self.independent] = v_independent
        v[self.dependent] = -self.inverse @ (self.jacobian @ v)
        return v

    def acceleration(self, v: np.ndarray, a_independent: np.ndarray) -> np.ndarray:
        """The acceleration (nv,) with independent components ``a_independent`` (n_ind,) and
        J q̈ + J̇ q̇ = 0 at the closed-chain velocity ``v`` (nv,) (J̇ q̇ from
        :meth:`~feeder.chain.model.closure.ClosedChain.bias`, which runs its own kinematics)."""
        a = np.zeros(self.jacobian.shape[1])
        a[self.independent] = a_independent
        bias = self.pose.chain.bias(self.pose.q, v)
        a[self.dependent] = -self.inverse @ (self.jacobian @ a + bias)
        return a


def check_pose(partition, pose: ChainPose, previous: PoseCheck | None = None) -> PoseCheck:
    """:meth:`~feeder.chain.assembly.partition.Partition.check_pose` (its docstring)."""
    q, jac = pose.q, pose.jacobian
    independent, dependent = partition.independent, partition.dependent
    jac_ind = jac[:, independent]
    tolerance = rank_tolerance(jac)
    pinv, rank_dep, range_dep = truncated_inverse(jac[:, dependent], tolerance)
    # The whole Jacobian has a larger rank than its dependent part iff some independent
    # column reaches outside the range of the dependent ones (J_ind's part off that range).
    outside = jac_ind - range_dep @ (range_dep.T @ jac_ind)
    reach = np.linalg.norm(outside, axis=0)
    if np.any(reach > tolerance):
        rank_full = rank_dep + np.linalg.matrix_rank(outside, tol=tolerance)
        freedom = jac.shape[1] - rank_full
        # A singular pose has more freedom than a regular one, never less: too many here are
        # too many everywhere (an open pose may have less: a planar loop's redundant rows).
        if pose.gap <= POSITION_TOLERANCE and independent.size > freedom:
            raise refusals.too_many_inputs(partition, freedom)
        pairs = zip(partition.independent_joints, reach, strict=True)
        names = [name for name, size in pairs if size > tolerance]
        raise refusals.cannot_follow(partition, q, names, rank_full, rank_dep)
    idle = deficiency = dependent.size - rank_dep
    if deficiency and not (previous is not None and previous.idle_count == deficiency):
        idle = idle_motions(partition, pose).shape[0]  # raises unless every one is idle
    scale = partition.speed_scale
    gain = velocity_gain(pinv @ jac_ind, scale[dependent], scale[independent])
    if gain > partition.max_gain:
        weakest = refusals.weakest_joints(partition, jac, tolerance)
        raise refusals.near_singular(partition, q, weakest, gain)
    return PoseCheck(pose, independent, dependent, jac, pinv, gain, idle)


def idle_motions(partition, pose: ChainPose) -> np.ndarray:
    """The motions (k, nv) left at ``pose`` with the independent joints locked, an orthonormal
    basis, tested to move no joint origin, frame or centre of gravity by more than
    :data:`~feeder.chain.assembly.rank.IDLE_TOLERANCE` of the reach per unit rate.

    Raises:
        SingularPoseError: A motion moves a point (its joints named).
    """
    jac = pose.jacobian
    rank, motions = locked_motions(jac, partition.dependent, rank_tolerance(jac))
    if motions.shape[0] == 0:
        return motions
    moved = np.abs(pose.point_rows() @ motions.T).max(axis=0)
    if np.all(moved <= IDLE_TOLERANCE * partition.length):
        return motions
    names = moved_joints(pose.chain.model, motions[int(np.argmax(moved))])
    raise refusals.not_determined(partition, pose.q, rank, names, float(moved.max()))
