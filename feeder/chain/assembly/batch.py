"""Continuation of a long trajectory in batches: every :data:`STRIDE`-th sample by the
sequential continuation of :class:`~feeder.chain.assembly.partition.Partition` (which keeps the
branch and checks every pose), the samples between them all at once.

Each sample between the coarse ones starts from its nearest coarse sample moved along the
closure's tangent there (the sequential path's predictor, error ~ step² × curvature), and Newton
runs on all of them together on the batched kinematics (:mod:`feeder.chain.kinematics`). With
J_r the closure rows that are independent at the first pose (redundant rows, such as a planar
loop's out-of-plane ones, dropped: J_r J_rᵀ is positive definite), restricted to the dependent
columns, each step is the minimum-norm one, Δ = −J_rᵀ (J_r J_rᵀ)⁻¹ r: one small symmetric solve
per sample instead of a singular value decomposition. Rates and accelerations use the same
matrices.

The sequential path's checks run on every sample: the loops closed to
:data:`~feeder.chain.assembly.newton.POSITION_TOLERANCE`, hinges the right way up, the correction
small next to the step (no branch switch), the joint limits; a sample that fails one is continued
sequentially from its predecessor instead. A rank that drops (J_r J_rᵀ ill-conditioned) or a
velocity gain past the limit sends the whole trajectory back to the sequential path, which gives
the error its precise message. Idle motions: each inner sample takes the minimum-norm correction
from its coarse sample, so an idle coordinate (a rod's spin angle) may differ from the sequential
path's by the drift that path accumulates between two coarse samples (measured 2e-4 rad on the
Cassie-like leg's rods); poses, rates and loads are otherwise the same to round-off.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import scipy.linalg

from ...exceptions import UnreachablePoseError
from ..kinematics.rows import closure_kinematics
from ..kinematics.tree import tree_motion
from .newton import CONTINUATION_STEP, POSITION_TOLERANCE, RANK_TOLERANCE

STRIDE = 16
"""Samples between two sequentially continued ones."""

NEWTON_STEPS = 8
"""Batched Newton iterations; a sample not closed by then is done the sequential way (from a
first-order predictor the error falls quadratically: 3–4 suffice)."""

MIN_SAMPLES = 2 * STRIDE
"""Trajectories shorter than this run sequentially (nothing to gain)."""


class BatchFallback(Exception):
    """A batched sample failed a check: the trajectory goes the sequential way."""


def batch_track(
    partition, q_first: np.ndarray, x: np.ndarray, dx: np.ndarray, ddx: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """q (N, nq), v, a (N, nv) and the velocity gain (N,) along ``x`` from the closed first
    sample ``q_first``, for the :class:`~feeder.chain.assembly.partition.Partition`
    ``partition`` (module docstring).

    Raises:
        BatchFallback: A check failed on some sample.
        FeederError: The sequential continuation of the coarse samples refused one.
    """
    if partition._prismatic.size:
        raise BatchFallback("prismatic speeds are scaled per sample")
    kept = _independent_rows(partition.chain.jacobian(q_first), partition)
    q = _positions(partition, q_first, x, kept)
    v, a, gain = _rates(partition, q, dx, ddx, kept)
    return q, v, a, gain


def _positions(partition, q_first, x, kept) -> np.ndarray:
    """The configurations (N, nq): every :data:`STRIDE`-th sample continued sequentially, the
    others predicted from them and corrected together; a sample that fails a check there is
    continued sequentially from the one before it (which is on the branch)."""
    n = x.shape[0]
    coarse = list(range(0, n, STRIDE))
    if coarse[-1] != n - 1:
        coarse.append(n - 1)
    q = np.empty((n, partition.chain.model.nq))
    q[0] = q_first
    for c0, c1 in zip(coarse, coarse[1:], strict=False):
        try:
            q[c1] = partition._continue(q[c0], x[c0], x[c1], c1)
        except UnreachablePoseError as exc:  # maybe only the stride is too long: sample by sample
            raise BatchFallback(str(exc)) from exc
    inner = np.setdiff1d(np.arange(n), coarse)
    if inner.size:
        guess, scale = _predict(partition, q, coarse, inner, x, kept)
        q[inner], failed = _newton(partition, guess, kept, scale)
        for i in inner[failed]:  # in increasing order: q[i − 1] is always settled
            q[i] = partition._continue(q[i - 1], x[i - 1], x[i], i)
    return q


def _independent_rows(jac: np.ndarray, partition) -> np.ndarray:
    """Indices of a set of closure rows that are independent at the first pose (pivoted QR of
    the dependent columns' rows), as many as their rank."""
    dependent = jac[:, partition.dependent]
    if dependent.size == 0:
        return np.zeros(0, dtype=int)
    _, r, pivots = scipy.linalg.qr(dependent.T, pivoting=True, mode="economic")
    diagonal = np.abs(np.diag(r))
    rank = int(np.sum(diagonal > RANK_TOLERANCE * max(float(diagonal[0]), 1e-300)))
    return np.sort(pivots[:rank])


def _predict(partition, q: np.ndarray, coarse: list[int], inner: np.ndarray, x: np.ndarray, kept):
    """Each inner sample predicted from its nearest coarse sample c along the closure's tangent
    there (minimum norm in the idle motions), its independent coordinates set exactly; and the
    size of each prediction's step, max |x_i − x_c| (the scale of the branch check)."""
    chain, model = partition.chain, partition.chain.model
    dependent, independent = partition.dependent, partition.independent
    anchors = np.array(coarse)
    nearest = anchors[np.abs(inner[:, None] - anchors[None, :]).argmin(axis=1)]
    rows = closure_kinematics(
        chain, tree_motion(model, q[nearest]), np.zeros((inner.size, model.nv))
    )
    jac = rows.jacobian[:, kept]
    jac_dep, jac_ind = jac[:, :, dependent], jac[:, :, independent]
    gram = jac_dep @ np.swapaxes(jac_dep, 1, 2)
    try:
        tangent = -np.swapaxes(jac_dep, 1, 2) @ np.linalg.solve(gram, jac_ind)
    except np.linalg.LinAlgError as exc:
        raise BatchFallback("a singular coarse pose") from exc
    step_ind = x[inner] - x[nearest]
    step = np.zeros((inner.size, model.nv))
    step[:, independent] = step_ind
    step[:, dependent] = np.einsum("nij,nj->ni", tangent, step_ind)
    guess = _integrate(model, q[nearest], step, model.nq == model.nv)
    guess = np.array(
        [partition.with_independent(g, xi) for g, xi in zip(guess, x[inner], strict=True)]
    )
    return guess, np.abs(step_ind).max(axis=1, initial=0.0)


def _integrate(model: pin.Model, q: np.ndarray, step: np.ndarray, flat: bool) -> np.ndarray:
    if flat:
        return q + step
    return np.array([pin.integrate(model, a, b) for a, b in zip(q, step, strict=True)])


def _newton(
    partition, q: np.ndarray, kept: np.ndarray, scale: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Minimum-norm Newton on the inner samples at once (module docstring); returns the
    configurations (wrapped, within limits) and which samples failed a check (not closed, a
    hinge upside down, a correction large next to the step)."""
    chain, model = partition.chain, partition.chain.model
    dependent = partition.dependent
    flat = model.nq == model.nv
    start = q.copy()
    zero = np.zeros((q.shape[0], model.nv))
    for _ in range(NEWTON_STEPS):
        rows = closure_kinematics(chain, tree_motion(model, q), zero)
        open_ = np.linalg.norm(rows.residual, axis=1) > POSITION_TOLERANCE
        if not open_.any():
            break
        jac = rows.jacobian[:, kept][:, :, dependent]
        gram = jac @ np.swapaxes(jac, 1, 2)
        try:
            lagrange = np.linalg.solve(gram, rows.residual[:, kept, None])
        except np.linalg.LinAlgError as exc:
            raise BatchFallback("a singular pose") from exc
        step = np.zeros((q.shape[0], model.nv))
        step[:, dependent] = -(np.swapaxes(jac, 1, 2) @ lagrange)[..., 0]
        step[~open_] = 0.0
        q = _integrate(model, q, step, flat)
    rows = closure_kinematics(chain, tree_motion(model, q), zero)
    failed = np.linalg.norm(rows.residual, axis=1) > POSITION_TOLERANCE
    for alignment in rows.hinge_alignment.values():
        failed |= alignment < 0.0
    if flat:
        correction = np.abs(q - start).max(axis=1)
    else:
        pairs = zip(start, q, strict=True)
        correction = np.array([np.abs(pin.difference(model, a, b)).max() for a, b in pairs])
    failed |= (correction > CONTINUATION_STEP * np.maximum(scale, 1e-12)) & (correction > 1e-9)
    q = partition.wrap(q)
    partition._check_limits(q[~failed])
    return q, failed


def _rates(partition, q, dx, ddx, kept) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Velocities, accelerations (minimum norm in the idle motions) and velocity gains of every
    sample, from the factor of J_r J_rᵀ."""
    chain, model = partition.chain, partition.chain.model
    dependent, independent = partition.dependent, partition.independent
    n = q.shape[0]
    zero = np.zeros((n, model.nv))
    rows = closure_kinematics(chain, tree_motion(model, q), zero)
    jac = rows.jacobian[:, kept]
    jac_dep, jac_ind = jac[:, :, dependent], jac[:, :, independent]
    gram = jac_dep @ np.swapaxes(jac_dep, 1, 2)
    eigenvalues = np.linalg.eigvalsh(gram)
    if np.any(eigenvalues[:, 0] <= (RANK_TOLERANCE * np.sqrt(eigenvalues[:, -1])) ** 2):
        raise BatchFallback("a rank drop")
    transposed = np.swapaxes(jac_dep, 1, 2)
    gains_map = transposed @ np.linalg.solve(gram, jac_ind)  # J_dep⁺ J_ind, (n, n_dep, n_ind)
    gain = np.sqrt(
        np.linalg.eigvalsh(np.swapaxes(gains_map, 1, 2) @ gains_map)[:, -1].clip(min=0.0)
    )
    if np.any(gain > partition.max_gain):
        raise BatchFallback("near a singular pose")
    v = np.zeros((n, model.nv))
    v[:, independent] = dx
    v[:, dependent] = -np.einsum("nij,nj->ni", gains_map, dx)
    a = np.zeros((n, model.nv))
    a[:, independent] = ddx
    bias = closure_kinematics(chain, tree_motion(model, q, v, zero), v).acceleration[:, kept]
    rhs = np.einsum("nij,nj->ni", jac_ind, ddx) + bias
    a[:, dependent] = -(transposed @ np.linalg.solve(gram, rhs[..., None]))[..., 0]
    return v, a, gain
