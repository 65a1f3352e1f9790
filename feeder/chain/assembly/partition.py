"""Assembly of a closed chain: the dependent coordinates from the independent ones.

Position level: damped Gauss–Newton (Levenberg–Marquardt, damping μ = ‖r‖², which keeps Newton's
quadratic convergence near a solution and shortens the steps far from it) on the closure residual
r(q) = 0 over the dependent coordinates, the independent ones held fixed; revolute angles are
wrapped into their joint's range after convergence. A branch is chosen by the guess or by a
condition the caller gives (:meth:`Partition.assemble`), and kept along a trajectory by
continuation (:meth:`Partition.track`). Velocity and acceleration level: the linear systems
J q̇ = 0 and J q̈ + J̇ q̇ = 0 solved for the dependent components. All solves are least squares,
so redundant rows (a planar loop) do no harm.

The rank test runs at the solution only: the dependent Jacobian must determine the dependent
velocities (full column rank) and let the independent ones move freely (same rank as the whole
Jacobian). Near a singular pose (a toggle, a dead centre) the dependent velocities grow without
bound for a bounded independent motion; the *velocity gain* ‖J_dep⁺ J_ind‖₂ measures it, and a
pose whose gain exceeds ``max_gain`` (default :data:`MAX_GAIN`) is refused with
:class:`~feeder.exceptions.SingularPoseError`.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
import pinocchio as pin

from ...exceptions import InputError, SingularPoseError, UnreachablePoseError
from ...validation import check_number, check_samples, check_vector
from ..model.closure import ClosedChain

POSITION_TOLERANCE = 1e-13
"""Closure residual [m] at which Newton stops: a few ulps of the mechanism's size (~1 m)."""

RANK_TOLERANCE = 1e-9
"""Singular values below this fraction of the largest count as zero in the rank tests: far above
round-off (1e-16) and far below any physical ratio of a mechanism's lever arms."""

MAX_GAIN = 1e3
"""Largest accepted velocity gain ‖J_dep⁺ J_ind‖₂ (dependent speed per unit independent speed,
SI units): a coordinate that must move a thousand times faster than the driving ones is at a
toggle for every practical purpose (the device's 5° transmission limit is a gain of ~3)."""

CONTINUATION_STEP = 0.5
"""Largest accepted Newton correction after the tangent predictor, as a fraction of the step of
the independent coordinates: a first-order predictor errs by O(step²), so a correction this large
means a step too coarse for the curvature, where the next solution may lie on another branch."""

MAX_ITERATIONS = 100
"""Newton iterations before assembly gives up."""

RESTARTS = 50
"""Random restarts (seeded) that :meth:`Partition.assemble` tries when Newton from the guess
stops at a local minimum of the residual, or its solution misses the requested branch."""


class Partition:
    """Split of a chain's velocity indices into independent and dependent ones.

    Args:
        chain: The closed chain.
        independent: Names of the joints whose coordinates are given.
        max_gain: Largest accepted velocity gain (:data:`MAX_GAIN`).

    Raises:
        InputError: An unknown joint name, or a name given twice.
    """

    def __init__(self, chain: ClosedChain, independent: Sequence[str], max_gain: float = MAX_GAIN):
        if isinstance(independent, str) or not isinstance(independent, Sequence):
            raise InputError(f"independent joints must be a list of names, got {independent!r}")
        if len(set(independent)) != len(independent):
            raise InputError(f"independent joints must be distinct, got {list(independent)}")
        self.chain = chain
        self.independent_joints = tuple(independent)
        self.max_gain = check_number("max_gain", max_gain)
        if not self.max_gain > 1.0:
            raise InputError(f"max_gain must be a number above 1, got {max_gain!r}")
        mask = np.zeros(chain.model.nv, dtype=bool)
        for name in self.independent_joints:
            mask[chain.joint_slice(name)] = True
        self.independent = np.flatnonzero(mask)
        self.dependent = np.flatnonzero(~mask)
        self._prismatic = np.array(
            [
                chain.model.joints[j].idx_v
                for j in range(1, chain.model.njoints)
                if chain.model.joints[j].shortname().startswith("JointModelP")
            ],
            dtype=int,
        )
        self._angles = [
            i
            for i in _revolute_angles(chain.model)
            if _velocity_index(chain.model, i) in self.dependent
        ]

    # -- checks -----------------------------------------------------------------------------

    def _check_independent(self, name: str, value: np.ndarray) -> np.ndarray:
        return check_vector(name, value, self.independent.size)

    def check_closed(self, q: np.ndarray, tolerance: float = 1e-9) -> np.ndarray:
        """``q`` as an array if it closes every loop to ``tolerance`` [m, rad], else raise.

        Raises:
            InputError: NaN/inf or misshaped q.
            UnreachablePoseError: q does not close the loops.
        """
        q = self.chain.check_q(q)
        gap = float(np.abs(self.chain.residual(q)).max(initial=0.0))
        if gap > tolerance:
            raise UnreachablePoseError(
                f"q = {np.round(q, 6)} does not close the loops: residual {gap:.3e} > "
                f"{tolerance:g} (assemble it first)"
            )
        return q

    def gain(self, q: np.ndarray) -> float:
        """Velocity gain ‖J_dep⁺ J_ind‖₂ at ``q`` (∞ where the dependent coordinates are not
        determined): the largest dependent speed per unit independent speed, prismatic speeds
        counted in units of the mechanism's size (:meth:`length_scale`)."""
        q = self.chain.check_q(q)
        return self._gain(q, self.chain.jacobian(q))

    def length_scale(self, q: np.ndarray) -> float:
        """The mechanism's size [m] at ``q``: the largest distance of a joint from the base
        (≥ 1 mm). Prismatic speeds divided by it compare with angular ones."""
        model, data = self.chain.model, self.chain.data
        pin.forwardKinematics(model, data, q)
        reach = max(
            (np.linalg.norm(data.oMi[j].translation) for j in range(1, model.njoints)), default=0.0
        )
        return max(float(reach), 1e-3)

    def _gain(self, q: np.ndarray, jac: np.ndarray) -> float:
        if self._prismatic.size:
            jac = jac.copy()
            jac[:, self._prismatic] *= self.length_scale(q)
        return velocity_gain(*self._split(jac))

    def _split(self, jac: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return jac[:, self.dependent], jac[:, self.independent]

    def _check_pose(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Closure Jacobian (nc, nv) and its dependent columns, after the rank and gain tests
        of the module docstring."""
        jac = self.chain.jacobian(q)
        jac_dep, jac_ind = self._split(jac)
        scale = float(np.abs(jac).max(initial=0.0)) or 1.0
        rank_full = np.linalg.matrix_rank(jac, tol=RANK_TOLERANCE * scale) if jac.size else 0
        rank_dep = (
            np.linalg.matrix_rank(jac_dep, tol=RANK_TOLERANCE * scale) if jac_dep.size else 0
        )
        if rank_dep < self.dependent.size:
            raise SingularPoseError(
                f"the closure does not determine the {self.dependent.size} dependent "
                f"coordinates at q = {np.round(q, 6)}: dependent Jacobian rank {rank_dep} "
                f"(too few independent joints {list(self.independent_joints)}, or a singular pose)"
            )
        if rank_dep < rank_full:
            raise SingularPoseError(
                f"the dependent coordinates cannot follow the independent ones at "
                f"q = {np.round(q, 6)}: closure Jacobian rank {rank_full}, dependent part rank "
                f"{rank_dep} (too many independent joints, or a singular pose)"
            )
        gain = self._gain(q, jac)
        if gain > self.max_gain:
            raise SingularPoseError(
                f"q = {np.round(q, 6)} is near a singular pose (toggle, dead centre): a unit "
                f"speed of {list(self.independent_joints)} needs dependent speeds up to "
                f"{gain:.3g} (limit {self.max_gain:g}); the loads grow without bound there"
            )
        return jac, jac_dep

    # -- position level ---------------------------------------------------------------------

    def _newton(self, q: np.ndarray, max_iterations: int) -> tuple[np.ndarray, float]:
        """Levenberg–Marquardt on the dependent coordinates from ``q``; returns (q, ‖r‖)."""
        model, chain = self.chain.model, self.chain
        residual = chain.residual(q)
        norm = float(np.linalg.norm(residual))
        for _ in range(max_iterations):
            if norm <= POSITION_TOLERANCE:
                break
            jac = chain.residual_jacobian(q)[:, self.dependent]
            damping = norm**2 * np.eye(self.dependent.size)  # [m²]: Yamashita–Fukushima
            step = np.zeros(model.nv)
            step[self.dependent] = -np.linalg.solve(jac.T @ jac + damping, jac.T @ residual)
            trial = pin.integrate(model, q, step)
            trial_residual = chain.residual(trial)
            trial_norm = float(np.linalg.norm(trial_residual))
            halvings = 0
            while trial_norm > norm and halvings < 30:  # backtrack until the residual drops
                step *= 0.5
                trial = pin.integrate(model, q, step)
                trial_residual = chain.residual(trial)
                trial_norm = float(np.linalg.norm(trial_residual))
                halvings += 1
            if trial_norm > norm:
                break
            q, residual, norm = trial, trial_residual, trial_norm
        return q, norm

    def _wrap(self, q: np.ndarray) -> np.ndarray:
        """Dependent revolute angles outside their joint's range moved by the multiple of 2π
        that brings them inside (a range of [0, 0] means "not set": angles go to (−π, π])."""
        model = self.chain.model
        q = q.copy()
        for i in self._angles:
            low, high = model.lowerPositionLimit[i], model.upperPositionLimit[i]
            if low == high == 0.0 or not (np.isfinite(low) and np.isfinite(high)):
                q[i] = np.pi - np.mod(np.pi - q[i], 2.0 * np.pi)
            elif not low <= q[i] <= high:
                middle = 0.5 * (low + high)
                shifted = q[i] - 2.0 * np.pi * np.round((q[i] - middle) / (2.0 * np.pi))
                if low - 1e-12 <= shifted <= high + 1e-12:
                    q[i] = shifted
        return q

    def _check_limits(self, q: np.ndarray) -> None:
        model = self.chain.model
        low, high = model.lowerPositionLimit, model.upperPositionLimit
        unset = (low == 0.0) & (high == 0.0)
        outside = ~unset & ((q < low - 1e-12) | (q > high + 1e-12))
        if np.any(outside):
            i = int(np.flatnonzero(outside)[0])
            joint = next(
                model.names[j]
                for j in range(1, model.njoints)
                if model.joints[j].idx_q <= i < model.joints[j].idx_q + model.joints[j].nq
            )
            raise UnreachablePoseError(
                f"closing the loop needs {joint} = {q[i]:.6g}, outside its limits "
                f"[{low[i]:.6g}, {high[i]:.6g}]"
            )

    def assemble(
        self,
        q_guess: np.ndarray,
        branch: Callable[[np.ndarray], bool] | None = None,
        max_iterations: int = MAX_ITERATIONS,
    ) -> np.ndarray:
        """Closed configuration with the independent coordinates of ``q_guess``.

        Args:
            q_guess: Configuration (nq,) whose independent coordinates are kept; its dependent
                ones are the starting guess, which picks the assembly branch.
            branch: Optional condition on the solution (e.g. ``lambda q: q[2] > 0``, "elbow
                up"). If Newton from the guess does not converge, or its solution fails the
                condition, up to :data:`RESTARTS` seeded random guesses of the dependent
                coordinates are tried.
            max_iterations: Newton iterations per attempt.

        Returns:
            q (nq,) with ‖residual‖ ≤ :data:`POSITION_TOLERANCE`, revolute angles wrapped into
            their ranges.

        Raises:
            InputError: NaN/inf or misshaped guess.
            UnreachablePoseError: No convergence, no solution on the branch, or a solution
                outside the joint limits.
            SingularPoseError: The solution is singular or near it (module docstring).
        """
        q_guess = self.chain.check_q(q_guess)
        rng = np.random.default_rng(0)
        best: tuple[float, np.ndarray] | None = None
        missed_branch = False
        for attempt in range(1 + RESTARTS):
            start = q_guess if attempt == 0 else self._random_guess(q_guess, rng)
            q, norm = self._newton(start.copy(), max_iterations)
            if best is None or norm < best[0]:
                best = (norm, q)
            if norm > POSITION_TOLERANCE or self.chain.reversed_hinges():
                continue  # not closed, or a hinge assembled upside down
            q = self._wrap(q)
            if branch is not None and not branch(q):
                missed_branch = True
                continue
            self._check_limits(q)
            self._check_pose(q)
            return q
        if missed_branch:
            raise UnreachablePoseError(
                f"no assembly on the requested branch found in {RESTARTS + 1} attempts"
            )
        norm, q = best
        gain = self._gain(q, self.chain.jacobian(q))
        if gain > self.max_gain:
            raise SingularPoseError(
                f"the loop closes only to {norm:.3e} near q = {np.round(q, 6)}, at a singular "
                f"pose (toggle, dead centre: velocity gain {gain:.3g} > {self.max_gain:g}): the "
                "given independent coordinates are at or beyond the end of the mechanism's travel"
            )
        raise UnreachablePoseError(
            f"the loop does not close at the given independent coordinates (best residual "
            f"{norm:.3e} after {max_iterations} damped Newton steps from the guess and from "
            f"{RESTARTS} random guesses)"
        )

    def _random_guess(self, q: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """``q`` with its dependent coordinates replaced by random values (±π, or within the
        joint's range where it is set)."""
        model = self.chain.model
        random = pin.integrate(model, pin.neutral(model), rng.uniform(-np.pi, np.pi, model.nv))
        guess = q.copy()
        for j in range(1, model.njoints):
            joint = model.joints[j]
            if joint.idx_v in self.dependent and joint.nq == 1:
                low, high = (
                    model.lowerPositionLimit[joint.idx_q],
                    model.upperPositionLimit[joint.idx_q],
                )
                if low == high or not (np.isfinite(low) and np.isfinite(high)):
                    low, high = -np.pi, np.pi
                guess[joint.idx_q] = rng.uniform(low, high)
            elif joint.idx_v in self.dependent:
                guess[joint.idx_q : joint.idx_q + joint.nq] = random[
                    joint.idx_q : joint.idx_q + joint.nq
                ]
        return guess

    # -- velocity and acceleration level ----------------------------------------------------

    def velocity(self, q: np.ndarray, v_independent: np.ndarray) -> np.ndarray:
        """Velocity (nv,) with the given independent components and J q̇ = 0.

        Args:
            q: Closed configuration (nq,).
            v_independent: Velocities of the independent coordinates, in the order of
                ``self.independent``.

        Raises:
            InputError: NaN/inf or misshaped inputs.
            UnreachablePoseError: q does not close the loops.
            SingularPoseError: A singular pose or one near it.
        """
        q = self.check_closed(q)
        v_independent = self._check_independent("v_independent", v_independent)
        return self._velocity(*self._check_pose(q), v_independent)

    def _velocity(self, jac: np.ndarray, jac_dep: np.ndarray, v_independent: np.ndarray):
        v = np.zeros(self.chain.model.nv)
        v[self.independent] = v_independent
        v[self.dependent] = -np.linalg.lstsq(jac_dep, jac @ v, rcond=None)[0]
        return v

    def acceleration(self, q: np.ndarray, v: np.ndarray, a_independent: np.ndarray) -> np.ndarray:
        """Acceleration (nv,) with the given independent components and J q̈ + J̇ q̇ = 0.

        Raises:
            InputError: NaN/inf or misshaped inputs, or velocities that open the loops.
            UnreachablePoseError: q does not close the loops.
            SingularPoseError: A singular pose or one near it.
        """
        q = self.check_closed(q)
        v = self.chain.check_v("v", v)
        a_independent = self._check_independent("a_independent", a_independent)
        jac, jac_dep = self._check_pose(q)
        gap_rate = float(np.abs(jac @ v).max(initial=0.0))
        if gap_rate > 1e-9 * max(1.0, float(np.abs(v).max())):
            raise InputError(
                f"v opens the loops at {gap_rate:.3e} per second: it is not a closed-chain "
                "velocity (use Partition.velocity)"
            )
        return self._acceleration(q, v, jac, jac_dep, a_independent)

    def _acceleration(self, q, v, jac, jac_dep, a_independent) -> np.ndarray:
        a = np.zeros(self.chain.model.nv)
        a[self.independent] = a_independent
        rhs = jac @ a + self.chain.bias(q, v)
        a[self.dependent] = -np.linalg.lstsq(jac_dep, rhs, rcond=None)[0]
        return a

    # -- trajectories -----------------------------------------------------------------------

    def track(
        self,
        q_start: np.ndarray,
        x: np.ndarray,
        dx: np.ndarray | None = None,
        ddx: np.ndarray | None = None,
        branch: Callable[[np.ndarray], bool] | None = None,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Follow a trajectory of the independent coordinates on one assembly branch.

        Each sample starts Newton from the previous solution moved along the closure's tangent
        (a first-order predictor), which keeps the branch as long as the samples are fine
        compared with the distance to a singular pose; a pose near one is refused.

        Args:
            q_start: Guess (nq,) of the first sample's configuration (picks the branch).
            x: Independent coordinates, (N, n_independent).
            dx, ddx: Their rates and accelerations (N, n_independent); zero if omitted.
            branch: Optional condition on the first sample's solution (:meth:`assemble`).

        Returns:
            q (N, nq), v (N, nv), a (N, nv) and the velocity gain of every sample (N,).
        """
        n_ind = self.independent.size
        x = check_samples("x", x, n_ind)
        dx = np.zeros_like(x) if dx is None else check_samples("dx", dx, n_ind)
        ddx = np.zeros_like(x) if ddx is None else check_samples("ddx", ddx, n_ind)
        if not x.shape == dx.shape == ddx.shape:
            raise InputError(
                f"x, dx, ddx must have one shape, got {x.shape}, {dx.shape}, {ddx.shape}"
            )
        model = self.chain.model
        n = x.shape[0]
        qs, vs, accs = np.empty((n, model.nq)), np.empty((n, model.nv)), np.empty((n, model.nv))
        gains = np.empty(n)
        guess = self._with_independent(self.chain.check_q(q_start), x[0])
        for i in range(n):
            if i == 0:
                q = self.assemble(guess, branch)
            else:
                q = self._continue(qs[i - 1], x[i] - x[i - 1], i)
            jac = self.chain.jacobian(q)
            jac_dep = jac[:, self.dependent]
            qs[i] = q
            vs[i] = self._velocity(jac, jac_dep, dx[i])
            accs[i] = self._acceleration(q, vs[i], jac, jac_dep, ddx[i])
            gains[i] = self._gain(q, jac)
        return qs, vs, accs, gains

    def _continue(self, previous: np.ndarray, step: np.ndarray, sample: int) -> np.ndarray:
        """The next sample's configuration: Newton from the tangent predictor, no restarts,
        the correction small next to the step (else a branch switch is possible: refused)."""
        guess = self._predict(previous, step)
        q, norm = self._newton(guess.copy(), MAX_ITERATIONS)
        correction = float(np.abs(pin.difference(self.chain.model, guess, q)).max(initial=0.0))
        size = float(np.abs(step).max(initial=0.0))
        if norm > POSITION_TOLERANCE or self.chain.reversed_hinges():
            raise UnreachablePoseError(
                f"sample {sample}: the loop does not close next to the previous sample (residual "
                f"{norm:.3e}): the end of the mechanism's travel, or samples too far apart"
            )
        if correction > CONTINUATION_STEP * max(size, 1e-12) and correction > 1e-9:
            raise UnreachablePoseError(
                f"sample {sample}: a step of {size:.3g} of the independent coordinates moved the "
                f"dependent ones {correction:.3g} off the tangent: the samples are too coarse to "
                "stay on one assembly branch (sample more finely)"
            )
        q = self._wrap(q)
        self._check_limits(q)
        self._check_pose(q)
        return q

    def _with_independent(self, q: np.ndarray, x: np.ndarray) -> np.ndarray:
        """``q`` with the independent coordinates set to ``x`` (one-dof joints: nq = nv)."""
        q = q.copy()
        model = self.chain.model
        for value, index in zip(x, self.independent, strict=True):
            joint = next(
                model.joints[j]
                for j in range(1, model.njoints)
                if model.joints[j].idx_v <= index < model.joints[j].idx_v + model.joints[j].nv
            )
            if joint.nq != joint.nv:
                raise InputError("independent joints must have nq = nv (revolute, prismatic)")
            q[joint.idx_q + index - joint.idx_v] = value
        return q

    def _predict(self, q: np.ndarray, step: np.ndarray) -> np.ndarray:
        """``q`` moved by ``step`` of the independent coordinates along the closure's tangent."""
        jac = self.chain.jacobian(q)
        jac_dep, jac_ind = self._split(jac)
        delta = np.zeros(self.chain.model.nv)
        delta[self.independent] = step
        delta[self.dependent] = -np.linalg.lstsq(jac_dep, jac_ind @ step, rcond=None)[0]
        return pin.integrate(self.chain.model, q, delta)


def velocity_gain(jac_dep: np.ndarray, jac_ind: np.ndarray) -> float:
    """‖J_dep⁺ J_ind‖₂, ∞ where J_dep has a (numerically) zero singular value."""
    if jac_dep.shape[1] == 0:
        return 0.0
    singular = np.linalg.svd(jac_dep, compute_uv=False)
    scale = max(1.0, float(np.abs(np.hstack([jac_dep, jac_ind])).max(initial=0.0)))
    if singular.size < jac_dep.shape[1] or singular[-1] <= RANK_TOLERANCE * scale:
        return float("inf")
    return float(np.linalg.norm(np.linalg.pinv(jac_dep) @ jac_ind, 2)) if jac_ind.size else 0.0


def _velocity_index(model: pin.Model, index_q: int) -> int:
    """Velocity index of a one-dof joint's configuration index."""
    joint = next(
        model.joints[j] for j in range(1, model.njoints) if model.joints[j].idx_q == index_q
    )
    return joint.idx_v


def _revolute_angles(model: pin.Model) -> list[int]:
    """Configuration indices of the revolute joints (angle coordinates, 2π-periodic)."""
    return [
        model.joints[j].idx_q
        for j in range(1, model.njoints)
        if model.joints[j].shortname().startswith(("JointModelR", "JointModelRevolute"))
        and model.joints[j].nq == 1
    ]
