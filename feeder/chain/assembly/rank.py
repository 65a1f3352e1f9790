"""The linear algebra of the rank tests: the motions left with the independent joints locked
(:func:`locked_motions`; idle motions among them move no point), truncated pseudo-inverses that
give idle motions no share, the velocity gain (:func:`velocity_gain`: dimensionless, lengths'
speeds in units of the mechanism's reach), the joints a motion moves (for the refusals), and the
self-stresses of the closures (:func:`self_stresses`: the closure forces that a rigid model
leaves undetermined, :func:`indeterminate_mask` the rows they involve).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from .newton import RANK_TOLERANCE

IDLE_TOLERANCE = 1e-9
"""An idle direction (unit vector of joint rates) may move a joint origin, frame or centre of
gravity by at most this [m per unit] times the mechanism's size: round-off of the Jacobians
(1e-16) is far below, any real lever arm (≥ 1e-3 of the size) far above."""


def rank_tolerance(jac: np.ndarray) -> float:
    """Singular values of the closure Jacobian ``jac`` at or below this are zero:
    :data:`~feeder.chain.assembly.newton.RANK_TOLERANCE` of its largest entry."""
    return RANK_TOLERANCE * (float(np.abs(jac).max(initial=0.0)) or 1.0)


def condition_bound(matrices: np.ndarray, inverses: np.ndarray) -> np.ndarray:
    """‖B‖_F ‖B⁺‖_F of each matrix B of a stack (n, m, k) and its computed inverse or
    pseudo-inverse B⁺ (n, k, m), (n,): a bound on its condition number σ_max/σ_min that needs
    no decomposition. A near-singular B has a computed inverse of huge norm (backward stability:
    it is the inverse of a matrix within round-off of B), so a test on the bound cannot pass by
    accident; inf where the inverse overflowed or is NaN (an exactly singular B)."""
    with np.errstate(invalid="ignore", over="ignore"):
        squares = np.einsum("nij,nij->n", matrices, matrices) * np.einsum(
            "nij,nij->n", inverses, inverses
        )
        bound = np.sqrt(squares)
    return np.where(np.isfinite(bound), bound, np.inf)


def locked_motions(
    jac: np.ndarray, dependent: np.ndarray, tolerance: float
) -> tuple[int, np.ndarray]:
    """The rank of the dependent columns ``jac[:, dependent]`` of the closure Jacobian (nc, nv)
    (singular values above ``tolerance``), and an orthonormal basis (k, nv) of the joint rates
    that keep the loops closed with every other column locked (k = 0 when there are none)."""
    nv = jac.shape[1]
    jac_dep = jac[:, dependent]
    if jac_dep.size:
        _, s, vt = np.linalg.svd(jac_dep)
        rank = int(np.sum(s > tolerance))
        free = vt[rank:]
    else:
        rank, free = 0, np.eye(dependent.size)
    motions = np.zeros((free.shape[0], nv))
    motions[:, dependent] = free
    return rank, motions


def truncated_inverse(
    matrix: np.ndarray, tolerance: float, relative: bool = False
) -> tuple[np.ndarray, int, np.ndarray]:
    """The pseudo-inverse of ``matrix`` (m, n) with its singular values at or below
    ``tolerance`` dropped (idle motions get no share: minimum-norm solutions), its rank r, and an
    orthonormal basis (m, r) of its range; ``relative``: ``tolerance`` is a fraction of the
    largest singular value (taken from the same decomposition)."""
    if matrix.size == 0:
        return np.zeros((matrix.shape[1], matrix.shape[0])), 0, np.zeros((matrix.shape[0], 0))
    u, s, vt = np.linalg.svd(matrix, full_matrices=False)
    keep = s > (tolerance * max(float(s[0]), 1e-300) if relative else tolerance)
    return (vt[keep].T / s[keep]) @ u[:, keep].T, int(keep.sum()), u[:, keep]


def velocity_gain(
    rates: np.ndarray, dependent: np.ndarray, independent: np.ndarray
) -> float | np.ndarray:
    """The velocity gain ‖S_dep⁻¹ R S_ind‖₂ of the rate map R = ∂q̇_dep/∂q̇_ind, (n_dep, n_ind)
    or (N, n_dep, n_ind) (then one gain per sample): the largest dependent speed per unit
    independent speed, each speed divided by its coordinate's scale S (the mechanism's reach L
    [m] for a length's rate, 1 for an angle's), so that it is dimensionless — rad/rad for a
    mechanism of revolute joints — and the same for a mechanism scaled up or down. 0 without
    dependent or independent coordinates.

    Args:
        rates: R, the minimum-norm solution's map (idle motions get no share).
        dependent, independent: The scales S (n_dep,), (n_ind,) [m or 1].
    """
    if rates.shape[-1] == 0 or rates.shape[-2] == 0:
        return 0.0 if rates.ndim == 2 else np.zeros(rates.shape[0])
    gain = np.linalg.norm(rates * (independent / dependent[:, None]), ord=2, axis=(-2, -1))
    return float(gain) if rates.ndim == 2 else gain


def moved_joints(model: pin.Model, motion: np.ndarray) -> tuple[str, ...]:
    """Names of the joints an idle motion (nv,) moves, largest share first."""
    shares = {
        model.names[j]: float(
            np.abs(
                motion[model.joints[j].idx_v : model.joints[j].idx_v + model.joints[j].nv]
            ).max()
        )
        for j in range(1, model.njoints)
    }
    return tuple(
        name for name, share in sorted(shares.items(), key=lambda x: -x[1]) if share > 1e-6
    )


SELF_STRESS_TOLERANCE = 1e-6
"""A closure row takes part in the self-stresses when the part of its unit vector in their span
(:func:`self_stresses`) exceeds this. Round-off of an SVD basis is ~1e-15 (ε times the
Jacobian's condition number, ~10 for the examples); but a row that takes no part at a symmetric
pose takes a share of the order of the distance to it, and an assembled pose sits up to ~1e-8
rad from where it was aimed (Bricard's linkage mounted at its symmetric pose: shares of 6e-9 in
two rows of its cut). A share of a millionth carries a millionth of the indeterminate force."""


GRAM_LIMIT = 1e10
"""Largest accepted bound ‖G‖_F ‖G⁻¹‖_F (≥ cond G = cond(J')²) of the Gram matrix G = J' J'ᵀ of
a closure Jacobian's moving rows J' for :func:`self_stress_bases` to take those rows as
independent without a decomposition: then cond J' ≤ 1e5, so its smallest singular value is
above 1e-5 of its largest, far above :func:`rank_tolerance` (1e-9 of the largest entry), and the
computed inverse (relative error ≤ cond(G) ε ≈ 1e-6) cannot pass by accident: a near-singular G
gives an inverse of huge norm (the argument of
:func:`~feeder.chain.dynamics.loads_solve._shortcut`)."""


def self_stresses(jac: np.ndarray) -> np.ndarray:
    """An orthonormal basis (k, nc) of the self-stresses of the closure Jacobian ``jac``
    (nc, nv): the closure forces λ with Jᵀ λ = 0, which balance each other on every body and do
    no work (k = nc − rank J, singular values at or below :func:`rank_tolerance` counting as
    zero). A rigid model cannot tell how much of them the closures carry: the forces of every row
    they involve (:func:`indeterminate_mask`) are statically indeterminate. One pose of
    :func:`self_stress_bases`."""
    return self_stress_bases(jac[None])[0]


def self_stress_bases(jacobians: np.ndarray) -> list[np.ndarray]:
    """:func:`self_stresses` of each closure Jacobian of a stack (n, nc, nv): n bases (k_i, nc).

    Where the rows that no joint moves (a row of norm at or below :func:`rank_tolerance`: a
    planar loop's out-of-plane rows) are the only dependence among the rows — the other rows J'
    independent by the margin of :data:`GRAM_LIMIT`, tested on their Gram matrices at once —
    the basis is those rows' unit vectors: they span the null space of Jᵀ, the one the singular
    value decomposition finds (it may return another orthonormal basis of it). The other poses
    take the decomposition."""
    n, nc, _ = jacobians.shape
    if nc == 0:
        return [np.zeros((0, 0)) for _ in range(n)]
    scale = np.abs(jacobians).max(axis=(1, 2))
    tolerance = RANK_TOLERANCE * np.where(scale > 0.0, scale, 1.0)
    still = np.linalg.norm(jacobians, axis=2) <= tolerance[:, None]  # (n, nc)
    bases: list[np.ndarray | None] = [None] * n
    groups: dict[bytes, list[int]] = {}  # the poses of each pattern of still rows
    for k, row in enumerate(still):
        groups.setdefault(row.tobytes(), []).append(k)
    for poses in groups.values():
        pattern = still[poses[0]]
        moving = jacobians[poses][:, ~pattern]
        passed = _independent(moving)
        unit = np.eye(nc)[pattern]
        for k, ok in zip(poses, passed, strict=True):
            bases[k] = unit.copy() if ok else _decomposed(jacobians[k])
    return bases


def _independent(rows: np.ndarray) -> np.ndarray:
    """Which stacks of rows (n, m, nv) are certainly independent (bool (n,)): the Gram bound of
    :data:`GRAM_LIMIT` (:func:`condition_bound`), no decomposition."""
    if rows.shape[1] == 0:
        return np.ones(rows.shape[0], dtype=bool)
    if rows.shape[1] > rows.shape[2]:  # more rows than columns: dependent
        return np.zeros(rows.shape[0], dtype=bool)
    gram = rows @ np.swapaxes(rows, 1, 2)
    try:
        inverse = np.linalg.inv(gram)
    except np.linalg.LinAlgError:  # some pose is exactly singular: the decomposition decides
        return np.zeros(rows.shape[0], dtype=bool)
    return condition_bound(gram, inverse) < GRAM_LIMIT


def _decomposed(jac: np.ndarray) -> np.ndarray:
    """The self-stresses of ``jac`` (nc, nv) from its singular value decomposition."""
    u, s, _ = np.linalg.svd(jac, full_matrices=True)
    rank = int(np.sum(s > rank_tolerance(jac)))
    return u[:, rank:].T.copy()


def indeterminate_mask(basis: np.ndarray) -> np.ndarray:
    """Which closure rows (nc,) bool the self-stresses ``basis`` (k, nc) (:func:`self_stresses`,
    orthonormal) involve: the part of the row's unit vector in their span (the norm of the row's
    column of B), above :data:`SELF_STRESS_TOLERANCE` (a property of the span, not of
    the basis chosen); for a stack of bases (n, k, nc), each one's (n, nc) (zero rows added to
    a basis change nothing: a stack of bases of different sizes is padded with them)."""
    return np.linalg.norm(basis, axis=-2) > SELF_STRESS_TOLERANCE
