"""Assembly at given independent coordinates from a guess
(:meth:`~feeder.chain.assembly.partition.Partition.assemble`): damped Newton over the dependent
coordinates from the guess, which picks the branch; when it stops at a local minimum of the
residual, or its solution misses the requested branch, Newton again from seeded random guesses.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pinocchio as pin

from ...exceptions import SingularPoseError
from ..kinematics.pose import ChainPose
from . import refusals
from .check import PoseCheck
from .newton import POSITION_TOLERANCE, newton

RESTARTS = 50
"""Random restarts (seeded) that :meth:`~feeder.chain.assembly.partition.Partition.assemble`
tries when Newton from the guess stops at a local minimum of the residual, or its solution misses
the requested branch."""


def assemble(
    partition,
    q_guess: np.ndarray,
    branch: Callable[[np.ndarray], bool] | None,
    max_iterations: int,
) -> PoseCheck:
    """:meth:`~feeder.chain.assembly.partition.Partition.assemble` (its docstring) for
    ``partition``, the pose's check returned (its ``q`` is the configuration that method
    returns): a caller that goes on from the pose need not check it again."""
    chain = partition.chain
    q_guess = chain.check_q(q_guess)
    rng = np.random.default_rng(0)
    best: tuple[float, np.ndarray] | None = None
    missed_branch = False
    for attempt in range(1 + RESTARTS):
        start = q_guess if attempt == 0 else random_guess(partition, q_guess, rng)
        q, norm = newton(chain, start.copy(), partition.dependent, max_iterations)
        if best is None or norm < best[0]:
            best = (norm, q)
        if norm > POSITION_TOLERANCE or ChainPose(chain, q).reversed_hinges:
            continue  # not closed, or a hinge assembled upside down
        q = partition.wrap(q)
        if branch is not None and not branch(q):
            missed_branch = True
            continue
        partition.check_limits(q)
        return partition.check_pose(ChainPose(chain, q))
    if missed_branch:
        raise refusals.missed_branch(RESTARTS + 1)
    norm, q = best
    try:
        partition.check_pose(ChainPose(chain, q))
    except SingularPoseError as exc:
        raise refusals.end_of_travel(norm, exc) from None
    raise refusals.not_assembled(norm, max_iterations, RESTARTS)


def random_guess(partition, q: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """``q`` with its dependent coordinates replaced by random values (±π, or within the
    joint's range where it is set; random rotations for multi-coordinate joints)."""
    model = partition.chain.model
    random = pin.integrate(model, pin.neutral(model), rng.uniform(-np.pi, np.pi, model.nv))
    guess = q.copy()
    for j in range(1, model.njoints):
        joint = model.joints[j]
        if joint.idx_v in partition.dependent and joint.nq == 1:
            low, high = (
                model.lowerPositionLimit[joint.idx_q],
                model.upperPositionLimit[joint.idx_q],
            )
            if low == high or not (np.isfinite(low) and np.isfinite(high)):
                low, high = -np.pi, np.pi
            guess[joint.idx_q] = rng.uniform(low, high)
        elif joint.idx_v in partition.dependent:
            guess[joint.idx_q : joint.idx_q + joint.nq] = random[
                joint.idx_q : joint.idx_q + joint.nq
            ]
    return guess
