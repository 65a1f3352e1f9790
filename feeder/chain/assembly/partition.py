"""Assembly of a closed chain: the dependent coordinates from the independent ones.

Position level: the mechanism is first *mounted* from a reference pose (the CAD's open one, or a
pose the user gives) onto the nearest closed pose over every coordinate
(:func:`~feeder.chain.assembly.newton.mount`); the independent coordinates are then moved to the
requested values by continuation, so the branch is the one nearest the reference — never one that
the joint limits or a random guess select. Along a trajectory the branch is kept by continuation
(:func:`~feeder.chain.assembly.tracking.track`): a tangent predictor and damped minimum-norm Newton
corrections over the dependent coordinates. Dependent revolute angles are wrapped into (−π, π] (or
into their joint's limits where those exclude it), never wound. Velocity and acceleration level:
the linear systems J q̇ = 0 and J q̈ + J̇ q̇ = 0 solved for the dependent components by truncated
least squares (minimum norm).

*Idle motions*: the motions of the dependent joints with every independent one locked that move no
joint's origin, no frame and no centre of gravity — a rod with a ball at each end spinning about
its axis, two coaxial hinges turning together. They are allowed: the kinematics follow the
minimum-norm solution (no idle velocity, no spinning rod), and the dynamics find their
accelerations (:mod:`feeder.chain.dynamics.inverse`). A locked-input motion that moves an origin
means too few independent joints, or a singular pose: refused.

The rank tests run at each solution (:meth:`Partition.check_pose` on a
:class:`~feeder.chain.kinematics.pose.ChainPose`; the
:class:`~feeder.chain.assembly.check.PoseCheck` it returns holds what they computed): the
independent joints must be able to move freely (the dependent part of the Jacobian has the whole
Jacobian's rank), and the dependent coordinates must be determined up to idle motions. Near a
singular pose (a toggle, a dead centre) the dependent velocities grow without bound for a bounded
independent motion; the *velocity gain* measures it, and a pose whose gain exceeds ``max_gain``
(default :data:`MAX_GAIN`) is refused with :class:`~feeder.exceptions.SingularPoseError`. The gain
is ‖S_dep⁻¹ J_dep⁺ J_ind S_ind‖₂: the largest dependent speed per unit independent speed, every
length's speed (a prismatic joint's, the linear ones of planar, translation and free-flyer joints)
counted in units of the mechanism's reach L (:attr:`Partition.length`: the largest distance of a
frame's origin from the world's at the model's zero pose), every angle's in rad/s. It is
dimensionless, rad/rad for a mechanism of revolute joints, and the same for a mechanism scaled up
or down: a cylinder acting at a lever arm h on a mechanism of reach L has a gain of about L/h (an
excavator's boom cylinder, h ≈ 0.25 m on L ≈ 6 m: ~25), a crank driving a rocker of comparable
length about 1; the limit refuses a lever arm shrunk to a thousandth of the reach, the same pose
for a 1 m model as for the 30 m machine it scales.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
import pinocchio as pin

from ...exceptions import InputError
from ...validation import check_number, check_vector
from ..kinematics.coordinates import length_rates
from ..kinematics.joints import kind_of
from ..kinematics.pose import ChainPose
from ..kinematics.tree import reach
from ..model.closure import ClosedChain
from . import check, refusals, restarts
from .check import PoseCheck
from .newton import MAX_ITERATIONS, POSITION_TOLERANCE, loop_gaps, mount
from .rank import rank_tolerance, truncated_inverse, velocity_gain

MAX_GAIN = 1e3
"""Largest accepted velocity gain (module docstring: dimensionless, lengths in units of the
mechanism's reach): a coordinate that must move a thousand times faster than the driving ones is
at a toggle for every practical purpose (the device's 5° transmission limit is a gain of ~3)."""


class Partition:
    """Split of a chain's velocity indices into independent and dependent ones; immutable
    after construction (every result at a pose is returned, none kept).

    Args:
        chain: The closed chain.
        independent: Names of the joints whose coordinates are given, one coordinate each
            (revolute, continuous, prismatic). Every ``x`` of the methods lists their values in
            this order.
        max_gain: Largest accepted velocity gain (:data:`MAX_GAIN`).

    Attributes:
        chain: The closed chain.
        independent_joints: The names given, in their order.
        independent: Velocity indices of the independent joints, in the order given.
        dependent: The other velocity indices, ascending.
        max_gain: The largest accepted velocity gain.
        length: The mechanism's reach L [m] (:func:`~feeder.chain.kinematics.tree.reach` at the
            model's zero pose): the unit of lengths' speeds in the velocity gain, and of the
            idle-motion test's lever arms.
        speed_scale: S (nv,) of the velocity gain: L [m] for a length's rate, 1 for an angle's.
        angle_columns: Velocity indices of the dependent revolute angles (those :meth:`wrap`
            brings into range).
        loops: Each closure's label and the ids of the joints of its loop, for the messages.

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
        self.length = reach(model, pin.neutral(model)[None])
        lengths = length_rates(model)  # the velocity components that are lengths' rates
        self._has_lengths = bool(lengths.any())
        self.speed_scale = np.where(lengths, self.length, 1.0)
        angles = [
            model.joints[j]
            for j in range(1, model.njoints)
            if kind_of(model.joints[j]) == "revolute" and model.joints[j].idx_v in self.dependent
        ]
        self._angles = tuple(joint.idx_q for joint in angles)  # the angles wrap() brings in
        self.angle_columns = np.array([joint.idx_v for joint in angles], dtype=int)
        self._limited = tuple(
            (model.names[j], model.joints[j].idx_q, model.joints[j].idx_v)
            for j in range(1, model.njoints)
            if model.joints[j].nq == 1
            and not model.lowerPositionLimit[model.joints[j].idx_q]
            == model.upperPositionLimit[model.joints[j].idx_q]
            == 0.0
        )  # one-coordinate joints with a range set ([0, 0] means "not set")
        self.loops = tuple(
            (closure.label, refusals.loop_joints(model, ids))
            for closure, ids in zip(chain.closures, chain.frame_ids, strict=True)
        )
        self._inputs = tuple(  # (idx_q, continuous) of each independent joint, in order
            (model.joints[j].idx_q, model.joints[j].nq == 2)
            for j in (model.getJointId(name) for name in self.independent_joints)
        )
        for array in (self.independent, self.dependent, self.speed_scale, self.angle_columns):
            array.setflags(write=False)
        self._frozen = True

    def __setattr__(self, name: str, value) -> None:
        if getattr(self, "_frozen", False):
            raise AttributeError(f"a Partition is immutable: make a new one ({name!r} given)")
        object.__setattr__(self, name, value)

    @property
    def gain_definition(self) -> str:
        """What the velocity gain is and its unit, for reports (module docstring)."""
        if not self._has_lengths:
            return "largest dependent speed per unit independent speed [rad/rad]"
        return (
            "largest dependent speed per unit independent speed, lengths' speeds in units of the "
            f"mechanism's reach L = {self.length:.4g} m [–]"
        )

    # -- the pose check ---------------------------------------------------------------------

    def check_closed(self, q: np.ndarray, tolerance: float = 1e-9) -> np.ndarray:
        """``q`` as an array if it closes every loop to ``tolerance`` [m, rad], else raise.

        Raises:
            InputError: NaN/inf or misshaped q.
            UnreachablePoseError: q does not close the loops.
        """
        q = self.chain.check_q(q)
        residual = self.chain.residual(q)
        if float(np.abs(residual).max(initial=0.0)) > tolerance:
            raise refusals.open_loop(self, q, residual, tolerance)
        return q

    def check_pose(self, pose: ChainPose, previous: PoseCheck | None = None) -> PoseCheck:
        """The rank, idle-motion and gain tests of the module docstring at ``pose``, and what
        they computed there.

        Args:
            pose: The pose (of this partition's chain).
            previous: The check of an earlier pose on the same branch, if any: a pose with as
                many dependent-rank deficiencies as it had idle motions needs no new idle-motion
                test (their number is structural; one with more is examined again).

        Raises:
            SingularPoseError: The independent joints cannot move freely, the dependent ones are
                not determined up to idle motions, or the velocity gain exceeds
                :attr:`max_gain`; the message names the loop and the joints.
            InputError: More independent joints than the mechanism has degrees of freedom.
        """
        return check.check_pose(self, pose, previous)

    def gain(self, q: np.ndarray) -> float:
        """The velocity gain at ``q`` (module docstring; idle motions do not count), without the
        tests of :meth:`check_pose`: also past :attr:`max_gain` (at an exactly singular pose
        the truncated pseudo-inverse drops the lost direction)."""
        jac = self.chain.jacobian(self.chain.check_q(q))
        pinv, _, _ = truncated_inverse(jac[:, self.dependent], rank_tolerance(jac))
        return velocity_gain(
            pinv @ jac[:, self.independent],
            self.speed_scale[self.dependent],
            self.speed_scale[self.independent],
        )

    def idle_motions(self, q: np.ndarray) -> np.ndarray:
        """Idle motions at the closed pose ``q`` (module docstring): an orthonormal basis
        (k, nv) of the joint rates that keep the loops closed with the independent joints locked
        and move no joint origin, frame or centre of gravity (k = 0 when there are none).

        Raises:
            SingularPoseError: Locked inputs leave a motion that moves an origin (too few
                independent joints, or a singular pose); the message names its joints.
        """
        return check.idle_motions(self, ChainPose(self.chain, q))

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
        v_independent = check_vector("v_independent", v_independent, self.independent.size)
        return self.check_pose(ChainPose(self.chain, q)).velocity(v_independent)

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
        a_independent = check_vector("a_independent", a_independent, self.independent.size)
        checked = self.check_pose(ChainPose(self.chain, q))
        gap_rate = float(np.abs(checked.jacobian @ v).max(initial=0.0))
        if gap_rate > 1e-9 * max(1.0, float(np.abs(v).max())):
            raise InputError(
                f"v opens the loops at {gap_rate:.3e} per second: it is not a closed-chain "
                "velocity (use Partition.velocity)"
            )
        return checked.acceleration(v, a_independent)

    # -- position level ---------------------------------------------------------------------

    def wrap(self, q: np.ndarray) -> np.ndarray:
        """``q`` (nq,) or (N, nq) with its dependent revolute angles moved by the multiple of 2π
        that brings them into (−π, π] — or, where that value is outside the joint's limits, into
        the limits if some turn of the angle is: never wound, and the same whatever generous
        limits are set (a range of [0, 0] means "not set")."""
        lower, upper = self.chain.model.lowerPositionLimit, self.chain.model.upperPositionLimit
        q = q.copy()
        for i in self._angles:
            low, high = lower[i], upper[i]
            principal = np.pi - np.mod(np.pi - q[..., i], 2.0 * np.pi)
            if low == high == 0.0:
                q[..., i] = principal
                continue
            shifted = principal + 2.0 * np.pi * np.ceil((low - principal) / (2.0 * np.pi))
            inside = (low - 1e-12 <= principal) & (principal <= high + 1e-12)
            q[..., i] = np.where(inside | (shifted > high + 1e-12), principal, shifted)
        return q

    def check_limits(self, q: np.ndarray) -> None:
        """Raise :class:`~feeder.exceptions.UnreachablePoseError` for the first joint of ``q``
        (nq,) or (N, nq) outside its limits (one-coordinate joints with a range set)."""
        lower, upper = self.chain.model.lowerPositionLimit, self.chain.model.upperPositionLimit
        q = np.atleast_2d(q)
        single = q.shape[0] == 1  # one pose (a continuation step): scalar tests, ten times faster
        for name, i, v in self._limited:
            low, high = lower[i], upper[i]
            if single:
                value = q[0, i]
                if value < low - 1e-12 or value > high + 1e-12:
                    raise refusals.outside_limits(name, value, low, high, v in self.independent)
                continue
            outside = (q[:, i] < low - 1e-12) | (q[:, i] > high + 1e-12)
            if outside.any():
                value = q[int(np.argmax(outside)), i]
                raise refusals.outside_limits(name, value, low, high, v in self.independent)

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
        if norm > POSITION_TOLERANCE or ChainPose(self.chain, q).reversed_hinges:
            raise refusals.not_mounted(norm, loop_gaps(self.chain, q_reference, q))
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
                condition, up to :data:`~feeder.chain.assembly.restarts.RESTARTS` seeded random
                guesses of the dependent coordinates are tried.
            max_iterations: Newton iterations per attempt.

        Returns:
            q (nq,) with ‖residual‖ ≤ :data:`POSITION_TOLERANCE`, revolute angles wrapped.

        Raises:
            InputError: NaN/inf or misshaped guess.
            UnreachablePoseError: No convergence, no solution on the branch, or a solution
                outside the joint limits.
            SingularPoseError: The solution is singular or near it (module docstring).
        """
        return restarts.assemble(self, q_guess, branch, max_iterations).q.copy()

    # -- independent coordinates ------------------------------------------------------------

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
