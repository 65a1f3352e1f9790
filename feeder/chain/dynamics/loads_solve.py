"""The least-squares solve of the loads' equations, every sample at once.

For a checked closed-chain motion (:mod:`feeder.chain.dynamics.inverse`) the actuator loads τ and
closure forces λ meet, per sample,

    [Sᵀ Jᵀ] [τ; λ] = M q̈ + b − Σ_e J_eᵀ w_e                                 (nv rows)

with the right-hand side from the Newton–Euler pass (:mod:`.newton_euler`). The actuator loads
must be determined (otherwise the actuation itself is singular: :class:`SingularPoseError`) and
the equations consistent (otherwise the actuated joints cannot produce the motion:
:class:`InputError`). Closure rows that repeat others (a planar loop) leave a null space of
statically indeterminate forces: the answer is the one of minimum ‖K^(−1/2) λ‖ (K the per-row
stiffness, the closure columns scaled by √K); which rows and reactions those are is
:mod:`.indeterminacy`'s.

Three ways answer, cheapest first (:func:`_solve`): the inverse of a square system, the normal
equations of a well-conditioned one, and the singular value decomposition where the rank drops
or the conditioning is doubtful; the checks that decide which may answer share the tolerances
below. The closure rows that no joint moves at any sample (a planar loop's out-of-plane rows:
zero columns of the equations, whose minimum-norm forces are exactly 0) are left out first,
which often makes the system square: the N-four-bar's 2N + 1 equations in 1 + 3N unknowns become
2N + 1 in 2N + 1.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Mapping, Sequence
from typing import Protocol

import numpy as np

from ...exceptions import InputError, SingularPoseError
from ...validation import check_finite
from ..assembly.newton import RANK_TOLERANCE
from ..assembly.rank import condition_bound
from ..kinematics.rows import ClosureKinematics
from ..kinematics.tree import TreeMotion
from ..model.closure import ClosedChain
from .block_inverse import block_inverse
from .newton_euler import generalized_forces, joint_wrenches

CONSISTENCY = 1e-9
"""Largest accepted residual of the dynamic equations, relative to their largest term: the
actuated joints can produce the motion (round-off is ~1e-14)."""

NULL_SPACE = 1e-6
"""A null-space direction of the equations "involves" an unknown when its component there exceeds
this (directions are unit vectors; round-off components are ~1e-15)."""

NORMAL_EQUATIONS = 1e3
"""Largest condition number for which the minimum-norm solution comes from the normal
equations A Aᵀ y = b (which square it: 1e6 × 1e-16 of relative round-off, below the 1e-9 of the
checks); worse-conditioned samples take the singular value decomposition."""

RANK_SUBSAMPLE = 32
"""Samples of a motion on which the closure rows' rank is measured (their structural rank: the
largest found; a motion's rank only drops at isolated singular poses)."""

MAX_FORCE_GAIN = 1e4
"""Largest accepted condition number of the equations' determined part (σ_max over the smallest
non-zero singular value of [Sᵀ Jᵀ], SI units). It grows without bound near a toggle or dead
centre (like the inverse square root of the distance): measured 10–16 along the device's cycles,
5–33 for the examples, 2.5e3 a tenth of a milliradian from the rocker-driven four-bar's dead
centre (its velocity gain there is 100) and 8e4 a tenth of a microradian from it. 1e4, six
hundred times the device's worst, refuses loads that the last digits of the geometry decide."""


class LoadUnknowns(Protocol):
    """What the solve needs of a :class:`~feeder.chain.dynamics.inverse.ChainDynamics`.

    Attributes:
        chain: The closed chain (its closure rows' labels and Jacobian).
        columns: The actuated joints' velocity columns, one per actuator load.
        row_scale: √K per closure row (nc,), K the row's stiffness (1 by default).
    """

    chain: ClosedChain
    columns: list[int]
    row_scale: np.ndarray


def row_scale(chain: ClosedChain, stiffness: Mapping[str, Sequence[float]]) -> np.ndarray:
    """√K per closure row (nc,) from closure label → its rows' stiffness K (default 1).

    Raises:
        InputError: An unknown closure, or not one positive number per row of it.
    """
    weights = np.ones(chain.nc)
    labels = [closure.label for closure in chain.closures]
    for label, values in stiffness.items():
        if label not in labels:
            raise InputError(f"stiffness given for unknown closure {label!r}; closures: {labels}")
        rows = chain.row_slices[labels.index(label)]
        values = check_finite(f"stiffness of {label!r}", values)
        if values.shape != (rows.stop - rows.start,) or np.any(values <= 0.0):
            raise InputError(
                f"stiffness of {label!r} must be {rows.stop - rows.start} positive numbers"
            )
        weights[rows] = values
    return np.sqrt(weights)


def solve_loads(
    dyn: LoadUnknowns,
    motion: TreeMotion,
    rows: ClosureKinematics,
    wrenches: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """The actuator loads τ (N, n_act) and closure forces λ (N, nc) of a checked closed-chain
    motion (module docstring); ``wrenches``: the tree's Newton–Euler pass
    (:func:`~.newton_euler.joint_wrenches`: force, moment (njoints, N, 3)) with whatever
    external wrenches act on it, if the caller has it; else the pass without external wrenches."""
    model = dyn.chain.model
    force, moment = joint_wrenches(model, motion) if wrenches is None else wrenches
    tree = generalized_forces(model, motion, force, moment)  # M q̈ + b − Σ J_eᵀ w_e
    n_act = len(dyn.columns)
    # closure rows no joint moves at any sample (a planar loop's out-of-plane rows): their
    # columns of the equations are zero, their minimum-norm forces exactly 0, and the others'
    # solution the same without them (a square system, often: one inverse, no decomposition)
    moved = (rows.jacobian != 0.0).any(axis=0).any(axis=1)  # samples first: a long axis
    system = load_equations(dyn, rows.jacobian, moved)

    @functools.cache
    def terms() -> np.ndarray:  # the terms the tree's forces are summed from (N,)
        return np.maximum(
            np.abs(force[1:]).max(axis=(0, 2), initial=0.0),
            np.abs(moment[1:]).max(axis=(0, 2), initial=0.0),
        )

    solution = _solve(system, tree, n_act, terms)
    lam = np.zeros((solution.shape[0], dyn.chain.nc))
    lam[:, moved] = solution[:, n_act:] * dyn.row_scale[moved]
    return solution[:, :n_act], lam


def load_equations(
    dyn: LoadUnknowns, jacobian: np.ndarray, moved: np.ndarray | None = None
) -> np.ndarray:
    """The matrix [Sᵀ Jᵀ] of the loads' equations (module docstring; SI units, the closure
    columns scaled by the square root of their stiffness), (N, nv, n_act + nc), from the closure
    rows' Jacobians J (N, nc, nv); ``moved`` (nc,) bool: only those rows' columns (then
    n_act + their count columns). It is the transposed view of a contiguous [S; J] (the
    shortcut inverts that one: no transposed copy)."""
    scale = dyn.row_scale
    if moved is not None:
        jacobian, scale = np.compress(moved, jacobian, axis=1), scale[moved]
    n, nc, nv = jacobian.shape
    n_act = len(dyn.columns)
    transposed = np.empty((n, n_act + nc, nv))
    transposed[:, :n_act] = 0.0
    transposed[:, np.arange(n_act), dyn.columns] = 1.0  # S
    if np.all(scale == 1.0):  # the default stiffness: J as it is
        transposed[:, n_act:] = jacobian
    else:
        np.multiply(jacobian, scale[:, None], out=transposed[:, n_act:])
    return np.swapaxes(transposed, 1, 2)


def load_rank(dyn: LoadUnknowns, q: np.ndarray) -> int:
    """The rank the loads' equations have at a closed pose q (nq,) away from singular poses:
    the actuated joints' count plus the closure rows' rank there, at most nv (as
    :func:`~feeder.chain.dynamics.inverse.inverse_dynamics` expects of every sample)."""
    rank = _rank(dyn.chain.jacobian(q)[None])[0] if dyn.chain.nc else 0
    return min(dyn.chain.model.nv, len(dyn.columns) + int(rank))


def _rank(matrices: np.ndarray) -> np.ndarray:
    """The rank of each matrix of a stack (n, m, k), (n,): its singular values above
    :data:`~feeder.chain.assembly.newton.RANK_TOLERANCE` of its largest — the count the
    singular-value path of the solve uses (:func:`_solve_svd`). numpy's own default (the size
    times ε) would count a redundant row's round-off (1e-17 … 1e-15 of the largest, Bricard's
    sixth hinge) as rank at some samples and not at others."""
    s = np.linalg.svd(matrices, compute_uv=False)
    return np.sum(s > RANK_TOLERANCE * np.maximum(s[:, :1], 1e-300), axis=1)


def load_gain(dyn: LoadUnknowns, q: np.ndarray, rank: int) -> float:
    """Condition number of the loads' equations at the pose q (nq,): the largest singular value
    of :func:`load_equations` over its ``rank``-th (:func:`load_rank`; infinite where the rank
    has dropped, 1 with no unknown). The solve refuses a sample above :data:`MAX_FORCE_GAIN`."""
    if rank == 0:
        return 1.0
    system = load_equations(dyn, dyn.chain.jacobian(q)[None])[0]
    s = np.linalg.svd(system, compute_uv=False)
    return float(s[0] / s[rank - 1]) if s[rank - 1] > RANK_TOLERANCE * s[0] else math.inf


def _solve(
    system: np.ndarray, rhs: np.ndarray, n_act: int, terms: Callable[[], np.ndarray]
) -> np.ndarray:
    """Minimum-norm solutions x (n, nx) of system[k] x = rhs[k] (n, nv, nx), after the checks of
    the module docstring. ``terms()`` (n,): the largest term each sample's right-hand side is
    summed from (its round-off's scale, for the consistency check where the sum cancels: a
    mechanism at rest in equilibrium), computed only where a check needs it.

    Where a sample's system has full rank and a small condition number (every sample of a
    well-actuated motion), x = A⁺ b is its minimum-norm solution, from one small inverse
    (:func:`_shortcut`); the other samples, and a subsample for the structural checks (the null
    space of the equations), go through the singular value decomposition — unless every sample
    is square and passed the shortcut, which leaves those checks nothing to find."""
    n = system.shape[0]
    if system.shape[2] == 0:  # an open tree with nothing actuated: the reactions alone
        return np.zeros((n, 0))
    fast, inverse = _shortcut(system)
    square = system.shape[1] == system.shape[2]
    if fast.all():  # every sample: no mask (a masked copy of the inverses costs as much)
        solution = np.einsum("nij,nj->ni", inverse, rhs)
        if square:
            # every sample square and invertible within MAX_FORCE_GAIN: full rank, no null
            # space, consistent: nothing the decomposition checks can fail
            return solution
        _check_consistency(system, rhs, solution, terms())  # a least-squares answer
    else:
        solution = np.empty((n, system.shape[2]))
        if np.any(fast):
            solution[fast] = np.einsum("nij,nj->ni", inverse[fast], rhs[fast])
            if not square:  # a least-squares answer: is it a solution?
                _check_consistency(system[fast], rhs[fast], solution[fast], terms()[fast])
    stride = max(1, n // RANK_SUBSAMPLE)
    checked = np.zeros(n, dtype=bool)
    checked[::stride] = True
    detailed = ~fast | checked
    structural = int(_rank(system[checked][:, :, n_act:]).max(initial=0))
    expected = min(system.shape[1], n_act + structural)
    indices = np.flatnonzero(detailed)
    exact = _solve_svd(
        system[detailed], rhs[detailed], n_act, expected, indices, terms()[detailed]
    )
    solution[indices[~fast[detailed]]] = exact[~fast[detailed]]
    return solution


def _shortcut(system: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Which samples of system (n, nv, nx) are certainly well-conditioned (bool (n,)), and for
    them the pseudo-inverse A⁺ (n, nx, nv): A⁻¹ when square (round-off cond(A) ε); for a wide
    A (fewer equations than unknowns) the right inverse Aᵀ (A Aᵀ)⁻¹, the minimum-norm solution;
    for a tall one (more equations than unknowns: a leg whose closures leave the actuated
    joints' rows dependent) the left inverse (Aᵀ A)⁻¹ Aᵀ, the least-squares solution, which
    :func:`_solve` then checks solves the equations. Either Gram matrix is the one of the short
    side (the other, of rank nx < nv or nv < nx, is singular: a shortcut through it would never
    pass and would send every sample to the singular value decomposition), and it squares the
    condition number: cond(B) = cond(A)². The test needs no decomposition: cond(B) ≤ ‖B‖_F
    ‖B⁻¹‖_F for B = A or the Gram matrix (:func:`~feeder.chain.assembly.rank.condition_bound`).
    A near-singular B gives a computed inverse of huge norm (backward stability: it is the
    inverse of a matrix within round-off of B), so the bound cannot pass by accident — a
    full-rank A passes only with cond(A) below
    :data:`MAX_FORCE_GAIN` (square) or :data:`NORMAL_EQUATIONS` (Gram: ≤ 1e6 × ε of relative
    round-off); a doubtful sample takes the singular value decomposition, which also refuses a
    singular one. The inverse is a block triangular one (:mod:`.block_inverse`: the square
    systems of mechanisms with many loops are sparse), equal to a dense one to round-off."""
    rows, unknowns = system.shape[1:]
    square = rows == unknowns
    transposed = np.swapaxes(system, 1, 2)
    if square:  # (A⁻¹)ᵀ = (Aᵀ)⁻¹: Aᵀ is the contiguous one (load_equations)
        matrix, inverse = system, np.swapaxes(block_inverse(transposed), 1, 2)
    else:
        matrix = system @ transposed if rows < unknowns else transposed @ system
        inverse = block_inverse(matrix)
    fast = condition_bound(matrix, inverse) < (MAX_FORCE_GAIN if square else NORMAL_EQUATIONS**2)
    if rows < unknowns:
        inverse = transposed @ inverse
    elif rows > unknowns:
        inverse = inverse @ transposed
    return fast, inverse


def _solve_svd(
    system: np.ndarray,
    rhs: np.ndarray,
    n_act: int,
    expected: int,
    samples: np.ndarray,
    terms: np.ndarray,
) -> np.ndarray:
    """The singular-value path of :func:`_solve` on some samples (their indices in the motion:
    ``samples``, for the messages): the checks (singular actuation, consistency, determined
    actuator loads) and the minimum-norm solutions. ``expected``: the rank the actuators and the
    closure rows can give."""
    u, s, vt = np.linalg.svd(system, full_matrices=True)
    scale = np.maximum(s[:, :1], 1e-300)
    rank_mask = s > RANK_TOLERANCE * scale  # (n, min(nv, nx))
    inverse = np.where(rank_mask, 1.0 / np.where(rank_mask, s, 1.0), 0.0)
    rank = rank_mask.sum(axis=1)
    smallest = s[np.arange(s.shape[0]), np.maximum(rank - 1, 0)]
    gain = s[:, 0] / np.maximum(smallest, 1e-300)
    worst = int(np.argmax(gain))
    refused = (gain > MAX_FORCE_GAIN) | (rank < expected)
    if np.any(refused):
        i = int(np.argmax(refused))  # the first sample refused
        why = (
            f"condition number {gain[i]:.3g} > {MAX_FORCE_GAIN:g}"
            if rank[i] >= expected
            else "the equations lose rank: the actuated joints lose their hold on the motion"
        )
        raise SingularPoseError(
            f"sample {samples[i]} is at or near a singular pose (toggle, dead centre) of the "
            f"mechanism or its actuation: the loads are unbounded there "
            f"({why}; the worst sample: {samples[worst]}, condition number {gain[worst]:.3g})",
            sample=int(samples[i]),
        )
    k = min(system.shape[1:])
    projected = np.einsum("nji,nj->ni", u[:, :, :k], rhs)
    solution = np.einsum("nij,nj->ni", np.swapaxes(vt[:, :k, :], 1, 2), inverse * projected)
    _check_consistency(system, rhs, solution, terms)
    for r in np.unique(rank):  # samples of equal rank share the null-space dimension
        basis = vt[rank == r, r:, :n_act]  # (samples, dim, n_act)
        if basis.size and np.abs(basis).max() > NULL_SPACE:
            raise SingularPoseError(
                "the actuator loads are not determined: the actuated joints and the closures "
                "can balance each other without load (a singular or redundant actuation)"
            )
    return solution


def _check_consistency(
    system: np.ndarray, rhs: np.ndarray, solution: np.ndarray, terms: np.ndarray
) -> None:
    """Refuse (:class:`InputError`) solutions (n, nx) that leave system (n, nv, nx) x = rhs
    (n, nv) a residual above :data:`CONSISTENCY` of the equations' largest term (``terms``: see
    :func:`_solve`)."""
    misfit = np.abs(np.einsum("nij,nj->ni", system, solution) - rhs).max(axis=1)
    size = np.maximum.reduce(
        [
            np.abs(rhs).max(axis=1),
            np.abs(system).max(axis=(1, 2)) * np.abs(solution).max(axis=1),
            terms,
        ]
    )
    worst = int(np.argmax(misfit / np.maximum(size, 1e-300)))
    if misfit[worst] > CONSISTENCY * max(size[worst], 1e-300):
        raise InputError(
            f"the actuated joints cannot produce the motion: the equations of motion leave a "
            f"residual of {misfit[worst]:.3e} (choose other actuated joints)"
        )
