"""Singular positions a forward run passes: the instants where the closure Jacobian J (nc, nv)
loses rank (a parallelogram lying flat, a linkage whose bars line up), found on the integrator's
dense output.

The test: the rank margin σ_r(J) / σ_1(J), with r the closure's rank at the start of the run
(:func:`closure_rank`), at the end of every accepted step; a local minimum of the margin along
the steps (a sample below both neighbours: the three bracket it) is refined on the dense output
of the steps around it (SciPy's bounded Brent search) to :data:`BRACKET` seconds, and it is a
singular instant when the margin there is at most
:data:`SINGULAR_TOLERANCE`. The ranks before and after are counted at the bracket's ends, the
rank there with :data:`SINGULAR_TOLERANCE`. The instants do not depend on where the steps land:
the margin is a continuous function of time on the dense output, and the step sampling only
brackets its minima.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ...exceptions import InputError, SingularPoseError
from ..assembly.rank import rank_tolerance
from ..kinematics.tree import JOINT_FIRST, TreeMotion
from ..model.closure import ClosedChain
from .forward_equations import IntegrationError
from .inverse import ChainDynamics, ChainLoads, inverse_dynamics
from .loads_solve import MAX_FORCE_GAIN, load_gain, load_rank

SINGULAR_TOLERANCE = 1e-6
"""Largest rank margin σ_r/σ_1 of the closure Jacobian at which the pose counts as singular (its
rank dropped): the margin falls like the distance to the singular pose (in radians, or metres
per unit reach), so this is a pose within ~1e-6 of it; above the path error of a run at the
default tolerances (≤ 1e-8) and the bracket's own (:data:`BRACKET` × the rate, ≤ 1e-8), far
below the margin of a mechanism that only approaches such a pose (a near miss by a tenth of a
degree keeps 1e-3). The projection onto the constraints uses the same cut-off
(:func:`~feeder.chain.dynamics.projection.project`)."""

BRACKET = 1e-9
"""Width [s] to which a singular instant is bracketed on the dense output."""

COAST = 1e-2
"""Fraction of the largest rank margin met so far (the mechanism's own conditioning away from
singular poses) below which a run that passes singular positions crosses the rest of the way by
its Taylor expansion (:class:`Coast`) instead of its equations: nearer, the constrained
equations amplify any velocity off the branch like the inverse of the margin, and a
regularisation that bounds them frees the collapsing directions. Measured on the N = 2
four-bar (rtol 1e-10, 20 s, 20 passes, each coast started near :data:`LANDING` of it): B0 errs
at most by 2.3e-6 m with a threshold of 3e-2 (the expansion's truncation), 3.3e-7 m with 1e-2,
5.6e-6 m with 3e-3, 2.0e-5 m with 1e-3 (the equations' amplified error in the derivatives the
expansion starts from)."""

LANDING = 0.5
"""Fraction of :data:`COAST` at which a run that passes singular positions aims the end of the
step before a coast: the step that would carry the margin below it is shortened to end there
(:meth:`RankWatch.landing`), so that a step no longer crosses the pose on the ill-conditioned
equations, nor ends so near it that the coast starts from them; an error of the aim of up to
half the target either way still lands in the coast's window."""

LANDING_FALL = 0.25
"""Smallest fraction of its value to which a shortened step aims the margin
(:meth:`RankWatch.landing`): the margin steepens towards the pose (measured on the N-four-bar:
its local rate extrapolated over a step from 0.13 to the target fell short by 5 %, and the step
crossed the pose), so a far target is reached in steps each of which cuts the margin at most
four-fold."""

SLOPE_STEP = 1e-3
"""Fraction of the last step [s] over which the margin's local rate is differenced on the dense
output (:meth:`RankWatch.slope`): the margin's curvature over it is negligible, and its change
(≥ ~1e-6 of the largest margin) far above the SVD's round-off."""

NEAR = 1e-1
"""Fraction of the largest rank margin met so far below which a run that passes singular
positions projects its state back onto the position and velocity constraints after every step
(not only when it drifts): there a velocity off the branch by Δ opens the velocity constraints
by only the margin times Δ, too little for the drift test to see, while the motion towards the
pose amplifies it like the inverse of the margin; the projection removes it each step, before
it grows."""

COAST_POSITION = 1e-8
"""Largest correction [rad, m] the projection may make at a coast's end (the expansion's error
across the constraints)."""

COAST_VELOCITY = 1e-5
"""Largest correction of the velocities at a coast's end, relative to the largest rate."""

FIT_POINTS = 4
"""Points of the stretch before a coast (its ends and two inner points) at which the equations
give q̈ and the power, whose cubic through them gives their first three derivatives at the
coast's start (q is expanded to fifth order, q̇ and the work to fourth)."""

FIT_RTOL = 1e-12
"""Relative tolerance of the short backward run that gives the fit points (:func:`coast`): the
expansion's derivatives come from differences of q̈ over the stretch, so its states must be
well below the run's own error (≥ 1e-14 relative: double precision's room)."""

MODES = ("pass", "stop")
"""What a run does at a singular position: pass through it, or stop there with an
:class:`~feeder.chain.dynamics.forward_equations.IntegrationError` naming the time."""


@dataclass(frozen=True)
class SingularPass:
    """One singular instant of a run.

    Attributes:
        time: When the closure's rank drops [s], to ± ``precision``.
        precision: Half the width of the bracket [s].
        rank_before, rank_at, rank_after: The closure's rank at the bracket's start, at the
            instant (singular values above :data:`SINGULAR_TOLERANCE` of the largest) and at
            the bracket's end.
        margin: σ_r/σ_1 at the instant (≤ :data:`SINGULAR_TOLERANCE`).
    """

    time: float
    precision: float
    rank_before: int
    rank_at: int
    rank_after: int
    margin: float

    def text(self) -> str:
        """One line for a summary."""
        return (
            f"t = {self.time:.9f} s (± {self.precision:.0e} s): closure rank "
            f"{self.rank_before} → {self.rank_at} → {self.rank_after} (margin {self.margin:.1e})"
        )


def closure_rank(chain: ClosedChain, q: np.ndarray) -> int:
    """The rank of the closure Jacobian at q (nq,): singular values above
    :func:`~feeder.chain.assembly.rank.rank_tolerance`."""
    if chain.nc == 0:
        return 0
    jac = chain.jacobian(q)
    return int(np.sum(np.linalg.svd(jac, compute_uv=False) > rank_tolerance(jac)))


def _values(chain: ClosedChain, q: np.ndarray) -> np.ndarray:
    """The singular values of the closure Jacobian at q (nq,) over the largest, decreasing,
    (min(nc, nv),). Its rows that are identically zero (a planar loop's out-of-plane ones: 40
    of the N = 40 four-bar's 120) change none and are left out of the SVD (half its time)."""
    jac = chain.jacobian(q)
    jac = jac[np.any(jac != 0.0, axis=1)]
    values = np.zeros(min(chain.nc, chain.model.nv))
    if jac.size:
        s = np.linalg.svd(jac, compute_uv=False)
        values[: s.size] = s / max(float(s[0]), 1e-300)
    return values


class RankWatch:
    """The singular instants of a run (module docstring), fed one accepted step at a time.

    Args:
        chain: The closed chain.
        q0: The start pose (nq,): the closure's rank there is the one watched.
        nq: Coordinates of q in the state y = (q, …).
    """

    def __init__(self, chain: ClosedChain, q0: np.ndarray, nq: int):
        self.chain, self.nq = chain, nq
        self.rank = closure_rank(chain, q0)
        self.passes: list[SingularPass] = []
        self.scale = 0.0  # the largest margin met so far
        self._points: list[tuple[float, float]] = []  # (t, margin), the last three
        self._dense: list = []  # the dense outputs of the last two steps
        self._near: list[list[float]] = []  # [start, end] of the stretches near a pose [s]

    def margin(self, t: float) -> float:
        """σ_r/σ_1 of the closure Jacobian on the dense output at time t [s]."""
        dense = next(d for d in reversed(self._dense) if d.t_min <= t <= d.t_max)
        return float(_values(self.chain, dense(t)[: self.nq])[self.rank - 1])

    def near(self) -> bool:
        """Whether the last step ended with the margin below :data:`NEAR`."""
        return bool(self._points) and self._points[-1][1] < NEAR * self.scale

    def near_samples(self, t: np.ndarray) -> np.ndarray:
        """Which of the times t [s] (N,) lie in a step that started or ended with the margin
        below :data:`NEAR` (bool (N,)): where a velocity off the branch hides from a drift
        test."""
        out = np.zeros(t.size, dtype=bool)
        for start, end in self._near:
            out |= (start <= t) & (t <= end)
        return out

    def slope(self) -> float:
        """The margin's rate [1/s] at the last step's end, differenced on its dense output over
        :data:`SLOPE_STEP` of the step."""
        (t0, _), (t1, m1) = self._points[-2:]
        delta = SLOPE_STEP * (t1 - t0)
        return (m1 - self.margin(t1 - delta)) / delta

    def approach(self) -> float | None:
        """The time [s] to the singular position ahead, from the margin and its local rate
        (:meth:`slope`), when the margin fell below :data:`COAST` in the last step and is
        falling; else None."""
        if len(self._points) < 2:
            return None
        (_, m0), (_, m1) = self._points[-2:]
        if not (m1 < COAST * self.scale and m1 < m0):
            return None
        rate = self.slope()
        return m1 / -rate if rate < 0.0 else None

    def landing(self, proposed: float) -> float | None:
        """The length [s] of the next step that ends with the margin at :data:`LANDING` ×
        :data:`COAST` of the largest (or at :data:`LANDING_FALL` of its value, when that is
        more), when the integrator's ``proposed`` step [s] would carry it below (the margin
        falling at its local rate, :meth:`slope`); else None. The rate is
        only differenced when the margin's fall over the last step, twice as fast, would
        reach the target within ``proposed``."""
        if len(self._points) < 2:
            return None
        (t0, m0), (t1, m1) = self._points[-2:]
        target = LANDING * COAST * self.scale
        if m1 >= m0 or m1 - 2.0 * proposed * (m0 - m1) / (t1 - t0) > target:
            return None
        rate = self.slope()
        if rate >= 0.0:
            return None
        length = (m1 - max(target, LANDING_FALL * m1)) / -rate
        return length if 0.0 < length < proposed else None

    def step(self, t_old: float, t_new: float, dense) -> None:
        """Feed one accepted step from t_old to t_new [s] with its dense output."""
        if self.rank == 0:
            return
        self._dense = [*self._dense[-1:], dense]
        if not self._points:
            self._points.append((t_old, self.margin(t_old)))
            self.scale = self._points[0][1]
        self._points.append((t_new, self.margin(t_new)))
        self.scale = max(self.scale, self._points[-1][1])
        if min(self._points[-2][1], self._points[-1][1]) < NEAR * self.scale:
            if self._near and self._near[-1][1] >= t_old:  # continues the last stretch
                self._near[-1][1] = t_new
            else:
                self._near.append([t_old, t_new])
        if len(self._points) >= 3:
            self._check(*self._points[-3:])
        self._points = self._points[-2:]

    def finish(self) -> None:
        """At the run's end: a margin still falling in the last step may reach its minimum
        there (a run that ends on or just past a singular position); search the last step."""
        if len(self._points) == 2 and self._points[1][1] < self._points[0][1]:
            self._check(self._points[0], self._points[1], self._points[1])

    def _check(self, left, middle, right) -> None:
        if not (middle[1] <= right[1] and (middle[1] < left[1] or middle is right)):
            return
        import scipy.optimize  # here: only runs that near a singular position pay its import

        # the margin's square: smooth at a pose the path passes (where the margin itself is a
        # V, |rate × (t − t*)|), so that Brent's parabolic steps converge in a few evaluations
        found = scipy.optimize.minimize_scalar(
            lambda t: self.margin(t) ** 2, bounds=(left[0], right[0]), method="bounded",
            options={"xatol": BRACKET},
        )  # fmt: skip
        margin = math.sqrt(found.fun)
        if margin > SINGULAR_TOLERANCE:
            return
        time = float(found.x)
        if self.passes and abs(time - self.passes[-1].time) <= 4.0 * BRACKET:
            return
        dense = next(d for d in reversed(self._dense) if d.t_min <= time <= d.t_max)
        at = int(np.sum(_values(self.chain, dense(time)[: self.nq]) > SINGULAR_TOLERANCE))
        before, after = (self._rank_at(x[0]) for x in (left, right))
        self.passes.append(SingularPass(time, BRACKET, before, at, after, margin))

    def _rank_at(self, t: float) -> int:
        dense = next(d for d in reversed(self._dense) if d.t_min <= t <= d.t_max)
        return closure_rank(self.chain, dense(t)[: self.nq])


def spread(loads: ChainLoads, keep: np.ndarray) -> ChainLoads:
    """The loads ``loads`` of the samples ``keep`` (bool (N,), its True samples) on all N
    samples, zero at the others (whose loads are indeterminate: the run's
    :attr:`~feeder.chain.dynamics.forward_run.ForwardRun.indeterminate` flags them): every
    per-sample array of the loads, their wrenches and their tree motion (its joint-first
    arrays along their sample axis, :data:`~feeder.chain.kinematics.tree.JOINT_FIRST`), and on
    a moving base its state and gravity (zero at the others too). The kinematics kept for the
    indeterminacy belong to the kept samples' poses: dropped (computed again from the spread
    poses when asked)."""
    count = int(keep.sum())

    def grow(value, axis: int = 0):
        if isinstance(value, np.ndarray):
            if value.ndim <= axis or value.shape[axis] != count:
                return value
            shape = (*value.shape[:axis], keep.size, *value.shape[axis + 1 :])
            full = np.zeros(shape, dtype=value.dtype)
            full[(slice(None),) * axis + (keep,)] = value
            return full
        if isinstance(value, TreeMotion):
            return dataclasses.replace(
                value,
                **{
                    f.name: grow(getattr(value, f.name), 1 if f.name in JOINT_FIRST else 0)
                    for f in dataclasses.fields(value)
                },
            )
        if isinstance(value, dict):
            return {key: grow(item) for key, item in value.items()}
        if isinstance(value, list | tuple) and not isinstance(value, str):
            return type(value)(grow(item) for item in value)
        if dataclasses.is_dataclass(value) and not isinstance(value, type):
            return dataclasses.replace(
                value, **{f.name: grow(getattr(value, f.name)) for f in dataclasses.fields(value)}
            )
        return value

    fields = {f.name for f in dataclasses.fields(loads)} - {"kinematics"}
    if loads.base is None:  # the model's gravity (3,), not per sample
        fields -= {"gravity", "base"}
    grown = {name: grow(getattr(loads, name)) for name in fields}
    return dataclasses.replace(loads, kinematics=None, **grown)


class Coast:
    """The state's Taylor expansion from (t0, y0): y(t) for t0 ≤ t ≤ t0 + h, q one order
    beyond q̇ on Pinocchio's configuration space (advanced by ``pin.integrate``), a stand-in
    for a step's dense output (``t_min``, ``t_max``, called with a time).

    Args:
        model: The Pinocchio model.
        t0, h: Start [s] and length [s].
        y0: The state (q, q̇, W, …) at t0 (:class:`~.forward_equations.ForwardEquations`).
        rates: The time derivatives of (q̇, W, …) at t0 from the first on, (k, y0.size − nq).
    """

    def __init__(self, model, t0: float, h: float, y0: np.ndarray, rates: np.ndarray):
        self.model, self.t_min, self.t_max = model, t0, t0 + h
        self.y0, self.rates = y0, rates
        self.factorials = np.cumprod(np.arange(1.0, len(rates) + 2))

    def __call__(self, t: float) -> np.ndarray:
        nq = self.model.nq
        s = t - self.t_min
        v0 = self.y0[nq:]
        powers = s ** np.arange(1, len(self.rates) + 2) / self.factorials
        out = np.empty_like(self.y0)
        step = v0 * s + powers[1:] @ self.rates
        out[:nq] = pin.integrate(self.model, self.y0[:nq], step[: self.model.nv])
        out[nq:] = v0 + powers[:-1] @ self.rates
        return out


def coast(equations, t0, y0, tau, end, project):
    """The :class:`Coast` across a singular position ahead (time to it ``tau`` [s]) from the
    step end (t0, y0), at most to ``end`` [s], and the state at its end projected onto the
    constraints (``project``). The derivatives of q̇ and the work at t0 come from the equations
    at :data:`FIT_POINTS` points of the stretch [t0 − tau, t0] before it (where the margin is
    still above :data:`COAST`, so that they are accurate), its states from a short backward run
    of SciPy's DOP853 at :data:`FIT_RTOL`: not the run's own dense output, whose accuracy and
    span depend on its method (RK45's fourth-order interpolant, BDF's short steps near the pose
    would make the fitted derivatives the expansion's largest error). The coast is refused when
    the projection's correction exceeds :data:`COAST_POSITION` or :data:`COAST_VELOCITY`.

    Raises:
        IntegrationError: The coast errs by more.
    """
    model = equations.model
    nq, nv = model.nq, model.nv
    span = tau
    x = np.linspace(-1.0, 0.0, FIT_POINTS)
    import scipy.integrate  # here: only runs that cross a singular position pay its import

    back = scipy.integrate.solve_ivp(
        equations, (t0, t0 - span), y0, method="DOP853", t_eval=t0 + span * x[::-1],
        rtol=FIT_RTOL, atol=FIT_RTOL * max(1.0, float(np.abs(y0).max())),
    )  # fmt: skip
    if not back.success:
        raise IntegrationError(
            f"the run cannot pass the singular position ahead of t = {t0:.6g} s: the equations "
            f"before it cannot be integrated ({back.message}); stop there instead "
            "(singular='stop')"
        )
    values = np.array([equations(time, y)[nq:] for time, y in zip(back.t, back.y.T, strict=True)])[
        ::-1
    ]
    c = np.polynomial.polynomial.polyfit(x, values, FIT_POINTS - 1)
    orders = np.arange(FIT_POINTS)
    factorials = np.cumprod(np.maximum(orders, 1.0))
    rates = c * (factorials / span**orders)[:, None]
    h = min(2.0 * tau, end - t0)
    path = Coast(model, t0, h, y0, rates)
    guess = path(t0 + h)
    y = project(equations.dyn.chain, guess)
    moved = float(np.abs(pin.difference(model, guess[:nq], y[:nq])).max())
    turned = float(np.abs(y[nq : nq + nv] - guess[nq : nq + nv]).max())
    scale = max(1.0, float(np.abs(y0[nq : nq + nv]).max()))
    if moved <= COAST_POSITION and turned <= COAST_VELOCITY * scale:
        return path, y
    raise IntegrationError(
        f"the run cannot pass the singular position ahead of t = {t0:.6g} s: its motion across "
        f"it errs by {moved:.2e} rad or m, {turned:.2e} per second (limits "
        f"{COAST_POSITION:g}, {COAST_VELOCITY:g} × the largest rate); stop there instead "
        "(singular='stop')"
    )


def determinate_loads(
    dyn: ChainDynamics, t, q, v, a, passes: Sequence[SingularPass] | None
) -> tuple[ChainLoads, np.ndarray]:
    """The loads of a run that passes singular positions: the samples near them whose loads'
    equations have a condition number above :data:`~.loads_solve.MAX_FORCE_GAIN` (or a lower
    rank) are flagged (bool (N,)) and given zero loads; the others are solved as usual.
    ``passes``: the closure's singular instants, around which the samples are tested outwards
    until one passes; None: test every sample (a singular pose of the loads' equations alone,
    where the actuated joints lose their hold and the closure keeps its rank)."""
    rank = load_rank(dyn, q[0])
    flagged = np.zeros(t.size, dtype=bool)
    if passes is None:
        flagged[:] = [load_gain(dyn, x, rank) > MAX_FORCE_GAIN for x in q]
    for singular in passes or ():
        start = int(np.searchsorted(t, singular.time))
        for k in range(start, t.size):
            if load_gain(dyn, q[k], rank) <= MAX_FORCE_GAIN:
                break
            flagged[k] = True
        for k in range(start - 1, -1, -1):
            if load_gain(dyn, q[k], rank) <= MAX_FORCE_GAIN:
                break
            flagged[k] = True
    keep = ~flagged
    if not keep.any():
        raise IntegrationError(
            "the run's loads cannot be computed at any sample: every one is at or near a "
            "singular pose"
        )
    try:
        loads = inverse_dynamics(dyn, q[keep], v[keep], a[keep], t=t[keep])
    except (SingularPoseError, InputError) as exc:
        if passes is None:
            raise IntegrationError(f"the run's loads cannot be computed: {exc}") from exc
        return determinate_loads(dyn, t, q, v, a, None)
    return spread(loads, keep), flagged
