"""Hybrid runs: the actuated joints follow their motion table, the freedoms they leave free are
integrated forward, and the loads and every reaction are computed along the resulting motion.

When locking the actuated joints leaves freedoms that carry mass (:mod:`.free_freedoms`: a rod
between two balls whose centre of gravity is off the line through them), the motion table does
not determine the mechanism's motion: its dynamics do. The state (q, q̇) of the whole chain is
integrated with the actuated joints prescribed. A reduced formulation gives q̈, the one of the
idle motions (:mod:`.idle`) with the free freedoms among them:

    q̈ = a_p + N z,    [J; S] a_p = [−J̇ q̇ − 2ω J q̇ − ω² r(q);  ẍ + 2ω (ẋ − S q̇) + ω² (x − S q)],

a_p the minimum-norm solution (the closure rows J and the actuated rows S, with Baumgarte's
corrector at the rate ω on the loops' residual r and on the actuated coordinates' gap to the
table's x(t)), N an orthonormal basis of the null space of [J; S] (every motion left with the
actuated joints locked: the free freedoms, and the idle motions that move no point) and z from
the equations of motion projected onto it, where neither closure nor actuator forces work:

    Nᵀ M N z = −Nᵀ (M a_p + b − Σ_e J_eᵀ w_e).

This is the system that Pinocchio's ``constraintDynamics`` solves with the loops and the
actuated joints as constraints (the tests check that the actuated loads found drive it to the
same q̈); in this form a freedom that moves no mass (Nᵀ M N singular: below
:data:`~.idle.INERTIA_RANK`) gets the minimum-norm z, where the KKT matrix of the constrained
dynamics is singular, and stays on the minimum-norm path as in the inverse dynamics.

The table's x, ẋ, ẍ between its samples: the quintic Hermite interpolant of its three columns
(SciPy's ``BPoly.from_derivatives``: C², it takes each sample's position, rate and acceleration).
Integration: SciPy's Runge–Kutta or implicit methods, stepped with the user's tolerances; drift
control as in :func:`~feeder.chain.dynamics.forward.simulate`: Baumgarte always, and a projection
of (q, q̇) onto the loops with the actuated joints at x(t), ẋ(t) (minimum-norm Newton over the
other coordinates, then the minimum-norm velocity correction) whenever an accepted step leaves
either by more than ``drift_tolerance``; every output sample projected so.

The free freedoms start from their pose at rest at the table's first sample (:func:`~.
free_freedoms.rest_pose`), their rates 0; each one's travel is the integral of its pivot joint's
rate in the locked motions (N Nᵀ q̇ at the pivot), whose largest magnitude is its *excursion*.

On a moving base (a :class:`~.inverse.ChainDynamics` with a ``base``) q, q̇, q̈ and the table are
the motion relative to the base, as in the inverse dynamics, whose loads already take the base
(the mount's wrench, the reactions in the base's moving axes). The hull enters as a moving root
(:mod:`~.forward_base`): b above is the moving base's bias b_B(q, q̇, t), the rooted tree's RNEA
with q̈ = 0 (:meth:`~.forward_base.MovingBase.bias`), which adds the fictitious forces of the
base's acceleration and rotation; M, J and S are the relative motion's. The free freedoms' rest
pose at the start is found under the gravity the base sees at the first sample: the level
gravity in the model's moving axes at t[0] (:attr:`~feeder.chain.model.base.BaseState.gravity`:
a slope or a hull pitched at t[0] tilts it); the base's acceleration and rotation at t[0] do not
enter it: the pose the mechanism rests in on a hull standing still in its attitude at t[0].
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ...exceptions import InputError, SingularPoseError, UnreachablePoseError
from ...validation import check_finite, check_number, check_samples
from ..assembly.continuation import MOUNT_STEP
from ..assembly.newton import POSITION_TOLERANCE, newton
from ..blas import one_blas_thread
from ..kinematics.coordinates import length_rates, pose_text
from .budget import MAX_STEPS, check_sample_count, step_cap_message
from .forward import ATOL, DRIFT_TOLERANCE, METHODS, RTOL, SMALLEST_RTOL
from .forward_base import stage_times
from .forward_equations import BAUMGARTE_RATE, IntegrationError
from .free_freedoms import FreeFreedoms, free_freedoms, rest_pose
from .hybrid_equations import HybridEquations, Prescribed
from .inverse import ChainDynamics, ChainLoads, check_dynamics, inverse_dynamics


@dataclass(frozen=True)
class HybridRun:
    """A hybrid run on the motion table's times (module docstring).

    Attributes:
        t: Times [s], (N,).
        q, v, a: The whole chain's motion, (N, nq), (N, nv), (N, nv) (projected samples).
        loads: The inverse dynamics of that motion: the actuated joints' loads, closure forces,
            every joint's reaction.
        free: The free freedoms (:class:`~.free_freedoms.FreeFreedoms`, at the first sample).
        start: The first sample's pose (nq,): the free freedoms at rest, rates 0.
        travel: Each free freedom's travel since t[0] [rad or m of its pivot joint], (N, m).
        residual: The largest gap of each sample to the loops and the table before its
            projection [m, rad], (N,): the drift.
        steps, evaluations, projections: Accepted steps, right-hand sides evaluated, steps
            projected back.
        settings: The integrator and its tolerances, as text.
        idle: The idle motions (moving no point) integrated with the free freedoms.
        gravity: On a moving base, the gravity [m/s²] (3,) in the model's moving axes at t[0]
            under which the free freedoms came to rest (module docstring); None at rest.
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    loads: ChainLoads
    free: FreeFreedoms
    start: np.ndarray
    travel: np.ndarray
    residual: np.ndarray
    steps: int
    evaluations: int
    projections: int
    settings: str
    idle: int
    gravity: np.ndarray | None = None

    def excursion(self) -> np.ndarray:
        """Each free freedom's largest |travel| over the run [rad or m], (m,)."""
        return np.abs(self.travel).max(axis=0)

    def text(self, model: pin.Model) -> list[str]:
        """The summary's lines: the free freedoms, the joints each moves and how far it moved,
        their start, and the run's integration (``model``: the chain's model)."""
        count = len(self.free)
        lengths = length_rates(model)
        lines = [
            f"hybrid run: the actuated joints leave {count} freedom(s) free that move mass; "
            f"integrated forward with the actuated joints following the table ({self.settings}, "
            f"{self.steps} steps, {self.projections} projections, largest drift "
            f"{self.residual.max():.2g} m or rad), the loads are those of the resulting motion"
        ]
        pairs = zip(self.free.joints, self.free.pivots, self.excursion(), strict=True)
        for k, (joints, pivot, excursion) in enumerate(pairs, start=1):
            unit = "m" if lengths[pivot] else "rad"
            lines.append(
                f"  free freedom {k} moves {', '.join(joints)}; max excursion {excursion:.4g} "
                f"{unit} (of {velocity_name(model, pivot)})"
            )
        if self.idle:
            lines.append(
                f"  {self.idle} idle motion(s) (moving no point) integrated with them, from rest"
            )
        ids = sorted({velocity_joint(model, pivot) for pivot in self.free.pivots})
        weighed = ""
        if self.gravity is not None:
            weighed = (
                " under the gravity the moving base sees there, "
                f"[{', '.join(f'{g:.4g}' for g in self.gravity)}] m/s² in its axes"
            )
        lines.append(
            f"  start: the free freedoms at rest (least potential energy, rates 0) at the first "
            f"sample, t = {self.t[0]:.4g} s{weighed}: {pose_text(model, self.start, ids)}"
        )
        return lines


def velocity_joint(model: pin.Model, index: int) -> int:
    """The id of the joint whose velocity components hold ``index``."""
    return next(
        j
        for j in range(1, model.njoints)
        if model.joints[j].idx_v <= index < model.joints[j].idx_v + model.joints[j].nv
    )


def velocity_name(model: pin.Model, index: int) -> str:
    """The joint of velocity component ``index``, named (with the component's number for a
    joint of several)."""
    j = velocity_joint(model, index)
    if model.joints[j].nv == 1:
        return model.names[j]
    return f"{model.names[j]} component {index - model.joints[j].idx_v + 1}"


@one_blas_thread
def hybrid_run(
    dyn: ChainDynamics,
    t: np.ndarray,
    x: np.ndarray,
    dx: np.ndarray,
    ddx: np.ndarray,
    q_start: np.ndarray,
    *,
    method: str = "DOP853",
    rtol: float = RTOL,
    atol: float = ATOL,
    rate: float = BAUMGARTE_RATE,
    drift_tolerance: float = DRIFT_TOLERANCE,
) -> HybridRun:
    """Run the chain with its actuated joints following (x, ẋ, ẍ) and its free freedoms
    integrated forward (module docstring), with the loads along the motion.

    Args:
        dyn: The chain's dynamics; its actuated joints are the prescribed ones; its ``base``, if
            any, moves (module docstring: q and the table relative to it).
        t: The table's increasing times [s], (N,), N ≥ 2.
        x, dx, ddx: The actuated joints' coordinates [rad, m], rates and accelerations, (N, n),
            columns in the order of ``dyn.actuated``.
        q_start: A closed pose (nq,) on the branch wanted (the assembled pose): its actuated
            joints are moved to x[0] by continuation, then its free freedoms come to rest.
        method, rtol, atol: SciPy's integrator (one of
            :data:`~feeder.chain.dynamics.forward.METHODS`) and its tolerances.
        rate: Baumgarte's rate ω [1/s]; drift_tolerance: the gap [m, rad] that triggers a
            projection.

    Raises:
        InputError: Bad arrays or settings, a hull table that does not cover t, no free freedom
            that carries mass (then the motion table determines the motion:
            :func:`~feeder.chain.track`).
        UnreachablePoseError: The loops do not close at the first sample.
        IntegrationError: The integrator failed, the run could not be projected back, or the
            loads cannot be computed (the message names the time).
    """
    check_dynamics(dyn)
    chain = dyn.chain
    n = len(dyn.actuated)
    t = check_finite("t [s]", t)
    if t.ndim != 1 or t.size < 2 or np.any(np.diff(t) <= 0.0):
        raise InputError(f"t must be increasing times, at least two, got shape {t.shape}")
    check_sample_count("t", t.size, chain.model.nv)
    x, dx, ddx = (check_samples(name, a, n) for name, a in (("x", x), ("dx", dx), ("ddx", ddx)))
    if not x.shape[0] == dx.shape[0] == ddx.shape[0] == t.size:
        raise InputError(f"x, dx, ddx must have one row per time ({t.size})")
    if method not in METHODS:
        raise InputError(f"method must be one of {list(METHODS)}, got {method!r}")
    for name, value in (("rtol", rtol), ("atol", atol), ("drift_tolerance", drift_tolerance)):
        if not check_number(name, value) > 0.0:
            raise InputError(f"{name} must be > 0, got {value!r}")
    if rtol < SMALLEST_RTOL:
        raise InputError(f"rtol must be at least {SMALLEST_RTOL:.1e}, got {rtol:g}")
    if not check_number("rate [1/s]", rate) >= 0.0:
        raise InputError(f"rate must be ≥ 0 [1/s], got {rate!r}")
    dyn.elements.check_covers(float(t[0]), float(t[-1]))
    gravity = None
    if dyn.base is not None:  # a hull table that does not cover the run: refused before it
        level = chain.model.gravity.linear
        gravity = dyn.base.state(t[[0, -1]], level).gravity[0]
    first = _first_sample(dyn, chain.check_q(q_start), x[0])
    free = free_freedoms(dyn, first)
    if not len(free):
        raise InputError(
            "the actuated joints leave no freedom that carries mass: the motion table "
            "determines the motion (feeder.chain.track, inverse_dynamics)"
        )
    equations = HybridEquations(dyn, free, Prescribed(t, x, dx, ddx), rate)
    q0 = rest_pose(dyn, first, free, float(t[0]), gravity)
    y0 = equations.project(t[0], np.concatenate([q0, np.zeros(chain.model.nv + len(free))]))
    states, steps, projections = _integrate(equations, t, y0, method, rtol, atol, drift_tolerance)
    settings = f"{method}, rtol {rtol:g}, atol {atol:g}, Baumgarte rate {rate:g} /s"
    counts = (steps, projections)
    return _results(equations, t, states, counts, y0[: chain.model.nq], settings, gravity)


def _first_sample(dyn: ChainDynamics, q: np.ndarray, x0: np.ndarray) -> np.ndarray:
    """``q`` with its actuated joints moved to ``x0`` in steps of at most
    :data:`~feeder.chain.assembly.continuation.MOUNT_STEP`, the loops closed after each by
    minimum-norm Newton over the other coordinates (the free freedoms keep their place)."""
    partition = dyn.partition
    start = partition.independent_values(q)
    steps = max(1, int(np.ceil(np.abs(x0 - start).max(initial=0.0) / MOUNT_STEP)))
    for k in range(1, steps + 1):
        moved = partition.with_independent(q, start + (x0 - start) * k / steps)
        q, norm = newton(dyn.chain, moved, partition.dependent)
        if norm > POSITION_TOLERANCE * 1e3:
            raise UnreachablePoseError(
                f"the loops do not close with the actuated joints at the motion's first sample "
                f"(gap {norm:.3e})"
            )
    return q


def _integrate(equations: HybridEquations, t, y0, method, rtol, atol, drift_tolerance):
    """The states (N, len(y0)) at the times t, the accepted steps and the projections."""
    import scipy.integrate  # here: only hybrid runs pay its import (~0.13 s)

    solver_class = getattr(scipy.integrate, method)
    nq = equations.nq

    def start(time: float, y: np.ndarray, first_step: float | None):
        return solver_class(equations, time, y, t[-1], rtol=rtol, atol=atol, first_step=first_step)

    states = np.empty((t.size, y0.size))
    states[0] = y0
    k, steps, projections = 1, 0, 0
    solver = start(t[0], y0, None)
    while k < t.size:
        if steps >= MAX_STEPS:
            raise IntegrationError(step_cap_message(solver.t, t[-1], ""))
        if equations.moving is not None:  # the base's motion at the step's times in one pass
            equations.moving.prepare(stage_times(solver))
        message = solver.step()
        steps += 1
        if solver.status == "failed":
            raise IntegrationError(
                f"the integrator ({method}) stopped at t = {solver.t:.6g} s: {message}"
            )
        if t[k] <= solver.t:
            dense = solver.dense_output()
            while k < t.size and t[k] <= solver.t:
                states[k] = dense(t[k])
                k += 1
        if k == t.size:
            break
        if equations.gap(solver.t, solver.y[:nq]) > drift_tolerance:
            y = equations.project(solver.t, solver.y)
            projections += 1
            solver = start(solver.t, y, min(solver.step_size, t[-1] - solver.t))
    return states, steps, projections


def _results(equations: HybridEquations, t, states, counts, start, settings, gravity) -> HybridRun:
    """The run's samples projected, their accelerations and loads (module docstring)."""
    nq, nv = equations.nq, equations.nv
    residual = np.array([equations.gap(time, y[:nq]) for time, y in zip(t, states, strict=True)])
    projected = np.array([equations.project(time, y) for time, y in zip(t, states, strict=True)])
    q, v = projected[:, :nq], projected[:, nq : nq + nv]
    a = np.array([equations.accelerations(*sample)[0] for sample in zip(t, q, v, strict=True)])
    try:
        loads = inverse_dynamics(equations.dyn, q, v, a, t=t)
    except (SingularPoseError, InputError) as exc:
        raise IntegrationError(f"the hybrid run's loads cannot be computed: {exc}") from exc
    return HybridRun(
        t=t,
        q=q,
        v=v,
        a=a,
        loads=loads,
        free=equations.free,
        start=start,
        travel=projected[:, nq + nv :],
        residual=residual,
        steps=counts[0],
        evaluations=equations.count,
        projections=counts[1],
        settings=settings,
        idle=equations.accelerations(t[0], q[0], v[0])[1].shape[1] - len(equations.free),
        gravity=gravity,
    )
