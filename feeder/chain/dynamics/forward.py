"""Forward runs of any closed chain, with error control.

The state (q, q̇) follows the index-1 equations of the closed chain

    [M  Jᵀ] [ q̈]   [τ − b          ]
    [J  0 ] [−λ] = [−J̇ q̇ − K_d J q̇ − K_p r(q)]

with τ = Sᵀ u(t, q, q̇) (the actuated joints' drive, given by the caller) plus the force elements'
generalized forces (:mod:`~feeder.chain.dynamics.elements`), b the Coriolis, centrifugal and
gravity terms, and Baumgarte's corrector K_p = ω², K_d = 2ω on the loop residual r (critically
damped: an error decays like e^(−ω t)). The accelerations come from Pinocchio's
``constraintDynamics`` on the chain's own constraint models (its proximal solver takes the
redundant rows of a planar loop); q̇ from q̇ (the rotations' and the unit circles' rates for the
joints whose q is not a vector: :class:`~feeder.chain.kinematics.joints.ConfigurationRate`).

Integration: SciPy's adaptive Runge–Kutta or implicit methods (``DOP853`` by default, ``Radau``
or ``BDF`` for stiff mechanisms — stiff springs), stepped one step at a time with the user's
``rtol`` / ``atol``; the results on the caller's time grid come from each step's dense output.
Drift control: Baumgarte always, and a projection of (q, q̇) back onto the position and velocity
constraints (minimum-norm Newton over every coordinate, then J q̇ = 0) whenever an accepted step
leaves the loops open, or a quaternion off unit length, by more than ``drift_tolerance`` (the
integrator then restarts from the projected state). Singular poses: after every accepted step
the condition number of the equations of the loads ([Sᵀ Jᵀ], :func:`~.inverse.load_gain`) is
checked against :data:`~.inverse.MAX_FORCE_GAIN`, the most the inverse dynamics of the samples
accept: a run that passes it (a toggle, a dead centre ahead, where the closure forces grow
without bound and the steps shrink) stops there with an :class:`IntegrationError` naming the
time, rather than crawl through the pose and have its samples refused after the whole run.
The work of the non-conservative forces (drives, dampers, pushes, pressures, loads) is
integrated with the state, so the energy balance E(t) − E(t₀) = W(t) checks the run to the
integrator's tolerance.

Results: every output sample is projected onto the constraints (the drift before the projection
is reported), its accelerations evaluated, and the inverse dynamics of the sampled motion give the
closure forces, the drive loads (equal to the applied ones: a check), every joint's reaction and
every force element's force, like the tables of ``feeder analyze``.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pinocchio as pin
import scipy.integrate

from ...exceptions import (
    FeederError,
    FeederWarning,
    InputError,
    SingularPoseError,
    UnreachablePoseError,
)
from ...validation import check_finite, check_number
from ..assembly.newton import POSITION_TOLERANCE, RANK_TOLERANCE, newton
from ..assembly.rank import truncated_inverse
from ..kinematics.joints import ConfigurationRate, angle_columns, angular_difference
from . import budget
from .budget import (
    Progress,
    check_sample_count,
    check_step_count,
    sample_progress,
    step_cap_message,
)
from .inverse import (
    MAX_FORCE_GAIN,
    ChainDynamics,
    ChainLoads,
    check_dynamics,
    inverse_dynamics,
    load_gain,
    load_rank,
)
from .stiffness import StiffnessTest, step_advice, stiff_warning

BAUMGARTE_RATE = 20.0
"""Default Baumgarte rate ω [1/s]: a loop error decays in 1/ω = 50 ms, fast compared with a
mechanism's motion and slow enough not to make the equations stiff."""

MAX_BAUMGARTE_RATE = 1e6
"""Largest accepted Baumgarte rate ω [1/s]. Its K_p = ω² (1e12 /s² here) multiplies the loop
residual into an acceleration: a residual at round-off (1e-13 m) becomes 0.1 m/s², the size of a
slow motion's accelerations, so a faster corrector drives the motion instead of correcting it
(and it makes the equations stiff at ω: an explicit step of at most 6/ω = 6 µs)."""

START_TOLERANCE = 1e-9
"""Largest accepted closure residual [m, rad] of the initial state (and of its velocity rows,
per second): assembly closes loops to ~1e-13; 1e-9 leaves room for rounded data."""

RTOL, ATOL = 1e-8, 1e-10
"""Default relative and absolute tolerances of the integrator (per step, on q [rad, m], q̇ and
the work [J])."""

SMALLEST_RTOL = 100.0 * float(np.finfo(float).eps)
"""Smallest accepted rtol (≈ 2.2e-14): SciPy's integrators raise a smaller one to this, with a
warning only, and the run's record would then claim a tolerance it was not run at."""

DRIFT_TOLERANCE = 1e-10
"""Default closure residual [m, rad] above which an accepted step is projected back onto the
constraints (Baumgarte alone keeps ~1e-11 at the default tolerances)."""

METHODS = ("DOP853", "RK45", "Radau", "BDF")
"""SciPy's integrators the runs can use: explicit Runge–Kutta pairs of order 8(5,3) and 5(4), and
the implicit Radau IIA (order 5) and BDF for stiff mechanisms."""

PROXIMAL = pin.ProximalSettings(1e-13, 1e-10, 100)
"""Pinocchio's proximal solver: absolute accuracy 1e-13 of the constraint accelerations,
regularisation μ = 1e-10 (positive: the redundant rows of a planar loop), at most 100 iterations
(1–3 are used)."""

Actuation = Callable[[float, np.ndarray, np.ndarray], np.ndarray]
"""u(t, q, q̇): the actuated joints' generalized forces [N or N·m] at time t [s], (n_actuated,)."""


class IntegrationError(FeederError):
    """A forward run stopped: the integrator could not meet its tolerance (a singular pose, an
    unbounded acceleration), the run reached a singular pose where its loads cannot be computed,
    or the forces became NaN."""


@dataclass(frozen=True)
class ForwardRun:
    """A forward run on the caller's time grid.

    Attributes:
        t: Times [s], (N,).
        q: Configurations, (N, nq) (projected onto the constraints).
        v: Velocities, (N, nv). a: Accelerations, (N, nv).
        loads: The inverse dynamics of the sampled motion: the drive loads (the applied ones),
            closure forces, every joint's reaction, every force element's force.
        residual: Closure residual [m, rad] of each sample before its projection, (N,): the drift.
        energy: Kinetic, gravitational and elastic energy [J], (N,).
        kinetic: Kinetic energy [J], (N,).
        work: Work of the non-conservative forces since t[0] [J], (N,).
        steps: Accepted integration steps. evaluations: Right-hand sides evaluated.
        projections: Steps projected back onto the constraints.
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    loads: ChainLoads
    residual: np.ndarray
    energy: np.ndarray
    kinetic: np.ndarray
    work: np.ndarray
    steps: int
    evaluations: int
    projections: int

    def drift(self) -> float:
        """Largest closure residual over the run before projection [m, rad]."""
        return float(self.residual.max())

    def balance(self) -> np.ndarray:
        """E(t) − E(t₀) − W(t) [J], (N,): zero for an exact run."""
        return self.energy - self.energy[0] - self.work

    def energy_error(self) -> float:
        """Largest |E(t) − E(t₀) − W(t)| [J] (:meth:`balance`)."""
        return float(np.abs(self.balance()).max())

    def energy_scales(self) -> dict[str, float]:
        """The energies [J] the run moves, against which its balance is measured: the largest
        kinetic energy, |work| and |change of the potential (gravitational and elastic)
        energy| over the run, and the round-off of the total energy (ε max |E|, the floor)."""
        potential = self.energy - self.kinetic
        return {
            "kinetic energy": float(self.kinetic.max()),
            "|work|": float(np.abs(self.work).max()),
            "|change of potential energy|": float(np.abs(potential - potential[0]).max()),
            "round-off of the energy": float(np.finfo(float).eps * np.abs(self.energy).max()),
        }

    def displacement(self, model: pin.Model) -> float:
        """Largest |q(t) ⊖ q(t₀)| over the run and the velocity components [rad, m]
        (:meth:`tracking` against the first sample)."""
        return float(self.tracking(model, np.tile(self.q[0], (self.t.size, 1))).max())

    def tracking(self, model: pin.Model, q_reference: np.ndarray) -> np.ndarray:
        """Largest |q ⊖ q_reference| of every velocity component over the run, (nv,) (a
        revolute angle wrapped by a turn, a quaternion of opposite sign, count as equal)."""
        reference = check_finite("q_reference", q_reference)
        if reference.shape != self.q.shape:
            raise InputError(f"q_reference must have shape {self.q.shape}, got {reference.shape}")
        angles = angle_columns(model)
        pairs = zip(reference, self.q, strict=True)
        gaps = [angular_difference(model, r, q, angles) for r, q in pairs]
        return np.abs(np.array(gaps)).max(axis=0)


class _Equations:
    """The right-hand side of the run (module docstring) on one pinocchio.Data."""

    def __init__(self, dyn: ChainDynamics, actuation: Actuation | None, rate: float):
        chain, model = dyn.chain, dyn.chain.model
        self.model, self.dyn, self.actuation = model, dyn, actuation
        self.data = model.createData()
        self.constraints = pin.StdVec_RigidConstraintModel()
        for constraint in chain.constraint_models:
            copy = pin.RigidConstraintModel(constraint)
            copy.m_baumgarte_parameters.Kp = rate**2
            copy.m_baumgarte_parameters.Kd = 2.0 * rate
            self.constraints.append(copy)
        self.datas = pin.StdVec_RigidConstraintData()
        for constraint in self.constraints:
            self.datas.append(constraint.createData())
        pin.initConstraintDynamics(model, self.data, self.constraints, self.datas)
        self.nq, self.nv = model.nq, model.nv
        self.rate = None if model.nq == model.nv else ConfigurationRate(model)
        self.columns = np.array(dyn.columns, dtype=int)
        self.zero = np.zeros(model.nv)
        self.count = 0

    def forces(self, t: float, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, float]:
        """τ (nv,) and the power [W] of the non-conservative forces."""
        elements = self.dyn.elements
        if self.actuation is None:
            return elements.generalized(q, v, t) if elements else (self.zero, 0.0)
        tau = np.zeros(self.model.nv)
        u = check_finite(f"actuation at t = {t:.6g} s [N or N·m]", self.actuation(t, q, v))
        if u.shape != self.columns.shape:
            raise InputError(
                f"actuation at t = {t:.6g} s must be {self.columns.size} finite numbers "
                f"[N or N·m], got {u!r}"
            )
        tau[self.columns] = u
        power = float(u @ v[self.columns])
        if elements:
            generalized, element_power = elements.generalized(q, v, t)
            tau += generalized
            power += element_power
        return tau, power

    def accelerations(self, t: float, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, float]:
        tau, power = self.forces(t, q, v)
        a = pin.constraintDynamics(
            self.model, self.data, q, v, tau, self.constraints, self.datas, PROXIMAL
        )
        return a, power

    def __call__(self, t: float, y: np.ndarray) -> np.ndarray:
        self.count += 1
        nq, nv = self.nq, self.nv
        q, v = y[:nq], y[nq : nq + nv]
        a, power = self.accelerations(t, q, v)
        if not np.all(np.abs(a) < 1e154):  # NaN, inf, or as meaningless (a @ a would overflow)
            raise IntegrationError(
                f"the accelerations are not finite at t = {t:.6g} s (a singular pose, or forces "
                "that are not finite)"
            )
        out = np.empty(nq + nv + 1)
        out[:nq] = v if self.rate is None else self.rate(q, v)
        out[nq:-1] = a
        out[-1] = power
        return out


def simulate(
    dyn: ChainDynamics,
    t: np.ndarray,
    q0: np.ndarray,
    v0: np.ndarray,
    actuation: Actuation | None = None,
    *,
    method: str = "DOP853",
    rtol: float = RTOL,
    atol: float = ATOL,
    rate: float = BAUMGARTE_RATE,
    drift_tolerance: float = DRIFT_TOLERANCE,
    max_step: float = np.inf,
    progress: bool = False,
) -> ForwardRun:
    """Run the closed chain forward from (q0, v0), results at the times ``t``.

    Every run is bounded (:mod:`~feeder.chain.dynamics.budget`): at most
    :func:`~feeder.chain.dynamics.budget.max_samples` output times (refused before the run) and
    :data:`~feeder.chain.dynamics.budget.MAX_STEPS` integration steps (a ``max_step`` that
    needs more is refused before the run; otherwise the run stops at the cap, naming the time
    it reached). An explicit method whose steps are held by stiffness is told after a few
    dozen steps (:class:`~feeder.exceptions.FeederWarning` naming the force element and the
    implicit method to use: :mod:`~feeder.chain.dynamics.stiffness`).

    Args:
        dyn: The chain's dynamics: its force elements act, its actuated joints receive
            ``actuation``'s forces (none: they are free).
        t: Increasing output times [s], (N,), N ≥ 2; the run starts at t[0].
        q0, v0: Initial state (nq,), (nv,), closed (e.g. Partition.mount / velocity).
        actuation: u(t, q, q̇) → the actuated joints' forces (n_actuated,), or None.
        method: One of :data:`METHODS`.
        rtol, atol: The integrator's tolerances (> 0; rtol ≥ :data:`SMALLEST_RTOL`).
        rate: Baumgarte rate ω [1/s] (0 ≤ ω ≤ :data:`MAX_BAUMGARTE_RATE`; 0 turns the
            corrector off).
        drift_tolerance: Closure residual [m, rad] that triggers a projection (> 0).
        max_step: Longest step [s] (> 0).
        progress: Show a progress line with an estimate of the time left on a terminal (none
            when stderr is not one) for a run longer than a few seconds.

    Raises:
        InputError: Bad dynamics, times, state, actuation or settings, more output times than
            the cap, an initial velocity that opens the loops, a force table that does not
            cover the run, actuation values that are not finite numbers, a chain on a moving or
            tilted base (:class:`ChainDynamics` with a base).
        UnreachablePoseError: An initial configuration that does not close the loops.
        IntegrationError: The integrator failed (unbounded accelerations), the run reached a
            singular pose (module docstring) or the step cap; the message names the time.
    """
    check_dynamics(dyn)
    chain = dyn.chain
    if dyn.base is not None:
        raise InputError(
            "forward runs are on a base at rest: this mechanism's base moves or is tilted "
            "([base]); its inverse dynamics (feeder analyze) take the base's motion, and a "
            "slope alone is a tilted gravity ([mechanism] gravity)"
        )
    t = _check_times(t, chain.model.nv)
    q, v = chain.check_q(q0), chain.check_v("v0", v0)
    if actuation is not None and not callable(actuation):
        raise InputError(f"actuation must be a function u(t, q, v) or None, got {actuation!r}")
    if method not in METHODS:
        raise InputError(f"method must be one of {list(METHODS)}, got {method!r}")
    _check_settings(rtol, atol, rate, drift_tolerance, max_step)
    check_step_count(float(t[-1] - t[0]), max_step)
    gap = float(np.abs(chain.residual(q)).max(initial=0.0))
    if gap > START_TOLERANCE:
        raise UnreachablePoseError(
            f"q0 does not close the loops (residual {gap:.3e} > {START_TOLERANCE:g}): mount it "
            "first (Partition.mount)"
        )
    opening = float(np.abs(chain.jacobian(q) @ v).max(initial=0.0))
    if opening > START_TOLERANCE * max(1.0, float(np.abs(v).max())):
        raise InputError(f"v0 opens the loops at {opening:.3e} per second: use Partition.velocity")
    dyn.elements.check_covers(float(t[0]), float(t[-1]))
    equations = _Equations(dyn, actuation, rate)
    y0 = np.concatenate([q, v, [0.0]])
    with Progress(float(t[0]), float(t[-1]), progress) as line:
        states, steps, projections = _integrate(
            equations, t, y0, method, rtol, atol, drift_tolerance, max_step, line
        )
    return _results(equations, t, states, steps, projections, progress)


def _check_times(t: np.ndarray, nv: int) -> np.ndarray:
    """The output times as a float array: increasing, at least two, at most the cap of
    :func:`~feeder.chain.dynamics.budget.max_samples`, over a finite span."""
    t = check_finite("t", t)
    if t.ndim != 1 or t.size < 2:
        raise InputError(f"t must be increasing output times, at least two, got shape {t.shape}")
    check_sample_count("t", t.size, nv)
    with np.errstate(over="ignore"):
        gaps = np.diff(t)
    if np.any(gaps <= 0.0):
        raise InputError(f"t must be increasing output times, at least two, got shape {t.shape}")
    if not math.isfinite(float(t[-1]) - float(t[0])):
        raise InputError(f"t spans {t[0]:g} to {t[-1]:g} s: its length is not a finite number")
    return t


def _check_settings(
    rtol: float, atol: float, rate: float, drift_tolerance: float, max_step: float
) -> None:
    """Refuse tolerances, a Baumgarte rate or a longest step out of their ranges
    (:func:`simulate`)."""
    for name, value in (("rtol", rtol), ("atol", atol), ("drift_tolerance", drift_tolerance)):
        if not check_number(name, value) > 0.0:
            raise InputError(f"{name} must be > 0, got {value!r}")
    if rtol < SMALLEST_RTOL:
        raise InputError(
            f"rtol {rtol:g} is below what double precision can meet ({SMALLEST_RTOL:.1e}, "
            "100 × the machine epsilon, where SciPy's integrators would raise it silently)"
        )
    if not 0.0 <= check_number("rate (Baumgarte's) [1/s]", rate) <= MAX_BAUMGARTE_RATE:
        raise InputError(
            f"rate (Baumgarte's) must be ≥ 0 and ≤ {MAX_BAUMGARTE_RATE:g} [1/s], got {rate!r}"
        )
    if max_step != np.inf and not check_number("max_step [s]", max_step) > 0.0:  # inf: no limit
        raise InputError(f"max_step must be > 0 [s], got {max_step!r}")


def _integrate(equations, t, y0, method, rtol, atol, drift_tolerance, max_step, line):
    """The states (N, nq + nv + 1) at the times t, the accepted steps and the projections;
    ``line``: the run's :class:`~feeder.chain.dynamics.budget.Progress`."""
    chain = equations.dyn.chain
    nq = equations.model.nq
    solver_class = getattr(scipy.integrate, method)

    def start(time: float, y: np.ndarray, first_step: float | None):
        return solver_class(
            equations, time, y, t[-1], rtol=rtol, atol=atol, max_step=max_step,
            first_step=first_step,
        )  # fmt: skip

    states = np.empty((t.size, y0.size))
    states[0] = y0
    k, steps, projections = 1, 0, 0
    stiffness = StiffnessTest(method)
    rank = load_rank(equations.dyn, y0[:nq])
    if load_gain(equations.dyn, y0[:nq], rank) > MAX_FORCE_GAIN:
        raise _singular(equations, rank, t[0], t[0], lambda _: y0)
    solver = start(t[0], y0, None)
    while k < t.size:
        if steps >= budget.MAX_STEPS:
            advice = step_advice(equations.dyn, stiffness, solver, (solver.t - t[0]) / steps)
            raise IntegrationError(step_cap_message(solver.t, t[-1], advice))
        message = solver.step()
        steps += 1
        if solver.status == "failed":
            raise IntegrationError(
                f"the integrator ({solver_class.__name__}) stopped at t = {solver.t:.6g} s: "
                f"{message} — the mechanism is at or near a singular pose (a toggle), or its "
                "equations are stiff (try method='Radau')"
            )
        if stiffness.check(solver):
            warning = stiff_warning(equations.dyn, stiffness, solver)
            warnings.warn(warning, FeederWarning, stacklevel=3)
        line.update(solver.t, steps)
        if load_gain(equations.dyn, solver.y[:nq], rank) > MAX_FORCE_GAIN:
            raise _singular(equations, rank, solver.t_old, solver.t, solver.dense_output())
        if t[k] <= solver.t:  # the step passed output times: its dense output gives them
            dense = solver.dense_output()
            while k < t.size and t[k] <= solver.t:
                states[k] = dense(t[k])
                k += 1
        if k == t.size:
            break
        y = solver.y
        residual = float(np.abs(chain.residual(y[:nq])).max(initial=0.0))
        unit = equations.rate is None or pin.isNormalized(equations.model, y[:nq], drift_tolerance)
        if residual > drift_tolerance or not unit:  # loops open, or quaternions off unit length
            y = _project(equations, y)
            projections += 1
            solver = start(solver.t, y, min(solver.step_size, t[-1] - solver.t))
    return states, steps, projections


def _singular(
    equations, rank: int, start: float, end: float, state: Callable[[float], np.ndarray]
) -> IntegrationError:
    """The error of a run that reaches a singular pose in its step from ``start`` to ``end``
    [s] (``state``: the step's state at a time, its dense output; ``start == end``: at the
    start of the run): the loads' equations there have a condition number above
    :data:`~feeder.chain.dynamics.inverse.MAX_FORCE_GAIN`, which
    :func:`~feeder.chain.dynamics.inverse.inverse_dynamics` would refuse at an output sample
    after the whole run (and near which the run itself crawls: the constraint forces grow
    without bound). The time it is passed is found to 1/1024 of the step by bisection."""
    dyn, nq = equations.dyn, equations.nq
    if end > start:
        for _ in range(10):
            middle = 0.5 * (start + end)
            if load_gain(dyn, state(middle)[:nq], rank) > MAX_FORCE_GAIN:
                end = middle
            else:
                start = middle
    kind = "singular pose (toggle, dead centre)"
    where, remedy = f"reaches a {kind} at t = {end:.6g} s", f"end the run before t = {start:.6g} s"
    if end == start:
        where, remedy = f"starts at or near a {kind}", "start it from another pose"
    return IntegrationError(
        f"the mechanism {where}: the condition number of the equations of its loads passes "
        f"{MAX_FORCE_GAIN:g} there, the limit of their solve (the closure forces and drive "
        f"loads grow without bound near it); {remedy}"
    )


def _project(equations, y: np.ndarray) -> np.ndarray:
    """The state y with (q, q̇) moved onto the position and velocity constraints: the nearest
    closed q (minimum-norm Newton over every coordinate, unit quaternions restored), then the
    minimum-norm change of q̇ that gives J q̇ = 0."""
    chain, model = equations.dyn.chain, equations.model
    nq, nv = model.nq, model.nv
    q = pin.normalize(model, y[:nq].copy())
    q, norm = newton(chain, q, np.arange(nv))
    if norm > POSITION_TOLERANCE * 1e3:
        raise IntegrationError(
            f"the run left the constraints by {norm:.3e} and cannot be projected back: a "
            "singular pose, or tolerances too loose"
        )
    v = y[nq : nq + nv]
    jac = chain.jacobian(q)
    # J⁺ truncated at RANK_TOLERANCE: a redundant row (a planar loop's, Bricard's) is a singular
    # value of round-off size that lstsq's default cut-off (n ε σ_max) may keep, and then J⁺ J = I
    # would project every velocity to zero.
    scale = float(np.abs(jac).max(initial=0.0))
    pinv, _, _ = truncated_inverse(jac, RANK_TOLERANCE * max(scale, 1e-300))
    v = v - pinv @ (jac @ v)
    return np.concatenate([q, v, y[nq + nv :]])


def _results(equations, t, states, steps, projections, progress: bool) -> ForwardRun:
    """The run's tables from the states at the output times (module docstring); ``progress``:
    show the samples' progress line (:func:`~feeder.chain.dynamics.budget.sample_progress`)."""
    dyn, model = equations.dyn, equations.model
    chain = dyn.chain
    nq, nv = model.nq, model.nv
    residual = np.empty(t.size)
    projected = np.empty_like(states)
    a = np.empty((t.size, nv))
    with sample_progress(t.size, progress) as line:
        for k, y in enumerate(states):
            residual[k] = np.abs(chain.residual(y[:nq])).max(initial=0.0)
            projected[k] = _project(equations, y)
            a[k] = equations.accelerations(t[k], projected[k, :nq], projected[k, nq : nq + nv])[0]
            line.update()
    q, v, work = projected[:, :nq], projected[:, nq : nq + nv], projected[:, -1]
    try:
        loads = inverse_dynamics(dyn, q, v, a, t=t)
    except SingularPoseError as exc:
        if exc.sample is None:
            raise IntegrationError(f"the run's loads cannot be computed: {exc}") from exc
        raise IntegrationError(
            f"the run's loads cannot be computed at t = {t[exc.sample]:.6g} s: {exc}; end the "
            f"run before t = {t[exc.sample]:.6g} s"
        ) from exc
    except InputError as exc:
        raise IntegrationError(f"the run's samples are not a consistent motion: {exc}") from exc
    data = equations.data
    pairs = zip(q, v, strict=True)
    kinetic = np.array([pin.computeKineticEnergy(model, data, x, y) for x, y in pairs])
    potential = np.array(
        [pin.computePotentialEnergy(model, data, x) + dyn.elements.energy(x) for x in q]
    )
    return ForwardRun(
        t=t,
        q=q,
        v=v,
        a=a,
        loads=loads,
        residual=residual,
        energy=kinetic + potential,
        kinetic=kinetic,
        work=work,
        steps=steps,
        evaluations=equations.count,
        projections=projections,
    )
