"""Damped minimum-norm Newton steps on the closure, and the mount of a mechanism from its open
(CAD) pose onto the nearest closed one.

Every step is a truncated-SVD least-squares step, so redundant closure rows (a planar loop),
idle motions (a rod that may spin about its axis) and the gimbal lock of a ball joint written as
three revolutes (a Jacobian that loses rank) are all harmless: the step is the smallest one that
reduces the residual, with Levenberg–Marquardt damping μ = ‖r‖² far from a solution (which keeps
Newton's quadratic convergence near it) and a backtracking line search.

The mount (:func:`mount`) solves min ‖q ⊖ q_ref‖ subject to r(q) = 0 over every coordinate: each
step is the Gauss–Newton step on r plus the part of the way back to q_ref that the closure leaves
free (the projection onto the null space of its Jacobian), the difference ⊖ taken on
Pinocchio's Lie groups. When the loops cannot close, :func:`loop_gaps` says which loop, by how
much, and how close it gets when it is the only one.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..model.closure import ClosedChain

POSITION_TOLERANCE = 1e-13
"""Closure residual [m] at which Newton stops: a few ulps of the mechanism's size (~1 m)."""

RANK_TOLERANCE = 1e-9
"""Singular values below this fraction of the largest count as zero in the rank tests and the
least-squares steps: far above round-off (1e-16) and far below any physical ratio of a
mechanism's lever arms."""

MAX_ITERATIONS = 100
"""Newton iterations before a solve gives up."""

CONTINUATION_STEP = 0.5
"""Largest accepted Newton correction after the predictor of a continuation step, as a fraction
of the step of the independent coordinates: a first-order predictor errs by O(step²), so a
correction this large means a step too coarse for the curvature, where the next solution may lie
on another branch."""

MOUNT_ITERATIONS = 400
"""Iterations of the mount from the open pose (its loops may start metres and half turns apart,
and its last iterations only walk along the closed set towards the reference)."""

STALL_WINDOW, STALL_GAIN = 25, 0.01
"""The mount from one start gives up when its gap has fallen by less than ``STALL_GAIN`` (1 %)
over the last ``STALL_WINDOW`` iterations: at that pace the 400 iterations would not even halve
it, let alone reach :data:`POSITION_TOLERANCE` (a loop that cannot close: an export whose loops
miss by millimetres crept from 0.15 to 0.104 over 350 iterations, measured). The restarts from
nudged poses still follow."""


def damped_step(
    jac: np.ndarray, residual: np.ndarray, tolerance: float = RANK_TOLERANCE
) -> np.ndarray:
    """The damped minimum-norm step −Σ σ/(σ² + μ) v uᵀ r over the singular triplets of ``jac``
    above ``tolerance`` (a fraction of the largest), μ = ‖r‖² (module docstring)."""
    if jac.size == 0:
        return np.zeros(jac.shape[1])
    u, s, vt = np.linalg.svd(jac, full_matrices=False)
    keep = s > tolerance * max(float(s[0]), 1e-300)
    damping = float(residual @ residual)
    gain = np.where(keep, s / (s**2 + damping), 0.0)
    return -vt.T @ (gain * (u.T @ residual))


def newton(
    chain: ClosedChain,
    q: np.ndarray,
    columns: np.ndarray,
    max_iterations: int = MAX_ITERATIONS,
    tolerance: float = RANK_TOLERANCE,
) -> tuple[np.ndarray, float]:
    """Damped Newton on the closure residual over the velocity ``columns`` (the others held),
    from ``q``, its steps over the singular values above ``tolerance`` of the largest
    (:func:`damped_step`); returns (q, ‖r‖)."""
    model = chain.model
    residual = chain.residual(q)
    norm = float(np.linalg.norm(residual))
    for _ in range(max_iterations):
        if norm <= POSITION_TOLERANCE:
            break
        step = np.zeros(model.nv)
        step[columns] = damped_step(chain.residual_jacobian(q)[:, columns], residual, tolerance)
        trial, trial_residual, trial_norm = _backtrack(chain, q, step, norm)
        if trial_norm >= norm:
            break
        q, residual, norm = trial, trial_residual, trial_norm
    return q, norm


def _backtrack(chain: ClosedChain, q: np.ndarray, step: np.ndarray, norm: float):
    """Halve ``step`` until the residual drops below ``norm`` (at most 30 times)."""
    for _ in range(30):
        trial = pin.integrate(chain.model, q, step)
        trial_residual = chain.residual(trial)
        trial_norm = float(np.linalg.norm(trial_residual))
        if trial_norm < norm:
            break
        step = 0.5 * step
    return trial, trial_residual, trial_norm


def mount(chain: ClosedChain, q_reference: np.ndarray) -> tuple[np.ndarray, float]:
    """The closed pose nearest to ``q_reference`` over every coordinate (module docstring);
    returns (q, ‖r‖), ‖r‖ > :data:`POSITION_TOLERANCE` when the loops do not close.

    A reference at a stationary point of the residual (a four-bar drawn with its links
    collinear: no first-order motion closes the gap) stalls Newton; then it starts again from
    the reference nudged by seeded random rotations of :data:`NUDGES` [rad, m], and keeps the
    closed pose nearest to the reference (the first one found among equally near mirror
    images): deterministic, and independent of the joint limits."""
    q, norm = _mount_from(chain, q_reference, q_reference)
    if norm <= POSITION_TOLERANCE:
        return q, norm
    rng = np.random.default_rng(0)
    best, best_distance = (q, norm), np.inf
    for size in NUDGES:
        start = pin.integrate(chain.model, q_reference, rng.normal(0.0, size, chain.model.nv))
        trial, trial_norm = _mount_from(chain, q_reference, start)
        distance = float(np.linalg.norm(pin.difference(chain.model, q_reference, trial)))
        if trial_norm <= POSITION_TOLERANCE and distance < best_distance - 1e-9:
            best, best_distance = (trial, trial_norm), distance
        elif best_distance == np.inf and trial_norm < best[1]:
            best = (trial, trial_norm)
    return best


NUDGES = (0.01, 0.01, 0.03, 0.03, 0.1, 0.1, 0.3, 0.3, 1.0, 1.0)
"""Standard deviations [rad, m] of the seeded nudges of :func:`mount` from a stalled reference:
small first (the nearest closed pose is usually close), then larger."""


def _mount_from(
    chain: ClosedChain, q_reference: np.ndarray, q: np.ndarray
) -> tuple[np.ndarray, float]:
    """:func:`mount` from the start ``q``."""
    model = chain.model
    q = q.copy()
    residual = chain.residual(q)
    norm = float(np.linalg.norm(residual))
    gaps = [norm]
    for _ in range(MOUNT_ITERATIONS):
        jac = chain.residual_jacobian(q)
        if norm > POSITION_TOLERANCE:
            step = damped_step(jac, residual)
            trial, trial_residual, trial_norm = _backtrack(chain, q, step, norm)
            stalled = (
                len(gaps) > STALL_WINDOW and trial_norm > (1.0 - STALL_GAIN) * gaps[-STALL_WINDOW]
            )
            if trial_norm >= norm or stalled:
                break
            gaps.append(trial_norm)
            q, residual, norm = trial, trial_residual, trial_norm
            continue
        # Closed: walk back towards the reference along the closed set (null-space step).
        offset = pin.difference(model, q_reference, q)
        if jac.size:
            _, s, vt = np.linalg.svd(jac)
            rank = int(np.sum(s > RANK_TOLERANCE * max(float(s[0]), 1e-300)))
            free = vt[rank:]
            step = -free.T @ (free @ offset)
        else:
            step = -offset
        if np.linalg.norm(step) <= 1e-12 * max(1.0, float(np.linalg.norm(offset))):
            break
        trial, trial_norm = newton(chain, pin.integrate(model, q, step), np.arange(model.nv))
        distance = float(np.linalg.norm(pin.difference(model, q_reference, trial)))
        if trial_norm > POSITION_TOLERANCE or distance >= np.linalg.norm(offset):
            break
        q, residual, norm = trial, chain.residual(trial), trial_norm
    return q, norm


def loop_gaps(chain: ClosedChain, q_reference: np.ndarray, q: np.ndarray) -> list[str]:
    """For each closure, at ``q`` (the best the mount reached): its gap [m] (position rows) and
    [rad] (rotation rows), and how close it gets when it is the only closure (mounted alone from
    ``q_reference``): one line of text per closure."""
    lines = []
    residual = chain.residual(q)
    for closure, rows in zip(chain.closures, chain.row_slices, strict=True):
        alone = ClosedChain(chain.model, [closure])
        q_alone, _ = mount(alone, q_reference)
        gap, gap_alone = residual[rows], alone.residual(q_alone)
        lines.append(
            f"loop {closure.label!r}: gap {np.linalg.norm(gap[:3]):.3g} m, "
            f"{np.linalg.norm(gap[3:]):.3g} rad; alone it closes to "
            f"{np.linalg.norm(gap_alone[:3]):.3g} m, {np.linalg.norm(gap_alone[3:]):.3g} rad"
        )
    return lines
