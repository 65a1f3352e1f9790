"""Assembly of a closed chain: the dependent coordinates from the independent ones.

Position level: the mechanism is first *mounted* from a reference pose (the CAD's open one, or a
pose the user gives) onto the nearest closed pose over every coordinate
(:func:`~feeder.chain.assembly.newton.mount`); the independent coordinates are then moved to the
requested values by continuation, so the branch is the one nearest the reference — never one that
the joint limits or a random guess select. Along a trajectory the branch is kept by continuation
(:meth:`Partition.track`): a tangent predictor and damped minimum-norm Newton corrections over the
dependent coordinates. Dependent revolute angles are wrapped into (−π, π] (or into their joint's
limits where those exclude it), never wound. Velocity and acceleration level: the linear systems
J q̇ = 0 and J q̈ + J̇ q̇ = 0 solved for the dependent components by truncated least squares
(minimum norm).

*Idle motions*: the motions of the dependent joints with every independent one locked that move no
joint's origin, no frame and no centre of gravity — a rod with a ball at each end spinning about
its axis, two coaxial hinges turning together. They are allowed: the kinematics follow the
minimum-norm solution (no idle velocity, no spinning rod), and the dynamics find their
accelerations
(:mod:`feeder.chain.dynamics.inverse`). A locked-input motion that moves an origin means too few
independent joints, or a singular pose: refused.

The rank tests run at each solution: the independent joints must be able to move freely (the
dependent part of the Jacobian has the whole Jacobian's rank), and the dependent coordinates must
be determined up to idle motions. Near a singular pose (a toggle, a dead centre) the dependent
velocities grow without bound for a bounded independent motion; the *velocity gain* measures it,
and a pose whose gain exceeds ``max_gain`` (default :data:`MAX_GAIN`) is refused with
:class:`~feeder.exceptions.SingularPoseError`. The gain is ‖S_dep⁻¹ J_dep⁺ J_ind S_ind‖₂: the
largest dependent speed per unit independent speed, every length's speed (a prismatic joint's,
the linear ones of planar, translation and free-flyer joints) counted in units of the
mechanism's reach L (:attr:`Partition.length`: the largest distance of a frame's origin from the
world's at the model's zero pose), every angle's in rad/s. It is dimensionless, rad/rad for a
mechanism of revolute joints, and the same for a mechanism scaled up or down: a cylinder acting
at a lever arm h on a mechanism of reach L has a gain of about L/h (an excavator's boom cylinder,
h ≈ 0.25 m on L ≈ 6 m: ~25), a crank driving a rocker of comparable length about 1; the limit
refuses a lever arm shrunk to a thousandth of the reach, the same pose for a 1 m model as for
the 30 m machine it scales.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Sequence

import numpy as np
import pinocchio as pin

from ...exceptions import InputError, SingularPoseError, UnreachablePoseError
from ...validation import check_finite, check_number, check_samples, check_vector
from ..kinematics.coordinates import length_rates, pose_text
from ..kinematics.joints import kind_of
from ..kinematics.tree import reach
from ..model.closure import ClosedChain
from .batch import MIN_SAMPLES, BatchFallback, batch_track
from .newton import (
    CONTINUATION_STEP,
    MAX_ITERATIONS,
    POSITION_TOLERANCE,
    RANK_TOLERANCE,
    loop_gaps,
    mount,
    newton,
)
from .rank import IDLE_TOLERANCE, moved_joints, point_rows, truncated_inverse, velocity_gain

MAX_GAIN = 1e3
"""Largest accepted velocity gain (module docstring: dimensionless, lengths in units of the
mechanism's reach): a coordinate that must move a thousand times faster than the driving ones is
at a toggle for every practical purpose (the device's 5° transmission limit is a gain of ~3)."""

MOUNT_STEP = 0.05
"""Largest step [rad, m] of the independent coordinates when they are moved from the mounted
pose to the first requested values (the continuation's own step test refuses coarser ones)."""

MIN_FRACTION = 2.0**-40
"""Smallest part of a sample's step that the continuation tries (:meth:`Partition._continue`
halves a part that fails): ~1e-12 of the step, round-off of the coordinates. Near a dead centre
the parts that succeed shrink with the distance to it (about half of it each), so the
continuation creeps up to it until the velocity gain passes :data:`MAX_GAIN`, a gain of 1e3 lying
~1e-6 of the coordinates short of a four-bar's dead centre: well above this floor."""

RESTARTS = 50
"""Random restarts (seeded) that :meth:`Partition.assemble` tries when Newton from the guess
stops at a local minimum of the residual, or its solution misses the requested branch."""


class Partition:
    """Split of a chain's velocity indices into independent and dependent ones.

    Args:
        chain: The closed chain.
        independent: Names of the joints whose coordinates are given, one coordinate each
            (revolute, continuous, prismatic). Every ``x`` of the methods lists their values in
            this order.
        max_gain: Largest accepted velocity gain (:data:`MAX_GAIN`).

    Attributes:
        independent: Velocity indices of the independent joints, in the order given.
        dependent: The other velocity indices, ascending.
        length: The mechanism's reach L [m] (:func:`~feeder.chain.kinematics.tree.reach` at the
            model's zero pose): the unit of lengths' speeds in the velocity gain, and of the
            idle-motion test's lever arms.

    Raises:
        InputError: An unknown joint name, a name given twice, a multi-coordinate joint.
    """

    def __init__(self, chain: ClosedChain, independent: Sequence[str], max_gain: float = MAX_GAIN):
        self.independent = chain.coordinate_columns(independent, "independent")
        self.chain = chain
        self.independent_joints = tuple(independent)
        self.max_gain = check_number("max_gain", max_gain)
        if not self.max_gain > 1.0:
            raise InputError(f"max_gain must be a number above 1, got {max_gain!r}")
        model = chain.model
        mask = np.ones(model.nv, dtype=bool)
        mask[self.independent] = False
        self.dependent = np.flatnonzero(mask)
        kinds = {j: kind_of(model.joints[j]) for j in range(1, model.njoints)}
        self.length = reach(model, pin.neutral(model)[None])
        self._lengths = length_rates(model)
        self._scale = np.where(self._lengths, self.length, 1.0)  # S of the velocity gain
        angles = [
            model.joints[j]
            for j, kind in kinds.items()
            if kind == "revolute" and model.joints[j].idx_v in self.dependent
        ]
        self._angles = [joint.idx_q for joint in angles]  # the angles wrap() brings into range
        self._angle_columns = np.array([joint.idx_v for joint in angles], dtype=int)
        self._limited = [
            (model.names[j], model.joints[j].idx_q, model.joints[j].idx_v)
            for j in range(1, model.njoints)
            if model.joints[j].nq == 1
            and not model.lowerPositionLimit[model.joints[j].idx_q]
            == model.upperPositionLimit[model.joints[j].idx_q]
            == 0.0
        ]  # one-coordinate joints with a range set ([0, 0] means "not set")
        self._last: tuple[bytes, tuple[np.ndarray, np.ndarray, float]] | None = None
        self._idle_count = 0
        """Idle motions verified at a pose (their number is structural: a pose with as many
        dependent-rank deficiencies needs no new check, one with more is examined again)."""
        self._loops = [
            (closure.label, _loop_joints(model, ids))
            for closure, ids in zip(chain.closures, chain.frame_ids, strict=True)
        ]  # each closure's label and the ids of the joints of its loop, for messages
        self._inputs = []  # (idx_q, continuous) of each independent joint, in the given order
        self._times: np.ndarray | None = None  # the samples' times [s] (track's), for messages
        for name in self.independent_joints:
            joint = model.joints[model.getJointId(name)]
            self._inputs.append((joint.idx_q, joint.nq == 2))

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
        residual = np.abs(self.chain.residual(q))
        gap = float(residual.max(initial=0.0))
        if gap > tolerance:
            worst = [float(residual[rows].max()) for rows in self.chain.row_slices]
            label, joints = self._loops[int(np.argmax(worst))]
            raise UnreachablePoseError(
                f"loop {label} is open by {gap:.3e} [m, rad] > {tolerance:g} at "
                f"{pose_text(self.chain.model, q, joints)}: not a closed pose (assemble it first)"
            )
        return q

    def gain(self, q: np.ndarray) -> float:
        """The velocity gain at ``q`` (module docstring; idle motions do not count), without the
        tests of :meth:`velocity`: also past :attr:`max_gain` (at an exactly singular pose the
        truncated pseudo-inverse drops the lost direction)."""
        q = self.chain.check_q(q)
        jac = self.chain.jacobian(q)
        pinv, _, _ = truncated_inverse(jac[:, self.dependent], self._rank_tolerance(jac))
        return self._gain(pinv, jac)

    @property
    def gain_definition(self) -> str:
        """What the velocity gain is and its unit, for reports (module docstring)."""
        if not self._lengths.any():
            return "largest dependent speed per unit independent speed [rad/rad]"
        return (
            "largest dependent speed per unit independent speed, lengths' speeds in units of the "
            f"mechanism's reach L = {self.length:.4g} m [–]"
        )

    def _gain(self, pinv: np.ndarray, jac: np.ndarray) -> float:
        """The velocity gain from the truncated pseudo-inverse (n_dep, nc) of the dependent
        columns of the closure Jacobian ``jac`` (nc, nv)."""
        rates = pinv @ jac[:, self.independent]
        return velocity_gain(rates, self._scale[self.dependent], self._scale[self.independent])

    @staticmethod
    def _rank_tolerance(jac: np.ndarray) -> float:
        """Singular values of the closure Jacobian ``jac`` at or below this are zero."""
        return RANK_TOLERANCE * (float(np.abs(jac).max(initial=0.0)) or 1.0)

    def _inputs_text(self, q: np.ndarray) -> str:
        """The independent joints' values at ``q``, labelled with their units (``this pose``
        without independent joints)."""
        model = self.chain.model
        ids = [model.getJointId(name) for name in self.independent_joints]
        return pose_text(model, q, ids) or "this pose"

    def _involved_text(self, q: np.ndarray, names: Sequence[str]) -> str:
        """``loop <label>`` (or ``loops …``) of the loops through the joints ``names``, and those
        joints' values at ``q``, labelled with their units: ``loop a-b (j = 0.3 rad)``."""
        model = self.chain.model
        ids = {model.getJointId(name) for name in names}
        loops = [label for label, joints in self._loops if joints & ids]
        where = f"loop{'s' if len(loops) > 1 else ''} {', '.join(loops)}" if loops else "the tree"
        return f"{where} ({pose_text(model, q, sorted(ids))})"

    def _weakest(self, jac: np.ndarray) -> tuple[str, ...]:
        """The dependent joints that the weakest direction of the closure Jacobian's dependent
        columns ``jac[:, dependent]`` moves (its smallest singular value above the rank
        tolerance: the motion a toggle frees), largest share first."""
        _, s, vt = np.linalg.svd(jac[:, self.dependent], full_matrices=False)
        kept = np.flatnonzero(s > self._rank_tolerance(jac))
        motion = np.zeros(self.chain.model.nv)
        motion[self.dependent] = vt[kept[-1] if kept.size else -1]
        return moved_joints(self.chain.model, motion)

    def _split(self, jac: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return jac[:, self.dependent], jac[:, self.independent]

    def idle_motions(self, q: np.ndarray) -> np.ndarray:
        """Idle motions at the closed pose ``q`` (module docstring): an orthonormal basis
        (k, nv) of the joint rates that keep the loops closed with the independent joints locked
        and move no joint origin, frame or centre of gravity (k = 0 when there are none).

        Raises:
            SingularPoseError: Locked inputs leave a motion that moves an origin (too few
                independent joints, or a singular pose); the message names its joints.
        """
        q = self.chain.check_q(q)
        return self._idle(q, self.chain.jacobian(q))

    def _idle(self, q: np.ndarray, jac: np.ndarray) -> np.ndarray:
        """:meth:`idle_motions` with the closure Jacobian at q (the chain's data hold q)."""
        model, nv = self.chain.model, self.chain.model.nv
        jac_dep = jac[:, self.dependent]
        scale = float(np.abs(jac).max(initial=0.0)) or 1.0
        if jac_dep.size:
            _, s, vt = np.linalg.svd(jac_dep)
            rank = int(np.sum(s > RANK_TOLERANCE * scale))
            free = vt[rank:]
        else:
            rank, free = 0, np.eye(self.dependent.size)
        if free.shape[0] == 0:
            return np.zeros((0, nv))
        motions = np.zeros((free.shape[0], nv))
        motions[:, self.dependent] = free
        points = point_rows(self.chain)  # (3 p, nv): joint origins, frames, centres of gravity
        moved = np.abs(points @ motions.T).max(axis=0)
        if np.all(moved <= IDLE_TOLERANCE * self.length):
            return motions
        # The locked-input motions that move points: name the joints of the worst one.
        names = moved_joints(model, motions[int(np.argmax(moved))])
        raise SingularPoseError(
            f"the closure does not determine the {self.dependent.size} dependent coordinates "
            f"at {self._inputs_text(q)}: dependent Jacobian rank {rank}; with "
            f"{list(self.independent_joints)} locked, {', '.join(names)} can still move in "
            f"{self._involved_text(q, names)}, up to {moved.max():.3g} m per unit rate: not an "
            "idle motion (too few independent joints, or a singular pose)"
        )

    def _check_pose(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
        """The closure Jacobian (nc, nv), the truncated pseudo-inverse of its dependent columns
        (n_dep, nc) and the velocity gain at ``q``, after the rank, idle-motion and gain tests of
        the module docstring. Remembered for the last pose (a trajectory asks for it when it
        checks a sample, when it gives its rates and when it predicts the next one)."""
        key = q.tobytes()
        if self._last is not None and self._last[0] == key:
            return self._last[1]
        jac = self.chain.jacobian(q)
        jac_dep, jac_ind = self._split(jac)
        tolerance = self._rank_tolerance(jac)
        pinv, rank_dep, range_dep = truncated_inverse(jac_dep, tolerance)
        # The whole Jacobian has a larger rank than its dependent part iff some independent
        # column reaches outside the range of the dependent ones (J_ind's part off that range).
        outside = jac_ind - range_dep @ (range_dep.T @ jac_ind)
        reach = np.linalg.norm(outside, axis=0)
        if np.any(reach > tolerance):
            rank_full = rank_dep + np.linalg.matrix_rank(outside, tol=tolerance)
            if np.abs(self.chain.residual(q)).max(initial=0.0) <= POSITION_TOLERANCE:
                self._check_count(self.chain.model.nv - rank_full)
            pairs = zip(self.independent_joints, reach, strict=True)
            names = [name for name, size in pairs if size > tolerance]
            raise SingularPoseError(
                f"the dependent coordinates cannot follow the independent ones at "
                f"{self._inputs_text(q)}: moving {', '.join(names)} opens "
                f"{self._involved_text(q, names)} whatever the dependent joints do (closure "
                f"Jacobian rank {rank_full}, dependent part rank {rank_dep}: not an admissible "
                "choice of independent joints, or a singular pose)"
            )
        deficiency = self.dependent.size - rank_dep
        if deficiency and deficiency != self._idle_count:
            self._idle_count = self._idle(q, jac).shape[0]  # raises unless all are idle
        gain = self._gain(pinv, jac)
        if gain > self.max_gain:
            weakest = self._weakest(jac)
            raise SingularPoseError(
                f"near a singular pose (toggle, dead centre) at {self._inputs_text(q)}: "
                f"{', '.join(weakest)} must move up to {gain:.3g} times as fast as "
                f"{', '.join(self.independent_joints)} in "
                f"{self._involved_text(q, weakest)} (velocity gain {gain:.4g} > "
                f"limit {self.max_gain:g}; {self.gain_definition}); the loads grow without bound "
                "there"
            )
        self._last = (key, (jac, pinv, gain))
        return jac, pinv, gain

    def _check_count(self, freedom: int) -> None:
        """Raise :class:`InputError` if more joints are independent than the mechanism has
        degrees of freedom at a closed pose with ``freedom`` of them (a singular pose has more
        than a regular one, never fewer: so too many here are too many everywhere; an open pose
        may have fewer, a planar loop's redundant rows counting there)."""
        count = self.independent.size
        if count > freedom:
            raise InputError(
                f"this mechanism has {freedom} degree{'s' if freedom != 1 else ''} of freedom; "
                f"{count} independent joints given ({', '.join(self.independent_joints)}): "
                f"make {freedom} of them independent (the file's 'independent' list)"
            )

    # -- position level ---------------------------------------------------------------------

    def wrap(self, q: np.ndarray) -> np.ndarray:
        """``q`` (nq,) or (N, nq) with its dependent revolute angles moved by the multiple of 2π
        that brings them into (−π, π] — or, where that value is outside the joint's limits, into
        the limits if some turn of the angle is: never wound, and the same whatever generous
        limits are set (a range of [0, 0] means "not set")."""
        model = self.chain.model
        q = q.copy()
        for i in self._angles:
            low, high = model.lowerPositionLimit[i], model.upperPositionLimit[i]
            principal = np.pi - np.mod(np.pi - q[..., i], 2.0 * np.pi)
            if low == high == 0.0:
                q[..., i] = principal
                continue
            shifted = principal + 2.0 * np.pi * np.ceil((low - principal) / (2.0 * np.pi))
            inside = (low - 1e-12 <= principal) & (principal <= high + 1e-12)
            q[..., i] = np.where(inside | (shifted > high + 1e-12), principal, shifted)
        return q

    def _check_limits(self, q: np.ndarray) -> None:
        """Raise :class:`UnreachablePoseError` for the first joint of ``q`` (nq,) or (N, nq)
        outside its limits (one-coordinate joints with a range set)."""
        model = self.chain.model
        q = np.atleast_2d(q)
        for name, i, v in self._limited:
            low, high = model.lowerPositionLimit[i], model.upperPositionLimit[i]
            outside = (q[:, i] < low - 1e-12) | (q[:, i] > high + 1e-12)
            if outside.any():
                value = q[int(np.argmax(outside)), i]
                role = "prescribed" if v in self.independent else "dependent"
                raise UnreachablePoseError(
                    f"the {role} joint {name} = {value:.6g} is outside its limits "
                    f"[{low:.6g}, {high:.6g}]"
                    + ("" if role == "prescribed" else " where the loops close")
                )

    def mount(self, q_reference: np.ndarray) -> np.ndarray:
        """The closed pose nearest to ``q_reference`` over every coordinate (the branch of the
        open CAD pose, or of a pose the user gives), angles wrapped.

        Raises:
            InputError: NaN/inf or misshaped reference.
            UnreachablePoseError: The loops do not close: which loop, by how much, and how close
                each gets alone.
        """
        q_reference = self.chain.check_q(q_reference)
        q, norm = mount(self.chain, q_reference)
        if norm > POSITION_TOLERANCE or self.chain.reversed_hinges():
            detail = "; ".join(loop_gaps(self.chain, q_reference, q))
            raise UnreachablePoseError(
                f"the loops do not close from the reference pose (residual {norm:.3e} after the "
                f"mount): {detail}"
            )
        return self.wrap(q)

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
            q (nq,) with ‖residual‖ ≤ :data:`POSITION_TOLERANCE`, revolute angles wrapped.

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
            q, norm = newton(self.chain, start.copy(), self.dependent, max_iterations)
            if best is None or norm < best[0]:
                best = (norm, q)
            if norm > POSITION_TOLERANCE or self.chain.reversed_hinges():
                continue  # not closed, or a hinge assembled upside down
            q = self.wrap(q)
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
        try:
            self._check_pose(q)
        except SingularPoseError as exc:
            raise SingularPoseError(
                f"the loops close only to {norm:.3e} [m, rad], near a singular pose (toggle, dead "
                "centre): the given independent coordinates are at or beyond the end of the "
                f"mechanism's travel ({exc})"
            ) from None
        raise UnreachablePoseError(
            f"the loop does not close at the given independent coordinates (best residual "
            f"{norm:.3e} after {max_iterations} damped Newton steps from the guess and from "
            f"{RESTARTS} random guesses)"
        )

    def _random_guess(self, q: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """``q`` with its dependent coordinates replaced by random values (±π, or within the
        joint's range where it is set; random rotations for multi-coordinate joints)."""
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
        """Velocity (nv,) with the given independent components (in the order of the
        independent joints) and J q̇ = 0, minimum norm in the idle motions.

        Raises:
            InputError: NaN/inf or misshaped inputs.
            UnreachablePoseError: q does not close the loops.
            SingularPoseError: A singular pose or one near it.
        """
        q = self.check_closed(q)
        v_independent = self._check_independent("v_independent", v_independent)
        jac, pinv, _ = self._check_pose(q)
        return self._velocity(jac, pinv, v_independent)

    def _velocity(self, jac: np.ndarray, pinv: np.ndarray, v_independent: np.ndarray):
        v = np.zeros(self.chain.model.nv)
        v[self.independent] = v_independent
        v[self.dependent] = -pinv @ (jac @ v)
        return v

    def acceleration(self, q: np.ndarray, v: np.ndarray, a_independent: np.ndarray) -> np.ndarray:
        """Acceleration (nv,) with the given independent components and J q̈ + J̇ q̇ = 0,
        minimum norm in the idle motions.

        Raises:
            InputError: NaN/inf or misshaped inputs, or velocities that open the loops.
            UnreachablePoseError: q does not close the loops.
            SingularPoseError: A singular pose or one near it.
        """
        q = self.check_closed(q)
        v = self.chain.check_v("v", v)
        a_independent = self._check_independent("a_independent", a_independent)
        jac, pinv, _ = self._check_pose(q)
        gap_rate = float(np.abs(jac @ v).max(initial=0.0))
        if gap_rate > 1e-9 * max(1.0, float(np.abs(v).max())):
            raise InputError(
                f"v opens the loops at {gap_rate:.3e} per second: it is not a closed-chain "
                "velocity (use Partition.velocity)"
            )
        return self._acceleration(q, v, jac, pinv, a_independent)

    def _acceleration(self, q, v, jac, pinv, a_independent) -> np.ndarray:
        a = np.zeros(self.chain.model.nv)
        a[self.independent] = a_independent
        a[self.dependent] = -pinv @ (jac @ a + self.chain.bias(q, v))
        return a

    # -- trajectories -----------------------------------------------------------------------

    def independent_values(self, q: np.ndarray) -> np.ndarray:
        """The independent coordinates of ``q`` (rad for revolute and continuous joints, m for
        prismatic ones), in the order of the independent joints."""
        return np.array([np.arctan2(q[i + 1], q[i]) if pair else q[i] for i, pair in self._inputs])

    def with_independent(self, q: np.ndarray, x: np.ndarray) -> np.ndarray:
        """``q`` with the independent coordinates set to ``x`` (in the order of the independent
        joints; a continuous joint's (cos, sin) from its angle)."""
        q = q.copy()
        for (i, pair), value in zip(self._inputs, x, strict=True):
            if pair:
                q[i : i + 2] = np.cos(value), np.sin(value)
            else:
                q[i] = value
        return q

    def track(
        self,
        q_start: np.ndarray,
        x: np.ndarray,
        dx: np.ndarray | None = None,
        ddx: np.ndarray | None = None,
        branch: Callable[[np.ndarray], bool] | None = None,
        t: np.ndarray | None = None,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Follow a trajectory of the independent coordinates on one assembly branch.

        The first sample: ``q_start`` closed as it is (:meth:`mount` if its loops are open, which
        picks the branch nearest to it), then its independent coordinates moved to ``x[0]`` by
        continuation — unless ``branch`` is given, which picks the first sample by
        :meth:`assemble` from ``q_start`` instead. Each later sample starts Newton from the
        previous solution moved along the closure's tangent (a first-order predictor), which
        keeps the branch as long as the samples are fine compared with the distance to a singular
        pose; a pose near one is refused.

        Args:
            q_start: A pose (nq,) that picks the branch (the reference pose).
            x: Independent coordinates, (N, n_independent), columns in the order of the
                independent joints.
            dx, ddx: Their rates and accelerations (N, n_independent); zero if omitted.
            branch: Optional condition on the first sample's solution (:meth:`assemble`).
            t: The samples' times [s] (N,), named in the messages (else the samples' numbers).

        Returns:
            q (N, nq), v (N, nv), a (N, nv) and the velocity gain of every sample (N,).

        Raises:
            SingularPoseError: A sample at or near a singular pose, or the motion reaching one
                between two samples (a dead centre: the end of the independent joints' travel),
                named with its time and pose.
            UnreachablePoseError: The loops do not close at a sample, or a joint leaves its
                limits.
            InputError: Bad arrays; more independent joints than degrees of freedom.
        """
        n_ind = self.independent.size
        x = check_samples("x", x, n_ind)
        dx = np.zeros_like(x) if dx is None else check_samples("dx", dx, n_ind)
        ddx = np.zeros_like(x) if ddx is None else check_samples("ddx", ddx, n_ind)
        if not x.shape == dx.shape == ddx.shape:
            raise InputError(
                f"x, dx, ddx must have one shape, got {x.shape}, {dx.shape}, {ddx.shape}"
            )
        if t is not None:
            t = check_finite("t [s]", t)
            if t.shape != (x.shape[0],):
                raise InputError(f"t must give one time per sample ({x.shape[0]}), got {t.shape}")
        self._times = t
        model = self.chain.model
        n = x.shape[0]
        first = self._first(self.chain.check_q(q_start), x[0], branch)
        if n >= MIN_SAMPLES:
            with contextlib.suppress(BatchFallback):  # then the sequential way, below
                return batch_track(self, first, x, dx, ddx)
        qs, vs, accs = np.empty((n, model.nq)), np.empty((n, model.nv)), np.empty((n, model.nv))
        gains = np.empty(n)
        for i in range(n):
            q = first if i == 0 else self._continue(qs[i - 1], x[i - 1], x[i], i)
            jac, pinv, gains[i] = self._check_pose(q)
            qs[i] = q
            vs[i] = self._velocity(jac, pinv, dx[i])
            accs[i] = self._acceleration(q, vs[i], jac, pinv, ddx[i])
        return qs, vs, accs, gains

    def _first(self, q_start, x0, branch) -> np.ndarray:
        """The first sample of :meth:`track` (its docstring)."""
        if branch is not None:
            return self.assemble(self.with_independent(q_start, x0), branch)
        gap = float(np.abs(self.chain.residual(q_start)).max(initial=0.0))
        q = self.mount(q_start) if gap > POSITION_TOLERANCE else q_start
        start = self.independent_values(q)
        steps = max(1, int(np.ceil(np.abs(x0 - start).max(initial=0.0) / MOUNT_STEP)))
        for k in range(steps):
            q = self._continue(
                q, start + (x0 - start) * k / steps, start + (x0 - start) * (k + 1) / steps, 0
            )
        return q

    def _continue(
        self, previous: np.ndarray, x_previous: np.ndarray, x: np.ndarray, sample: int
    ) -> np.ndarray:
        """The next sample's configuration, with independent coordinates ``x`` (those of
        ``previous`` are ``x_previous``): Newton from the tangent predictor, no restarts, the
        correction small next to the step (else a branch switch is possible). A part of the step
        that fails is halved, one that succeeds doubled (a ball joint written as three revolutes
        near gimbal lock, or a dead centre, curve the dependent coordinates sharply). A part
        below :data:`MIN_FRACTION` of the step that still fails is a singular pose: only there
        do the loops stop closing, or the dependent coordinates jump, for a vanishing step.

        Raises:
            SingularPoseError: The motion reaches a singular pose on the way (a dead centre: the
                end of the independent joints' travel; or branches meeting), or a pose near one;
                the message names the sample, its time and the pose.
            UnreachablePoseError: The sample is outside a joint's limits.
        """
        q, done, part = previous, 0.0, 1.0
        try:
            while done < 1.0:
                end = min(1.0, done + part)
                start = x_previous + (x - x_previous) * done
                stop = x if end == 1.0 else x_previous + (x - x_previous) * end
                trial, closed = self._step(q, start, stop)
                if closed:
                    q, done, part = trial, end, min(2.0 * part, 1.0)
                    continue
                part /= 2.0
                if part < MIN_FRACTION:
                    weakest = self._weakest(self.chain.jacobian(q))
                    raise SingularPoseError(
                        f"the motion reaches a singular pose (a dead centre, or assembly branches "
                        f"meeting) at {self._inputs_text(self.with_independent(q, start))}, in "
                        f"{self._involved_text(q, weakest)}, velocity gain {self.gain(q):.3g}: "
                        "it cannot be followed past there; end the motion before it, or choose "
                        "other independent joints"
                    )
            q = self.wrap(q)
            self._check_limits(q)
            self._check_pose(q)
        except SingularPoseError as exc:
            raise SingularPoseError(f"{self._where(sample)}: {exc}") from None
        return q

    def _where(self, sample: int) -> str:
        """The sample's number, and its time when :meth:`track` was given the times."""
        if self._times is None:
            return f"sample {sample}"
        return f"sample {sample} (t = {self._times[sample]:.6g} s)"

    def _step(
        self, previous: np.ndarray, x_previous: np.ndarray, x: np.ndarray
    ) -> tuple[np.ndarray, bool]:
        """One predictor–corrector step of :meth:`_continue`: (q, whether it succeeded: the loops
        closed, the hinges the right way up, the correction small next to the step)."""
        step = x - x_previous
        guess = self.with_independent(self._predict(previous, step), x)
        q, norm = newton(self.chain, guess.copy(), self.dependent)
        correction = float(np.abs(pin.difference(self.chain.model, guess, q)).max(initial=0.0))
        size = float(np.abs(step).max(initial=0.0))
        closed = norm <= POSITION_TOLERANCE and not self.chain.reversed_hinges()
        on_branch = correction <= CONTINUATION_STEP * max(size, 1e-12) or correction <= 1e-9
        return q, closed and on_branch

    def _predict(self, q: np.ndarray, step: np.ndarray) -> np.ndarray:
        """``q`` moved by ``step`` of the independent coordinates along the closure's tangent
        (minimum norm in the idle motions)."""
        jac, pinv, _ = self._check_pose(q)
        delta = np.zeros(self.chain.model.nv)
        delta[self.independent] = step
        delta[self.dependent] = -pinv @ (jac[:, self.independent] @ step)
        return pin.integrate(self.chain.model, q, delta)


def _loop_joints(model: pin.Model, frames: tuple[int, int]) -> set[int]:
    """Ids of the joints of a closure's loop: those that carry one of its two ``frames`` (ids)
    but not the other (the tree's path between the two frames' bodies)."""
    a, b = (model.frames[f].parentJoint for f in frames)
    return (set(model.supports[a]) ^ set(model.supports[b])) - {0}
