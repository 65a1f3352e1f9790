"""Inverse dynamics of any closed chain: actuator loads, closure forces and every joint's reaction.

For a prescribed motion (q, q̇, q̈) of the open tree cut at the closures, the closed chain moves
when the closure forces λ act at the cuts and the actuators drive the named joints:

    M(q) q̈ + b(q, q̇) − Σ_e J_eᵀ w_e = Sᵀ τ + Jᵀ λ                      (one sample, nv rows)

* M q̈ + b are the tree's Newton–Euler forces (gravity from the model); w_e are the external
  wrenches on named frames, J_e their frame Jacobians;
* J (nc × nv) are the closure rows (:class:`~feeder.chain.model.closure.ClosedChain`), λ the forces
  conjugate to them: a force [N] on the body of ``frame_a`` at its origin for the point rows, a
  moment [N·m] for the rotation rows, and the opposite on the body of ``frame_b``;
* S selects the actuated joints' velocity components; τ are their generalized forces.

nv equations in n_act + nc unknowns, solved for all samples at once. The actuator loads must be
determined (otherwise the actuation itself is singular: :class:`SingularPoseError`) and the
equations consistent (otherwise the actuated joints cannot produce the motion:
:class:`InputError`). Closure rows that repeat others (a planar loop) leave a null space of
statically indeterminate forces: the answer given is the one of minimum ‖K^(−1/2) λ‖, K the
optional per-row stiffness (default 1: minimum norm, SI units) — the forces a set of elastic
supports of stiffness K would share — and those rows are listed in
:attr:`ChainLoads.indeterminate`.

The reaction wrench of every joint of the tree is the wrench its parent exerts on its child,
world axes, moment about the joint's origin: the rate of momentum of the child's subtree less
gravity, the closure forces and the external wrenches acting on it
(:mod:`feeder.chain.kinematics.tree`: Newton–Euler over all samples at once, equal to Pinocchio's
RNEA to round-off), and the mount's: the wrench the base's support exerts on the whole mechanism.

On a moving base (:class:`~feeder.chain.model.base.BaseMotion`: a slope, a ride, a hull table)
q, q̇, q̈ are the motion relative to the base, and every vector (reactions, closure forces, external
wrenches) is in the base's moving axes; the closure rows are the relative motion's and the
Newton–Euler passes take the absolute one (:func:`~feeder.chain.kinematics.tree.on_base`).

The module is long (~500 lines) for one concern, the load solve: its equations, the three ways of
solving them (the inverse of a square system, the normal equations, the SVD where the rank drops)
and the checks that decide which of them may answer share their tolerances and their messages.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ...exceptions import InputError, SingularPoseError, UnreachablePoseError
from ...validation import check_finite, check_samples
from ..assembly.newton import RANK_TOLERANCE
from ..assembly.partition import Partition
from ..kinematics.joints import kind_of
from ..kinematics.rows import ClosureKinematics, closure_kinematics
from ..kinematics.tree import (
    TreeMotion,
    generalized_forces,
    joint_wrenches,
    on_base,
    tree_motion,
)
from ..model.base import BaseMotion, BaseState
from ..model.closure import ClosedChain
from ..model.forces import ForceElement
from .elements import BoundElements
from .idle import idle_accelerations, idle_basis
from .reactions import (
    ClosureWrench,
    JointWrench,
    MountWrench,
    closure_wrenches,
    joint_reactions,
)

CLOSURE_TOLERANCE = 1e-9
"""Largest accepted closure residual [m, rad] of a prescribed configuration, and (per second,
per second²) of its velocity and acceleration rows: assembly closes loops to ~1e-13; 1e-9 leaves
room for motion data rounded to 9 digits."""

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

CONVENTION = (
    "statically indeterminate closure forces: minimum ‖K^(-1/2) λ‖ (K the per-row stiffness, "
    "default 1: minimum norm in SI units)"
)


@dataclass(frozen=True)
class ChainLoads:
    """Inverse dynamics of a closed chain along N samples.

    Attributes:
        actuators: Actuated joint name → its generalized force [N or N·m], (N,).
        closure_forces: λ, one column per closure row (:meth:`ClosedChain.row_labels`), (N, nc).
        closures: Closure label → :class:`ClosureWrench`.
        joints: Joint name → :class:`JointWrench` (every joint of the tree but a free-flyer,
            which transmits no wrench).
        indeterminate: Labels of the closure rows whose forces are statically indeterminate
            (reported with the convention :data:`CONVENTION`).
        convention: How indeterminate forces were chosen.
        accelerations: q̈ (N, nv), the accelerations the loads belong to: the prescribed ones
            plus the idle motions' (:mod:`~feeder.chain.dynamics.idle`; equal to the prescribed
            ones when there is none).
        idle_motions: Number of idle motions (free with every actuated joint locked).
        elements: Force element name → its force (N,): a spring's or cylinder's tension [N]
            (positive pulls its frames together), a joint spring's resistance [N·m or N].
        mount: The wrench the mount exerts on the mechanism (:class:`MountWrench`).
        base: The base's motion at the samples, or None for a base at rest.
    """

    actuators: dict[str, np.ndarray]
    closure_forces: np.ndarray
    closures: dict[str, ClosureWrench]
    joints: dict[str, JointWrench]
    indeterminate: tuple[str, ...]
    convention: str
    accelerations: np.ndarray
    idle_motions: int
    elements: dict[str, np.ndarray]
    mount: MountWrench
    base: BaseState | None = None


class ChainDynamics:
    """What the inverse dynamics of one chain needs that does not change along a motion.

    Args:
        chain: The closed chain (its model's gravity is used); a tree of any joints of
            :mod:`~feeder.chain.kinematics.joints`.
        actuated: Names of the actuated joints (one coordinate each: revolute, continuous,
            prismatic).
        stiffness: Optional closure label → per-row stiffness (rows of that closure), for the
            split of statically indeterminate forces; default 1 everywhere.
        elements: Force elements acting on the chain (:mod:`~feeder.chain.model.forces`).
        base: The base's prescribed motion (:class:`~feeder.chain.model.base.BaseMotion`),
            None for a base at rest.

    Raises:
        InputError: A joint type the dynamics do not handle (helical, ellipsoid, composite,
            mimic), an unknown or multi-coordinate actuated joint, a name given twice, a bad
            stiffness, a force element on an unknown frame or joint, a moving base without
            gravity or with a forward axis that is not horizontal.
    """

    def __init__(
        self,
        chain: ClosedChain,
        actuated: Sequence[str],
        stiffness: Mapping[str, Sequence[float]] | None = None,
        elements: Sequence[ForceElement] = (),
        base: BaseMotion | None = None,
    ):
        if not isinstance(chain, ClosedChain):
            raise InputError(
                f"chain must be a ClosedChain (the model and its closures), got {chain!r}"
            )
        if stiffness is not None and not isinstance(stiffness, Mapping):
            raise InputError(
                "stiffness must map closure labels to their rows' stiffness (a dict), got "
                f"{stiffness!r}"
            )
        if base is not None and not isinstance(base, BaseMotion):
            raise InputError(f"base must be a BaseMotion, got {base!r}")
        if base is not None and base.profiles:
            base.vehicle_axes(chain.model.gravity.linear)
        self.base = base if base is not None and base.profiles else None
        for j in range(1, chain.model.njoints):
            kind_of(chain.model.joints[j])
        self.columns = chain.coordinate_columns(actuated, "actuated").tolist()
        self.chain = chain
        self.actuated = tuple(actuated)
        weights = np.ones(chain.nc)
        labels = [closure.label for closure in chain.closures]
        for label, values in (stiffness or {}).items():
            if label not in labels:
                raise InputError(
                    f"stiffness given for unknown closure {label!r}; closures: {labels}"
                )
            rows = chain.row_slices[labels.index(label)]
            values = check_finite(f"stiffness of {label!r}", values)
            if values.shape != (rows.stop - rows.start,) or np.any(values <= 0.0):
                raise InputError(
                    f"stiffness of {label!r} must be {rows.stop - rows.start} positive numbers"
                )
            weights[rows] = values
        self.row_scale = np.sqrt(weights)
        self.data = chain.model.createData()
        self.elements = BoundElements(chain, elements)

    def idle_count(self, q: np.ndarray) -> int:
        """Number of idle motions at the closed pose ``q`` with the actuated joints locked
        (:meth:`~feeder.chain.assembly.partition.Partition.idle_motions`; 0 when the locked
        mechanism can still move an origin: then it is under-actuated, which the load solve
        reports)."""
        try:
            return Partition(self.chain, self.actuated).idle_motions(q).shape[0]
        except SingularPoseError:
            return 0


def check_dynamics(dyn: ChainDynamics) -> None:
    """Refuse a ``dyn`` that is not a :class:`ChainDynamics`."""
    if not isinstance(dyn, ChainDynamics):
        raise InputError(
            "dyn must be a ChainDynamics (the chain with its actuated joints and force "
            f"elements), got {dyn!r}"
        )


def check_motion(
    dyn: ChainDynamics, q: np.ndarray, v: np.ndarray, a: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, TreeMotion, ClosureKinematics]:
    """q (N, nq), v, a (N, nv) as float arrays if they are a closed-chain motion, else raise;
    also returns the tree's batched motion and the closure rows along it.

    Raises:
        InputError: NaN/inf, shapes, velocities or accelerations that open the loops.
        UnreachablePoseError: A configuration that does not close the loops.
    """
    check_dynamics(dyn)
    model = dyn.chain.model
    q = check_samples("q", q, model.nq)
    v = check_samples("v", v, model.nv)
    a = check_samples("a", a, model.nv)
    if not q.shape[0] == v.shape[0] == a.shape[0]:
        raise InputError(f"q, v, a must have N samples each, got {q.shape}, {v.shape}, {a.shape}")
    motion = tree_motion(model, q, v, a)
    rows = closure_kinematics(dyn.chain, motion, v)
    for label, alignment in rows.hinge_alignment.items():
        if np.any(alignment < 0.0):
            k = int(np.argmax(alignment < 0.0))
            raise UnreachablePoseError(
                f"sample {k}: the revolute cut {label!r} is assembled with its two hinge axes "
                "opposite (upside down): not a closed configuration of the mechanism"
            )
    scale = np.maximum.reduce(
        [np.ones(v.shape[0]), np.abs(v).max(axis=1) ** 2, np.abs(a).max(axis=1)]
    )
    for what, values, limit, error in (
        ("configuration", rows.residual, np.ones_like(scale), UnreachablePoseError),
        ("velocities", rows.rate, np.sqrt(scale), InputError),
        ("accelerations", rows.acceleration, scale, InputError),
    ):
        worst = np.abs(values).max(axis=1, initial=0.0) / limit
        k = int(np.argmax(worst))
        if worst[k] > CLOSURE_TOLERANCE:
            if error is UnreachablePoseError:
                raise UnreachablePoseError(
                    f"sample {k} does not close the loops: residual {worst[k]:.3e} > "
                    f"{CLOSURE_TOLERANCE:g}"
                )
            raise InputError(
                f"the {what} of sample {k} open the loops ({worst[k]:.3e}): not a closed-chain "
                "motion (Partition.velocity / acceleration, feeder.chain.track give one)"
            )
    return q, v, a, motion, rows


def _external_terms(
    chain: ClosedChain, n: int, external: Mapping[str, np.ndarray]
) -> list[tuple[int, np.ndarray]]:
    """The checked external wrenches: (frame id, world wrench (N, 6) about the frame's origin)."""
    terms = []
    for name, wrench in external.items():
        frame = chain.frame_id(name)
        values = check_finite(f"external wrench on {name!r}", wrench)
        if values.shape == (6,):
            values = np.tile(values, (n, 1))
        if values.shape != (n, 6):
            raise InputError(
                f"external wrench on {name!r} must be (6,) or ({n}, 6), got {values.shape}"
            )
        terms.append((frame, values))
    return terms


def inverse_dynamics(
    dyn: ChainDynamics,
    q: np.ndarray,
    v: np.ndarray,
    a: np.ndarray,
    external: Mapping[str, np.ndarray] | None = None,
    t: np.ndarray | None = None,
) -> ChainLoads:
    """Actuator loads, closure forces and every joint's reaction for a closed-chain motion.

    Args:
        dyn: The chain's dynamics (:class:`ChainDynamics`).
        q, v, a: Configurations (N, nq), velocities and accelerations (N, nv) of a closed-chain
            motion (checked: :func:`check_motion`).
        external: Optional external wrenches by frame name: world [force (3) N, moment (3) N·m
            about the frame's origin], (N, 6) or (6,) (constant).
        t: The samples' times [s], (N,): needed when a force element or the base's motion
            varies in time.

    Raises:
        InputError: Bad arrays, a motion that opens the loops, or one the actuated joints cannot
            produce.
        UnreachablePoseError: A configuration that does not close the loops.
        SingularPoseError: Actuator loads not determined by the equations (a singular
            actuation).
    """
    q, v, a, motion, rows = check_motion(dyn, q, v, a)
    terms = _external_terms(dyn.chain, q.shape[0], external or {})
    forces = {}
    t = _times(dyn, t, q.shape[0])
    if dyn.elements:
        element_terms, forces = dyn.elements.wrenches(motion, q, v, t)
        terms = terms + element_terms
    base = None
    if dyn.base is not None:
        base = dyn.base.state(t, dyn.chain.model.gravity.linear)
        motion = on_base(motion, base)
    count = dyn.idle_count(q[0])
    if count:
        basis = idle_basis(rows, dyn.columns, count)
        a = a + idle_accelerations(dyn.chain.model, q, motion, basis, terms)
        motion = tree_motion(dyn.chain.model, q, v, a)
        if base is not None:
            motion = on_base(motion, base)
    tau, lam, indeterminate = solve_loads(dyn, motion, rows, terms)
    closures, closure_terms = closure_wrenches(dyn.chain, rows, lam)
    joints, mount = joint_reactions(
        dyn.chain, motion, closure_terms + terms, None if base is None else base.rotation
    )
    return ChainLoads(
        actuators={name: tau[:, i] for i, name in enumerate(dyn.actuated)},
        closure_forces=lam,
        closures=closures,
        joints=joints,
        indeterminate=indeterminate,
        convention=CONVENTION,
        accelerations=a,
        idle_motions=count,
        elements=forces,
        mount=mount,
        base=base,
    )


def _times(dyn: ChainDynamics, t: np.ndarray | None, n: int) -> np.ndarray:
    """The samples' times (N,) [s], checked; zeros when nothing varies in time."""
    if t is None:
        if dyn.elements.timed:
            raise InputError("a force element varies in time: give the samples' times t [s]")
        if dyn.base is not None and dyn.base.timed:
            raise InputError("the base moves: give the samples' times t [s]")
        return np.zeros(n)
    t = check_finite("t", t)
    if t.shape != (n,):
        raise InputError(f"t must have one time per sample, shape ({n},), got {t.shape}")
    dyn.elements.check_covers(float(t.min()), float(t.max()))
    return t


def solve_loads(
    dyn: ChainDynamics,
    motion: TreeMotion,
    rows: ClosureKinematics,
    external: list[tuple[int, np.ndarray]] = (),
) -> tuple[np.ndarray, np.ndarray, tuple[str, ...]]:
    """The actuator loads τ (N, n_act) and closure forces λ (N, nc) of a checked closed-chain
    motion (module docstring), and the labels of the indeterminate closure rows."""
    model = dyn.chain.model
    force, moment = joint_wrenches(model, motion, external)
    tree = generalized_forces(model, motion, force, moment)  # M q̈ + b − Σ J_eᵀ w_e
    n_act = len(dyn.columns)
    system = load_equations(dyn, rows.jacobian)
    solution, indeterminate = _solve(system, tree, n_act, dyn.chain.row_labels())
    return solution[:, :n_act], solution[:, n_act:] * dyn.row_scale, indeterminate


def load_equations(dyn: ChainDynamics, jacobian: np.ndarray) -> np.ndarray:
    """The matrix [Sᵀ Jᵀ] of the loads' equations (module docstring; SI units, the closure
    columns scaled by the square root of their stiffness), (N, nv, n_act + nc), from the closure
    rows' Jacobians J (N, nc, nv)."""
    n, nc, nv = jacobian.shape
    n_act = len(dyn.columns)
    system = np.zeros((n, nv, n_act + nc))
    system[:, dyn.columns, np.arange(n_act)] = 1.0
    system[:, :, n_act:] = np.swapaxes(jacobian, 1, 2) * dyn.row_scale
    return system


def load_rank(dyn: ChainDynamics, q: np.ndarray) -> int:
    """The rank the loads' equations have at a closed pose q (nq,) away from singular poses:
    the actuated joints' count plus the closure rows' rank there, at most nv (as
    :func:`inverse_dynamics` expects of every sample)."""
    rank = np.linalg.matrix_rank(dyn.chain.jacobian(q)) if dyn.chain.nc else 0
    return min(dyn.chain.model.nv, len(dyn.columns) + int(rank))


def load_gain(dyn: ChainDynamics, q: np.ndarray, rank: int) -> float:
    """Condition number of the loads' equations at the pose q (nq,): the largest singular value
    of :func:`load_equations` over its ``rank``-th (:func:`load_rank`; infinite where the rank
    has dropped, 1 with no unknown). :func:`inverse_dynamics` refuses a sample above
    :data:`MAX_FORCE_GAIN`."""
    if rank == 0:
        return 1.0
    system = load_equations(dyn, dyn.chain.jacobian(q)[None])[0]
    s = np.linalg.svd(system, compute_uv=False)
    return float(s[0] / s[rank - 1]) if s[rank - 1] > RANK_TOLERANCE * s[0] else math.inf


def _solve(
    system: np.ndarray, rhs: np.ndarray, n_act: int, labels: list[str]
) -> tuple[np.ndarray, tuple[str, ...]]:
    """Minimum-norm solutions of system[k] x = rhs[k] (n, nv, nx), after the checks of the module
    docstring; returns x (n, nx) and the labels of indeterminate closure rows.

    Where a sample's system has full row rank and a small condition number (every sample of a
    well-actuated motion), x = A⁺ b is its minimum-norm solution, from one small inverse
    (:func:`_shortcut`); the other samples, and a subsample for the structural checks (the null
    space of the equations), go through the singular value decomposition."""
    n = system.shape[0]
    if system.shape[2] == 0:  # an open tree with nothing actuated: the reactions alone
        return np.zeros((n, 0)), ()
    fast, inverse = _shortcut(system)
    solution = np.empty((n, system.shape[2]))
    if np.any(fast):
        solution[fast] = np.einsum("nij,nj->ni", inverse[fast], rhs[fast])
    stride = max(1, n // RANK_SUBSAMPLE)
    checked = np.zeros(n, dtype=bool)
    checked[::stride] = True
    detailed = ~fast | checked
    structural = int(np.linalg.matrix_rank(system[checked][:, :, n_act:]).max(initial=0))
    expected = min(system.shape[1], n_act + structural)
    indices = np.flatnonzero(detailed)
    exact, null = _solve_svd(system[detailed], rhs[detailed], n_act, expected, indices)
    solution[indices[~fast[detailed]]] = exact[~fast[detailed]]
    indeterminate = tuple(label for label, flag in zip(labels, null[n_act:], strict=True) if flag)
    return solution, indeterminate


def _shortcut(system: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Which samples of system (n, nv, nx) are certainly well-conditioned (bool (n,)), and for
    them the right inverse A⁺ (n, nx, nv): A⁻¹ when square (round-off cond(A) ε), else
    Aᵀ (A Aᵀ)⁻¹ (the normal equations square the condition number). The test needs no
    decomposition: cond(B) ≤ ‖B‖_F ‖B⁻¹‖_F for B = A, or B = A Aᵀ whose condition number is
    cond(A)². A near-singular B gives a computed inverse of huge norm (backward stability: it
    is the inverse of a matrix within round-off of B), so the bound cannot pass by accident; a
    doubtful sample takes the singular value decomposition, which also refuses a singular one."""
    square = system.shape[1] == system.shape[2]
    matrix = system if square else system @ np.swapaxes(system, 1, 2)
    try:
        inverse = np.linalg.inv(matrix)
    except np.linalg.LinAlgError:  # some sample is exactly singular: the others one by one
        inverse = np.array([_inverse_or_nan(m) for m in matrix])
    with np.errstate(invalid="ignore", over="ignore"):
        bound = np.linalg.norm(matrix, axis=(1, 2)) * np.linalg.norm(inverse, axis=(1, 2))
    fast = np.isfinite(bound) & (bound < (MAX_FORCE_GAIN if square else NORMAL_EQUATIONS**2))
    if not square:
        inverse = np.swapaxes(system, 1, 2) @ inverse
    return fast, inverse


def _inverse_or_nan(matrix: np.ndarray) -> np.ndarray:
    try:
        return np.linalg.inv(matrix)
    except np.linalg.LinAlgError:
        return np.full_like(matrix, np.nan)


def _solve_svd(
    system: np.ndarray, rhs: np.ndarray, n_act: int, expected: int, samples: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The singular-value path of :func:`_solve` on some samples (their indices in the motion:
    ``samples``, for the messages): the checks (singular actuation, consistency, determined
    actuator loads), the minimum-norm solutions and which unknowns a null-space direction
    involves (nx,) bool. ``expected``: the rank the actuators and the closure rows can give."""
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
    misfit = np.abs(np.einsum("nij,nj->ni", system, solution) - rhs).max(axis=1)
    size = np.maximum(
        np.abs(rhs).max(axis=1), np.abs(system).max(axis=(1, 2)) * np.abs(solution).max(axis=1)
    )
    worst = int(np.argmax(misfit / np.maximum(size, 1e-300)))
    if misfit[worst] > CONSISTENCY * max(size[worst], 1e-300):
        raise InputError(
            f"the actuated joints cannot produce the motion: the equations of motion leave a "
            f"residual of {misfit[worst]:.3e} (choose other actuated joints)"
        )
    null = np.zeros(system.shape[2], dtype=bool)
    for r in np.unique(rank):  # samples of equal rank share the null-space dimension
        basis = vt[rank == r, r:, :]  # (samples, dim, nx)
        if basis.size and np.abs(basis[:, :, :n_act]).max() > NULL_SPACE:
            raise SingularPoseError(
                "the actuator loads are not determined: the actuated joints and the closures "
                "can balance each other without load (a singular or redundant actuation)"
            )
        if basis.size:
            null |= np.abs(basis).max(axis=(0, 1)) > NULL_SPACE
    return solution, null
