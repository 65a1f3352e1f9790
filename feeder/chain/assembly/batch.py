"""Continuation of a long trajectory in batches: every :data:`STRIDE`-th sample by the
sequential continuation (:func:`~feeder.chain.assembly.continuation.advance`, which keeps the
branch and checks every pose), the samples between them all at once.

Each sample between two coarse ones is predicted by the cubic Hermite curve through both coarse
poses with the closure's tangents there (error O(stride⁴): ~1e-7 on the shipped examples at a
stride of 32, where a one-sided tangent errs by ~1e-5), and Newton runs on all of them together
on the batched kinematics (:mod:`feeder.chain.kinematics`). With J_r the closure rows that are
independent at the first pose (redundant rows, such as a planar loop's out-of-plane ones,
dropped), restricted to the dependent columns, each step is the minimum-norm one,
Δ = −J_r⁺ r (J_r⁻¹ when it is square, Jᵀ (J Jᵀ)⁻¹ when idle motions leave it wide): one small
solve per sample instead of a singular value decomposition. The last Newton pass's Jacobians give
the rates; one velocity pass gives the accelerations' bias. Passes at rest skip the velocity
recursions.

The sequential path's checks run on every sample: the loops closed to
:data:`~feeder.chain.assembly.newton.POSITION_TOLERANCE`, hinges the right way up, the correction
small next to the step (no branch switch), the joint limits; a sample that fails one is continued
sequentially from its predecessor instead. A rank that drops (J_r ill-conditioned), a
velocity gain past the limit, more than :data:`MAX_REDONE` of a stride's samples failing (the
first stride is tried alone first) or two consecutive samples further apart than the closure's
tangent allows in one sequential step (:func:`_check_steps`: a stride too long for the motion)
sends the whole trajectory back to the sequential path, which gives an error its precise
message. Idle motions: each inner sample takes the minimum-norm
correction from its prediction between the coarse samples, so an idle coordinate (a rod's spin
angle) may differ from the sequential path's by the drift that path accumulates between two
coarse samples (measured 2e-4 rad on the Cassie-like leg's rods); poses, rates and loads are
otherwise the same to round-off.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import scipy.linalg

from ...exceptions import SingularPoseError, UnreachablePoseError
from ..kinematics.pose import ChainPose
from ..kinematics.rows import closure_kinematics
from ..kinematics.tree import tree_motion
from .check import PoseCheck
from .continuation import advance
from .newton import CONTINUATION_STEP, POSITION_TOLERANCE, RANK_TOLERANCE
from .rank import condition_bound, velocity_gain
from .trajectory import Trajectory

STRIDE = 32
"""Samples between two sequentially continued ones (32 measured fastest on the benchmarks'
mechanisms: 16 doubles the sequential work, 64 needs a second Newton pass)."""

NEWTON_STEPS = 8
"""Batched Newton iterations; a sample not closed by then is done the sequential way (from the
Hermite predictor the error falls quadratically: 1–2 suffice)."""

MIN_SAMPLES = 2 * STRIDE
"""Trajectories shorter than this run sequentially (nothing to gain)."""

MAX_REDONE = 0.25
"""Largest fraction of the inner samples that may fail the batched checks and be redone one by
one; past it the whole trajectory goes the sequential way at once. A redone sample costs ~3
sequential ones (its predecessor checked anew, then its own step): with 112 of 193 redone the
batched tracking took 1.8 × the sequential one (issue 29); break-even is near a third."""


class BatchFallback(Exception):
    """A batched sample failed a check: the trajectory goes the sequential way."""


def batch_track(
    partition,
    first: PoseCheck,
    x: np.ndarray,
    dx: np.ndarray,
    ddx: np.ndarray,
    times: np.ndarray | None = None,
) -> Trajectory:
    """The motion along ``x`` (N, n_ind) with rates ``dx`` and accelerations ``ddx`` from the
    checked first sample ``first``, for the :class:`~feeder.chain.assembly.partition.Partition`
    ``partition`` (module docstring); ``times`` [s] name the samples in the messages.

    Raises:
        BatchFallback: A check failed on some sample.
        FeederError: The sequential continuation of a sample that failed a check refused it.
    """
    kept = _independent_rows(first.jacobian, partition)
    q, jacobian = _positions(partition, first, x, kept, times)
    v, a, gain, rates = _rates(partition, q, jacobian, dx, ddx, kept)
    _check_steps(partition, q, x, rates)
    return Trajectory(q, v, a, gain, batched=True)


def _positions(partition, first, x, kept, times) -> tuple[np.ndarray, np.ndarray]:
    """The configurations (N, nq) and their closure Jacobians (N, nc, nv): every
    :data:`STRIDE`-th sample continued sequentially, the others predicted from them and
    corrected together; a sample that fails a check there is continued sequentially from the
    one before it (which is on the branch). The first stride goes alone first: one too long
    for the motion shows there (more than :data:`MAX_REDONE` of its samples fail), before the
    other coarse samples cost their sequential work."""
    chain = partition.chain
    n = x.shape[0]
    coarse = list(range(0, n, STRIDE))
    if coarse[-1] != n - 1:
        coarse.append(n - 1)
    q = np.empty((n, chain.model.nq))
    jacobian = np.empty((n, chain.nc, chain.model.nv))
    checks = {0: first}  # the samples continued sequentially
    q[0], jacobian[0] = first.q, first.jacobian
    for anchors in (coarse[:2], coarse[1:]):
        for c0, c1 in zip(anchors, anchors[1:], strict=False):
            try:  # a refusal: the sequential path decides
                checks[c1] = advance(partition, checks[c0], x[c0], x[c1], c1, times)
            except (UnreachablePoseError, SingularPoseError) as exc:
                raise BatchFallback(str(exc)) from exc
            q[c1], jacobian[c1] = checks[c1].q, checks[c1].jacobian
        inner = np.setdiff1d(np.arange(anchors[0], anchors[-1] + 1), anchors)
        if not inner.size:
            continue
        tangents = {c: checks[c].tangent() for c in anchors}
        guess, scale = _predict(partition, q, anchors, tangents, inner, x)
        q[inner], jacobian[inner], failed = _newton(partition, guess, kept, scale)
        if failed.sum() > MAX_REDONE * inner.size:
            raise BatchFallback("the stride is too long for the motion")
        for i in inner[failed]:  # in increasing order: q[i − 1] is always settled
            before = checks[i - 1] if i - 1 in checks else ChainPose(chain, q[i - 1])
            checks[i] = advance(partition, before, x[i - 1], x[i], i, times, known=first)
            q[i], jacobian[i] = checks[i].q, checks[i].jacobian
    return q, jacobian


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


def _predict(partition, q, coarse, tangents, inner, x) -> tuple[np.ndarray, np.ndarray]:
    """Each inner sample predicted between its two coarse neighbours c0 < i < c1 by the cubic
    Hermite curve in s = (i − c0)/(c1 − c0) through both poses with both tangents (the
    closure's tangent times the path's rate dx/ds, central differences of ``x``): error
    O(stride⁴), where the one-sided tangent predictor errs by O(stride²); its independent
    coordinates set exactly. Also the size of each prediction's step, max |x_i − x_c| from the
    nearest coarse sample c (the scale of the branch check)."""
    model = partition.chain.model
    dependent, independent = partition.dependent, partition.independent
    anchors = np.array(coarse)
    right = np.searchsorted(anchors, inner)
    c0, c1 = anchors[right - 1], anchors[right]
    span = (c1 - c0)[:, None]
    s = (inner[:, None] - c0[:, None]) / span
    rate = np.gradient(x, axis=0, edge_order=2) if x.shape[0] > 2 else np.gradient(x, axis=0)

    def slope(c: np.ndarray) -> np.ndarray:  # dq/ds at the coarse samples c, (k, nv)
        out = np.empty((c.size, model.nv))
        out[:, independent] = rate[c] * span
        out[:, dependent] = np.einsum(
            "kij,kj->ki", np.array([tangents[int(k)] for k in c]), rate[c] * span
        )
        return out

    flat = model.nq == model.nv
    chord = _difference(model, q[c0], q[c1], flat)
    chord[:, partition.angle_columns] = np.angle(
        np.exp(1j * chord[:, partition.angle_columns])
    )  # dependent angles are wrapped: the short way round
    h01, h10, h11 = 3 * s**2 - 2 * s**3, s**3 - 2 * s**2 + s, s**3 - s**2
    step = h10 * slope(c0) + h01 * chord + h11 * slope(c1)
    guess = _integrate(model, q[c0], step, flat)
    guess = np.array(
        [partition.with_independent(g, xi) for g, xi in zip(guess, x[inner], strict=True)]
    )
    nearest = np.where(s[:, 0] <= 0.5, c0, c1)
    return guess, np.abs(x[inner] - x[nearest]).max(axis=1, initial=0.0)


def _integrate(model: pin.Model, q: np.ndarray, step: np.ndarray, flat: bool) -> np.ndarray:
    if flat:
        return q + step
    return np.array([pin.integrate(model, a, b) for a, b in zip(q, step, strict=True)])


def _difference(model: pin.Model, q0: np.ndarray, q1: np.ndarray, flat: bool) -> np.ndarray:
    if flat:
        return q1 - q0
    return np.array([pin.difference(model, a, b) for a, b in zip(q0, q1, strict=True)])


def _newton(
    partition, q: np.ndarray, kept: np.ndarray, scale: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Minimum-norm Newton on the inner samples at once (module docstring); returns the
    configurations (wrapped, within limits), their closure Jacobians (N, nc, nv), and which
    samples failed a check (not closed, a hinge upside down, a correction large next to the
    step)."""
    chain, model = partition.chain, partition.chain.model
    dependent = partition.dependent
    flat = model.nq == model.nv
    start = q.copy()
    for iteration in range(NEWTON_STEPS + 1):
        rows = closure_kinematics(chain, tree_motion(model, q))
        open_ = np.linalg.norm(rows.residual, axis=1) > POSITION_TOLERANCE
        if not open_.any() or iteration == NEWTON_STEPS:
            break
        jac = rows.jacobian[:, kept[:, None], dependent]
        step = np.zeros((q.shape[0], model.nv))
        step[:, dependent] = -_min_norm_solve(jac, rows.residual[:, kept])
        step[~open_] = 0.0
        q = _integrate(model, q, step, flat)
    failed = open_.copy()
    for alignment in rows.hinge_alignment.values():
        failed |= alignment < 0.0
    correction = np.abs(_difference(model, start, q, flat)).max(axis=1)
    failed |= (correction > CONTINUATION_STEP * np.maximum(scale, 1e-12)) & (correction > 1e-9)
    q = partition.wrap(q)
    partition.check_limits(q[~failed])
    return q, rows.jacobian, failed


def _min_norm_solve(jac: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """The minimum-norm solutions x (n, d) of J x = rhs, J (n, r, d) of full row rank: J⁻¹ rhs
    when square (no idle motions), else Jᵀ (J Jᵀ)⁻¹ rhs."""
    try:
        if jac.shape[1] == jac.shape[2]:
            return np.linalg.solve(jac, rhs[..., None])[..., 0]
        lagrange = np.linalg.solve(jac @ np.swapaxes(jac, 1, 2), rhs[..., None])
    except np.linalg.LinAlgError as exc:
        raise BatchFallback("a singular pose") from exc
    return (np.swapaxes(jac, 1, 2) @ lagrange)[..., 0]


def _right_inverse(jac: np.ndarray) -> np.ndarray:
    """J⁺ (n, d, r) of J (n, r, d) of full row rank: J⁻¹ when square (no idle motions), else
    Jᵀ (J Jᵀ)⁻¹."""
    try:
        if jac.shape[1] == jac.shape[2]:
            return np.linalg.inv(jac)
        transposed = np.swapaxes(jac, 1, 2)
        return transposed @ np.linalg.inv(jac @ transposed)
    except np.linalg.LinAlgError as exc:
        raise BatchFallback("a rank drop") from exc


def _check_steps(partition, q: np.ndarray, x: np.ndarray, rates: np.ndarray) -> None:
    """The sequential continuation's branch test on every pair of consecutive samples: the
    change of the coordinates from sample i to i + 1 must be the closure's tangent at i times
    the change of the independent ones, q_dep(i+1) − q_dep(i) = R_i (x(i+1) − x(i)) (R_i, the
    rates ``rates`` (N, n_dep, n_ind)), within the correction
    :func:`~feeder.chain.assembly.continuation.advance` accepts in one step
    (:data:`~feeder.chain.assembly.newton.CONTINUATION_STEP` of the step). A stride too long for
    the motion (a crank turning past a full revolution between two coarse samples) makes the
    Hermite predictions meaningless: Newton still closes the loops, on either branch, with a
    correction that the per-sample test (scaled by the distance to the coarse sample) lets
    pass. Raises :class:`BatchFallback` where any pair fails: the sequential path then decides,
    subdividing the steps it must."""
    model = partition.chain.model
    change = _difference(model, q[:-1], q[1:], model.nq == model.nv)
    angles = partition.angle_columns
    change[:, angles] = np.angle(np.exp(1j * change[:, angles]))  # wrapped: the short way
    step = np.diff(x, axis=0)
    tangent = -np.einsum("nij,nj->ni", rates[:-1], step)
    error = np.abs(change[:, partition.dependent] - tangent).max(axis=1, initial=0.0)
    size = np.abs(step).max(axis=1, initial=0.0)
    if np.any((error > CONTINUATION_STEP * np.maximum(size, 1e-12)) & (error > 1e-9)):
        raise BatchFallback("the stride is too long for the motion")


def _rates(
    partition, q, jacobian, dx, ddx, kept
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Velocities, accelerations (minimum norm in the idle motions), velocity gains of every
    sample, and the rate maps J_dep⁺ J_ind (N, n_dep, n_ind) (q̇_dep = −J_dep⁺ J_ind q̇_ind),
    from the closure Jacobians (N, nc, nv) at q."""
    chain, model = partition.chain, partition.chain.model
    dependent, independent = partition.dependent, partition.independent
    n = q.shape[0]
    jac_dep = jacobian[:, kept[:, None], dependent]
    jac_ind = jacobian[:, kept[:, None], independent]
    inverse = _right_inverse(jac_dep)  # J_r,dep⁺ (n, n_dep, n_r)
    # Rank test without a decomposition: σ_max/σ_min ≤ ‖J‖_F ‖J⁺‖_F, so this passes only where
    # the singular values of J_r,dep stay above RANK_TOLERANCE of the largest (conservative: a
    # doubtful sample sends the trajectory the sequential way, which tests exactly).
    if not np.all(condition_bound(jac_dep, inverse) < 1.0 / RANK_TOLERANCE):
        raise BatchFallback("a rank drop")
    gains_map = inverse @ jac_ind  # J_dep⁺ J_ind, (n, n_dep, n_ind)
    scale = partition.speed_scale
    gain = velocity_gain(gains_map, scale[dependent], scale[independent])
    if np.any(gain > partition.max_gain):
        raise BatchFallback("near a singular pose")
    v = np.zeros((n, model.nv))
    v[:, independent] = dx
    v[:, dependent] = -np.einsum("nij,nj->ni", gains_map, dx)
    a = np.zeros((n, model.nv))
    a[:, independent] = ddx
    zero = np.zeros((n, model.nv))
    motion = tree_motion(model, q, v, zero)
    bias = closure_kinematics(chain, motion, v, with_jacobian=False).acceleration[:, kept]
    rhs = np.einsum("nij,nj->ni", jac_ind, ddx) + bias
    a[:, dependent] = -np.einsum("nij,nj->ni", inverse, rhs)
    return v, a, gain, gains_map
