"""Forward runs of any closed chain, with error control.

The state (q, q̇) and the work of the non-conservative forces follow the closed chain's index-1
equations with Baumgarte's corrector (:mod:`~feeder.chain.dynamics.forward_equations`); the
result is a :class:`~feeder.chain.dynamics.forward_run.ForwardRun`.

On a moving base (a :class:`ChainDynamics` with a ``base``) q, q̇, q̈ are the motion relative to
the base, as in the inverse dynamics, and the hull enters as a moving root whose fictitious
forces change the equations' bias (:mod:`~feeder.chain.dynamics.forward_base`); the state gains
the base's work, the energies are the absolute motion's, and the loads' mount wrench is the
base's support on the mechanism at every sample. An actuation may be a
:class:`~feeder.chain.dynamics.forward_equations.Controller`, whose states are integrated with
the run's (y = (q, q̇, W, x[, W_B])).

Integration: SciPy's adaptive Runge–Kutta or implicit methods (``DOP853`` by default, ``Radau``
or ``BDF`` for stiff mechanisms — stiff springs), stepped one step at a time with the user's
``rtol`` / ``atol``; the results on the caller's time grid come from each step's dense output.
Drift control: Baumgarte always, and a projection of (q, q̇) back onto the position and velocity
constraints (:func:`~feeder.chain.dynamics.projection.project`) whenever an accepted step
leaves the loops open, or a quaternion off unit length, by more than ``drift_tolerance`` (the
integrator then restarts from the projected state).

Singular poses, two choices (``singular``). ``"stop"`` (the default of a driven run): after every
accepted step the condition number of the equations of the loads ([Sᵀ Jᵀ],
:func:`~.loads_solve.load_gain`) is checked against :data:`~.loads_solve.MAX_FORCE_GAIN`, the most
the inverse dynamics of the samples accept: a run that passes it (a toggle, a dead centre ahead,
where the closure forces grow without bound and the steps shrink) stops there with an
:class:`IntegrationError` naming the time, rather than crawl through the pose and have its
samples refused after the whole run. ``"pass"`` (the default of an undriven run): the run goes
through the singular positions of the closure on the branch its motion carries
(:mod:`~feeder.chain.dynamics.singular`): the closure's rank margin is watched on the dense
output and each rank drop listed with its time; the step that would carry the margin past
the coast's threshold is shortened to end inside it (:meth:`~.singular.RankWatch.landing`: a
step never crosses the pose on the equations); next to the pose every step is projected back
onto the constraints (a velocity off the branch is invisible to the drift test there and grows
like the inverse of the margin), and the last stretch, where the constrained equations are too
ill-conditioned to be trusted, is crossed by the motion's Taylor expansion from the equations
just before it (an index reduction onto the motion itself: no regularisation of the collapsing
directions is needed, and the expansion's error is measured by the projection at its end). The
samples whose loads are indeterminate there are flagged and given zero loads; the others are
solved as usual.
The work of the non-conservative forces (drives, dampers, pushes, pressures, loads) is
integrated with the state, so the energy balance E(t) − E(t₀) = W(t) checks the run to the
integrator's tolerance.

Results: the output samples (:mod:`~feeder.chain.dynamics.forward_samples`): each sample's
state, projected where the run left its loops open, its accelerations, the loads of the sampled
motion and the energies; or, for a run asked for its motion alone (``loads=False``), the states
and the actuation only.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable

import numpy as np
import pinocchio as pin

from ...exceptions import FeederWarning, InputError, UnreachablePoseError
from ...validation import check_finite, check_number
from ..blas import one_blas_thread
from . import budget
from .budget import (
    Progress,
    check_sample_count,
    check_step_count,
    step_cap_message,
)
from .forward_base import stage_times
from .forward_equations import (
    BAUMGARTE_RATE,
    EMPTY,
    Actuation,
    Controller,
    ForwardEquations,
    IntegrationError,
)
from .forward_run import ForwardRun
from .forward_samples import results
from .inverse import ChainDynamics, check_dynamics
from .loads_solve import MAX_FORCE_GAIN, load_gain, load_rank
from .projection import project
from .singular import MODES, RankWatch, coast
from .stiffness import StiffnessTest, step_advice, stiff_warning

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

EXPLICIT = ("DOP853", "RK45")
"""The explicit methods among :data:`METHODS`: their equations are evaluated at the nearest unit
circles and quaternions (:mod:`~feeder.chain.dynamics.forward_equations`)."""

METHODS = ("DOP853", "RK45", "Radau", "BDF")
"""SciPy's integrators the runs can use: explicit Runge–Kutta pairs of order 8(5,3) and 5(4), and
the implicit Radau IIA (order 5) and BDF for stiff mechanisms. Through a singular position
(``singular="pass"``) DOP853, RK45 and Radau carry the N-four-bar at the default tolerances
(tests/chain/test_iftomm.py); BDF restarts at first order after each of the projections made
near the pose, and its state there errs beyond the crossing's limits (1.2e-8 m against
:data:`~feeder.chain.dynamics.singular.COAST_POSITION`): the run stops there, naming the time."""


@one_blas_thread
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
    singular: str | None = None,
    loads: bool = True,
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
        q0, v0: Initial state (nq,), (nv,), closed (e.g. Partition.mount; v0 from given joint
            rates: :func:`~feeder.chain.assembly.rates.initial_rates`).
        actuation: u(t, q, q̇) → the actuated joints' forces (n_actuated,), a
            :class:`~.forward_equations.Controller` (an actuation with states of its own,
            integrated with the run's), or None.
        method: One of :data:`METHODS`.
        rtol, atol: The integrator's tolerances (> 0; rtol ≥ :data:`SMALLEST_RTOL`).
        rate: Baumgarte rate ω [1/s] (0 ≤ ω ≤ :data:`MAX_BAUMGARTE_RATE`; 0 turns the
            corrector off).
        drift_tolerance: Closure residual [m, rad] that triggers a projection (> 0).
        max_step: Longest step [s] (> 0).
        progress: Show a progress line with an estimate of the time left on a terminal (none
            when stderr is not one) for a run longer than a few seconds.
        singular: At a singular position (:mod:`~feeder.chain.dynamics.singular`): ``"pass"``
            through it (the run lists the instants, and flags the samples whose loads are
            indeterminate there), or ``"stop"`` there (an :class:`IntegrationError` naming the
            time; the module docstring). Default: pass for a passive run (no actuation, or no
            actuated joint), stop for a driven one.
        loads: Compute the samples' accelerations, the loads of the sampled motion and the
            energies (:mod:`~feeder.chain.dynamics.forward_samples`); False: the motion alone,
            the run's ``a``, ``loads``, ``energy`` and ``kinetic`` None (a controller's study).

    Raises:
        InputError: Bad dynamics, times, state, actuation or settings, more output times than
            the cap, an initial velocity that opens the loops, a force table that does not
            cover the run, a hull table that does not, actuation values that are not finite
            numbers, a controller whose states or rates are not its n_states finite numbers.
        UnreachablePoseError: An initial configuration that does not close the loops.
        IntegrationError: The integrator failed (unbounded accelerations), the run reached a
            singular pose (module docstring) or the step cap; the message names the time.
    """
    check_dynamics(dyn)
    chain = dyn.chain
    t = _check_times(t, chain.model.nv)
    q, v = chain.check_q(q0), chain.check_v("v0", v0)
    if actuation is not None and not callable(actuation):
        raise InputError(
            f"actuation must be a function u(t, q, v), a Controller or None, got {actuation!r}"
        )
    x0 = _controller_start(actuation, float(t[0]), q, v)
    if method not in METHODS:
        raise InputError(f"method must be one of {list(METHODS)}, got {method!r}")
    if singular is None:
        singular = "pass" if actuation is None or not dyn.columns else "stop"
    if singular not in MODES:
        raise InputError(f"singular must be one of {list(MODES)}, got {singular!r}")
    if not isinstance(loads, bool):
        raise InputError(f"loads must be True or False, got {loads!r}")
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
        raise InputError(
            f"v0 opens the loops at {opening:.3e} per second: close it with "
            "feeder.chain.initial_rates (or Partition.velocity)"
        )
    dyn.elements.check_covers(float(t[0]), float(t[-1]))
    if dyn.base is not None:  # a hull table that does not cover the run: refused before it
        dyn.base.state(t[[0, -1]], chain.model.gravity.linear)
    equations = ForwardEquations(dyn, actuation, rate, normalize=method in EXPLICIT)
    y0 = np.concatenate([q, v, [0.0], x0, [0.0] if equations.moving else []])
    with Progress(float(t[0]), float(t[-1]), progress) as line:
        watch = RankWatch(chain, q, chain.model.nq) if singular == "pass" else None
        states, steps, projections = _integrate(
            equations, t, y0, method, rtol, atol, drift_tolerance, max_step, line, watch
        )
    if watch is not None:
        watch.finish()
    return results(
        equations, t, states, steps, projections, progress, watch, drift_tolerance, loads
    )


def _controller_start(
    actuation: Actuation | Controller | None, t0: float, q0: np.ndarray, v0: np.ndarray
) -> np.ndarray:
    """A :class:`Controller`'s states at the start (n_states,), checked (none for an actuation
    without states)."""
    if not isinstance(actuation, Controller):
        return EMPTY
    n = actuation.n_states
    if not (isinstance(n, int | np.integer) and not isinstance(n, bool) and n >= 0):
        raise InputError(f"a controller's n_states must be a whole number ≥ 0, got {n!r}")
    x0 = check_finite("the controller's initial states", actuation.start(t0, q0.copy(), v0.copy()))
    if x0.shape != (n,):
        raise InputError(
            f"the controller's initial states must be {n} finite numbers (n_states), got {x0!r}"
        )
    return x0


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


def _integrate(equations, t, y0, method, rtol, atol, drift_tolerance, max_step, line, watch):
    """The states (N, nq + nv + 1) at the times t, the accepted steps and the projections;
    ``line``: the run's :class:`~feeder.chain.dynamics.budget.Progress`; ``watch``: the
    :class:`~feeder.chain.dynamics.singular.RankWatch` of a run that passes singular positions,
    or None for one that stops at them."""
    chain = equations.dyn.chain
    nq = equations.model.nq
    import scipy.integrate  # here: only forward runs pay its import (~0.13 s)

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
    if watch is None and load_gain(equations.dyn, y0[:nq], rank) > MAX_FORCE_GAIN:
        raise _singular(equations, rank, t[0], t[0], lambda _: y0)
    solver = start(t[0], y0, None)
    while k < t.size:
        if steps >= budget.MAX_STEPS:
            advice = step_advice(equations.dyn, stiffness, solver, (solver.t - t[0]) / steps)
            raise IntegrationError(step_cap_message(solver.t, t[-1], advice))
        if equations.moving is not None:  # the base's motion at the step's times in one pass
            equations.moving.prepare(stage_times(solver))
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
        dense = solver.dense_output()
        if watch is not None:
            watch.step(solver.t_old, solver.t, dense)
        elif load_gain(equations.dyn, solver.y[:nq], rank) > MAX_FORCE_GAIN:
            raise _singular(equations, rank, solver.t_old, solver.t, dense)
        if t[k] <= solver.t:  # the step passed output times: its dense output gives them
            end = int(np.searchsorted(t, solver.t, side="right"))
            states[k:end] = dense(t[k:end]).T  # all at once (12 µs a call, measured)
            k = end
        if k == t.size:
            break
        y = solver.y
        tau = None if watch is None else watch.approach()
        if tau is not None:  # a singular position ahead: cross it by the motion's expansion
            path, y = coast(equations, solver.t, y, tau, t[-1], project)
            watch.step(path.t_min, path.t_max, path)
            while k < t.size and t[k] <= path.t_max:
                states[k] = path(t[k])
                k += 1
            projections += 1
            if k == t.size:  # the coast reached the run's end
                break
            solver = start(path.t_max, y, min(solver.step_size, t[-1] - path.t_max))
            continue
        residual = float(np.abs(chain.residual(y[:nq])).max(initial=0.0))
        unit = equations.rate is None or pin.isNormalized(equations.model, y[:nq], drift_tolerance)
        near = watch is not None and watch.near()  # near a singular position: every step
        proposed = solver.h_abs  # the next step's length, as SciPy's step control chose it
        first = None
        if residual > drift_tolerance or not unit or near:  # loops open, quaternions off unit
            y = project(equations.dyn.chain, y)
            projections += 1
            # near a singular position every step restarts, its length as the integrator's
            # own control would make it
            first = proposed if near else solver.step_size
        land = None if watch is None else watch.landing(first or proposed)
        if land is not None:  # a singular position ahead: end the next step before it
            first = land
        if first is not None:
            solver = start(solver.t, y, min(first, t[-1] - solver.t))
    return states, steps, projections


def _singular(
    equations, rank: int, start: float, end: float, state: Callable[[float], np.ndarray]
) -> IntegrationError:
    """The error of a run that reaches a singular pose in its step from ``start`` to ``end``
    [s] (``state``: the step's state at a time, its dense output; ``start == end``: at the
    start of the run): the loads' equations there have a condition number above
    :data:`~feeder.chain.dynamics.loads_solve.MAX_FORCE_GAIN`, which
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
