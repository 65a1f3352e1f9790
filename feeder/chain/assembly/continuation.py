"""Sequential continuation along a motion, on one assembly branch: each sample from the one
before it, through the public methods of :class:`~feeder.chain.assembly.partition.Partition`
(and, for a first sample on a requested branch, the assembly behind
:meth:`~feeder.chain.assembly.partition.Partition.assemble`, whose pose check it keeps).

Each step starts Newton from the previous pose moved along the closure's tangent (a first-order
predictor, :meth:`~feeder.chain.assembly.check.PoseCheck.step`), with no restarts; its correction
must stay small next to the step, else a branch switch is possible. A part of the step that fails
is halved, one that succeeds doubled (a ball joint written as three revolutes near gimbal lock, or
a dead centre, curve the dependent coordinates sharply); a part below :data:`MIN_FRACTION` of the
step that still fails is a singular pose. Every pose reached is checked
(:meth:`~feeder.chain.assembly.partition.Partition.check_pose`), the check passed on from one
sample to the next (its idle motions vouch for a pose with as many).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pinocchio as pin

from ...exceptions import SingularPoseError
from ..kinematics.pose import ChainPose
from . import refusals, restarts
from .check import PoseCheck
from .newton import CONTINUATION_STEP, MAX_ITERATIONS, POSITION_TOLERANCE, newton
from .rank import rank_tolerance
from .trajectory import Trajectory

MOUNT_STEP = 0.05
"""Largest step [rad, m] of the independent coordinates when they are moved from the mounted
pose to the first requested values (the continuation's own step test refuses coarser ones)."""

MIN_FRACTION = 2.0**-40
"""Smallest part of a sample's step that the continuation tries (:func:`advance` halves a part
that fails): ~1e-12 of the step, round-off of the coordinates. Near a dead centre the parts that
succeed shrink with the distance to it (about half of it each), so the continuation creeps up to
it until the velocity gain passes :data:`~feeder.chain.assembly.partition.MAX_GAIN`, a gain of 1e3
lying ~1e-6 of the coordinates short of a four-bar's dead centre: well above this floor."""


def where(sample: int, times: np.ndarray | None) -> str:
    """The sample's number, and its time [s] when the motion has times."""
    if times is None:
        return f"sample {sample}"
    return f"sample {sample} (t = {times[sample]:.6g} s)"


def first_sample(
    partition,
    q_start: np.ndarray,
    x0: np.ndarray,
    branch: Callable[[np.ndarray], bool] | None,
    times: np.ndarray | None = None,
) -> PoseCheck:
    """The first sample of a motion, checked: ``q_start`` closed as it is (mounted if its loops
    are open, which picks the branch nearest to it), then its independent coordinates moved to
    ``x0`` by continuation in steps of at most :data:`MOUNT_STEP` — unless ``branch`` is given,
    which picks it by :meth:`~feeder.chain.assembly.partition.Partition.assemble` instead."""
    chain = partition.chain
    if branch is not None:  # assembled and checked once
        guess = partition.with_independent(q_start, x0)
        return restarts.assemble(partition, guess, branch, MAX_ITERATIONS)
    gap = float(np.abs(chain.residual(q_start)).max(initial=0.0))
    q = partition.mount(q_start) if gap > POSITION_TOLERANCE else q_start
    start = partition.independent_values(q)
    steps = max(1, int(np.ceil(np.abs(x0 - start).max(initial=0.0) / MOUNT_STEP)))
    current: PoseCheck | ChainPose = ChainPose(chain, q)
    for k in range(steps):
        begin, end = start + (x0 - start) * k / steps, start + (x0 - start) * (k + 1) / steps
        current = advance(partition, current, begin, end, 0, times)
    return current


def advance(
    partition,
    previous: PoseCheck | ChainPose,
    x_previous: np.ndarray,
    x: np.ndarray,
    sample: int,
    times: np.ndarray | None = None,
    known: PoseCheck | None = None,
) -> PoseCheck:
    """The next sample, checked, with independent coordinates ``x`` (module docstring).

    Args:
        partition: The partition.
        previous: The previous sample, checked or not yet (then checked here first); its
            independent coordinates are ``x_previous``.
        x_previous, x: The two samples' independent coordinates (n_ind,).
        sample: The next sample's number (and ``times``, its time), for the messages.
        known: A check on the same branch whose idle motions vouch for ``previous``'s.

    Raises:
        SingularPoseError: The motion reaches a singular pose on the way (a dead centre: the
            end of the independent joints' travel; or branches meeting), or a pose near one;
            the message names the sample, its time and the pose.
        UnreachablePoseError: The sample is outside a joint's limits.
    """
    current, done, part = previous, 0.0, 1.0
    last = previous if isinstance(previous, PoseCheck) else known  # vouches for idle motions
    try:
        while done < 1.0:
            if not isinstance(current, PoseCheck):
                current = last = partition.check_pose(current, last)
            end = min(1.0, done + part)
            start = x_previous + (x - x_previous) * done
            stop = x if end == 1.0 else x_previous + (x - x_previous) * end
            trial = _step(partition, current, start, stop)
            if trial is not None:
                current, done, part = trial, end, min(2.0 * part, 1.0)
                continue
            part /= 2.0
            if part < MIN_FRACTION:
                jac, q = current.jacobian, current.q
                weakest = refusals.weakest_joints(partition, jac, rank_tolerance(jac))
                at = partition.with_independent(q, start)
                raise refusals.dead_centre(partition, at, q, weakest, current.gain)
        q = partition.wrap(current.q)
        partition.check_limits(q)
        if last is not None and q.tobytes() == last.q.tobytes():
            return last  # the angles were in range: the pose the last part started from
        return partition.check_pose(ChainPose(partition.chain, q), last)
    except SingularPoseError as exc:
        raise SingularPoseError(f"{where(sample, times)}: {exc}") from None


def _step(partition, checked: PoseCheck, x_previous: np.ndarray, x: np.ndarray):
    """One predictor–corrector step of :func:`advance` from the checked pose: the pose reached
    (ChainPose), or None if it failed (the loops not closed, a hinge upside down, or the
    correction large next to the step)."""
    chain = partition.chain
    step = x - x_previous
    predicted = pin.integrate(chain.model, checked.q, checked.step(step))
    guess = partition.with_independent(predicted, x)
    q, norm = newton(chain, guess.copy(), partition.dependent)
    correction = float(np.abs(pin.difference(chain.model, guess, q)).max(initial=0.0))
    size = float(np.abs(step).max(initial=0.0))
    on_branch = correction <= CONTINUATION_STEP * max(size, 1e-12) or correction <= 1e-9
    if norm > POSITION_TOLERANCE or not on_branch:
        return None
    pose = ChainPose(chain, q)
    return None if pose.reversed_hinges else pose


def sequential(
    partition,
    first: PoseCheck,
    x: np.ndarray,
    dx: np.ndarray,
    ddx: np.ndarray,
    times: np.ndarray | None = None,
) -> Trajectory:
    """The motion along ``x`` (N, n_ind) with rates ``dx`` and accelerations ``ddx``, from the
    checked first sample ``first``, one sample after the other (:func:`advance`)."""
    model = partition.chain.model
    n = x.shape[0]
    q, v, a = np.empty((n, model.nq)), np.empty((n, model.nv)), np.empty((n, model.nv))
    gain = np.empty(n)
    checked = first
    for i in range(n):
        if i:
            checked = advance(partition, checked, x[i - 1], x[i], i, times)
        q[i], gain[i] = checked.q, checked.gain
        v[i] = checked.velocity(dx[i])
        a[i] = checked.acceleration(v[i], ddx[i])
    return Trajectory(q, v, a, gain, batched=False)
