"""The equations of a forward run: the right-hand side (q̇, q̈, power) of a closed chain's state.

The state (q, q̇) follows the index-1 equations of the closed chain

    [M  Jᵀ] [ q̈]   [τ − b          ]
    [J  0 ] [−λ] = [−J̇ q̇ − K_d J q̇ − K_p r(q)]

with τ = Sᵀ u(t, q, q̇) (the actuated joints' drive, given by the caller: :data:`Actuation`; a
:class:`Controller` may also push line force elements, Σ_e g_e(q) P_e, g_e = dℓ_e/dq) plus
the force elements' generalized forces (:mod:`~feeder.chain.dynamics.elements`), b the Coriolis,
centrifugal and gravity terms, and Baumgarte's corrector K_p = ω², K_d = 2ω on the loop residual
r (critically damped: an error decays like e^(−ω t)). The accelerations come from Pinocchio's
``constraintDynamics`` on the chain's own constraint models (its proximal solver takes the
redundant rows of a planar loop); q̇ from q̇ (the rotations' and the unit circles' rates for the
joints whose q is not a vector: :class:`~feeder.chain.kinematics.joints.ConfigurationRate`). The
power of the non-conservative forces (drives, dampers, pushes, pressures, loads) follows, so that
their work is integrated with the state; then a :class:`Controller`'s states (an actuation with
states of its own: u and ẋ from (t, q, q̇, x)) and, on a moving base, the base's power
(:mod:`~feeder.chain.dynamics.forward_base`, which also gives b there: the moving base's).

The integrator's q leaves the unit circles (a continuous joint's (cos, sin)) and the unit
quaternions by its truncation error, and an explicit Runge–Kutta method's inner stages, linear
combinations of states on them, by O(h²): those stages' off-unit lengths move the bodies and
open the loops by O(h²), which Baumgarte's K_p turns into accelerations that the step-size
control must resolve. For the explicit methods (``normalize``) the equations are therefore
evaluated at the nearest unit circles and quaternions (``pin.normalize``; their rate keeps the
integrator's q): DOP853 at rtol 1e-10 took 4 ms steps on the N = 40 four-bar, 40–80 ms with the
normalisation (measured). Radau, whose steps the corrector does not hold (518 steps over 3 s
of the N = 2 four-bar normalised, 571 not), keeps q as integrated: normalised, its states next
to a flat pose carried velocities off the branch 100 × larger (B0 off by 2.9e-5 m after three
passes at rtol 1e-8, 2.4e-7 m without). A chain whose q is a vector is evaluated at q itself.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol, runtime_checkable

import numpy as np
import pinocchio as pin

from ...exceptions import FeederError, InputError
from ...validation import check_finite
from ..kinematics.joints import ConfigurationRate
from .forward_base import MovingBase
from .inverse import ChainDynamics
from .pushed_elements import carrying

BAUMGARTE_RATE = 20.0
"""Default Baumgarte rate ω [1/s]: a loop error decays in 1/ω = 50 ms, fast compared with a
mechanism's motion and slow enough not to make the equations stiff."""

PROXIMAL = pin.ProximalSettings(1e-13, 1e-10, 100)
"""Pinocchio's proximal solver: absolute accuracy 1e-13 of the constraint accelerations,
regularisation μ = 1e-10 (positive: the redundant rows of a planar loop), at most 100 iterations
(1–3 are used). A run that passes a singular position keeps these settings: next to the pose,
where no regularisation makes the equations both bounded and faithful to the branch, it does not
evaluate them but crosses by the motion's expansion (:mod:`~feeder.chain.dynamics.singular`)."""

Actuation = Callable[[float, np.ndarray, np.ndarray], np.ndarray]
"""u(t, q, q̇): the actuated joints' generalized forces [N or N·m] at time t [s], (n_actuated,)."""


@runtime_checkable
class Controller(Protocol):
    """An actuation with states of its own (an actuator's lag, a controller's integrator): the
    run integrates its states x with the mechanism's, y = (q, q̇, W, x).

    Attributes:
        n_states: Number of its states (≥ 0).

    Optional attributes (read with ``getattr``; a controller without them drives the actuated
    joints alone):

    * ``pushes: tuple[str, ...]`` — names of line force elements (springs, cylinders) of the
      chain whose push [N] (extending) the controller gives too: its u is then (n_actuated +
      len(pushes),), the pushes after the drives, and each push P_e adds P_e g_e(q) to τ
      (g_e = dℓ_e/dq, :meth:`~.elements.BoundElements.unit_pushes`) and P_e ℓ̇_e to the power;
      the run's loads take the pushes it applied at the samples
      (:meth:`ForwardEquations.loads_dynamics`).
    * ``at_samples(t, q, v, x) -> u`` — u at N instants at once (times (N,), q (N, nq), q̇
      (N, nv), x (N, n_states)), (N, len(u)): the values of ``__call__``'s u there, for the
      run's output samples (:meth:`ForwardEquations.sample_commands`), where one call per sample
      would cost more than the run's steps (a servo's 4 501 samples against its 253 steps).
    """

    n_states: int

    def start(self, t0: float, q0: np.ndarray, v0: np.ndarray) -> np.ndarray:
        """The states at the start of the run (n_states,), from the start time [s] and state."""

    def __call__(
        self, t: float, q: np.ndarray, v: np.ndarray, x: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """(u, ẋ): the actuated joints' generalized forces [N or N·m] (n_actuated,) and the
        states' rates (n_states,) at time t [s], state (q, q̇) and states x."""


EMPTY = np.zeros(0)
"""The states of an actuation without any."""


def _pushed(dyn: ChainDynamics, names: object) -> tuple:
    """The bound line elements of ``dyn`` named ``names`` (a controller's ``pushes``).

    Raises:
        InputError: Not a tuple of names, a name that is not a spring or cylinder of ``dyn``.
    """
    if not isinstance(names, tuple) or not all(isinstance(name, str) for name in names):
        raise InputError(f"a controller's pushes must be a tuple of element names, got {names!r}")
    lines = tuple(dyn.elements.line(name) for name in names)
    if None in lines:
        missing = names[lines.index(None)]
        raise InputError(f"a controller pushes {missing!r}: not a spring or cylinder of the chain")
    return lines


class IntegrationError(FeederError):
    """A forward run stopped: the integrator could not meet its tolerance (a singular pose, an
    unbounded acceleration), the run reached a singular pose where its loads cannot be computed,
    or the forces became NaN."""


class ForwardEquations:
    """The right-hand side of a run (module docstring) on one pinocchio.Data: called as
    f(t, y) with y = (q, q̇, W, x[, W_B]) — the configuration (nq), velocities (nv), the work of
    the non-conservative forces [J], a :class:`Controller`'s states (n_states) and, on a moving
    base, the base's work [J] — it returns their rates; ``count``: the calls so far."""

    def __init__(
        self,
        dyn: ChainDynamics,
        actuation: Actuation | Controller | None,
        rate: float,
        normalize: bool = False,
    ):
        chain, model = dyn.chain, dyn.chain.model
        self.model, self.dyn, self.actuation = model, dyn, actuation
        self.controller = actuation if isinstance(actuation, Controller) else None
        self.n_states = 0 if self.controller is None else self.controller.n_states
        self.pushed = _pushed(dyn, getattr(self.controller, "pushes", ()))
        """The line elements the controller pushes (Controller's ``pushes``), bound."""
        self.data = model.createData()
        self.constraints, self.datas = chain.corrected_constraints(self.data, rate)
        # the samples' accelerations: the closed chain's own, without the corrector
        self.sample_data = model.createData()
        self.sample_constraints, self.sample_datas = chain.corrected_constraints(
            self.sample_data, 0.0
        )
        self.nq, self.nv = model.nq, model.nv
        self.rate = None if model.nq == model.nv else ConfigurationRate(model)
        self.normalize = normalize and self.rate is not None  # module docstring
        self.columns = np.array(dyn.columns, dtype=int)
        self.zero = np.zeros(model.nv)
        self.moving = None if dyn.base is None else MovingBase(model, dyn.base)
        self.size = self.nq + self.nv + 1 + self.n_states + (self.moving is not None)
        self.count = 0

    def states(self, y: np.ndarray) -> np.ndarray:
        """The controller's states x of a state y (size,), (n_states,); of states (N, size),
        (N, n_states)."""
        first = self.nq + self.nv + 1
        return y[..., first : first + self.n_states]

    def command(self, t: float, q: np.ndarray, v: np.ndarray, x: np.ndarray = EMPTY):
        """u (n_actuated + n_pushed,): the drives [N or N·m] and the pushed elements' pushes [N],
        and ẋ (n_states,) of the actuation at (t, q, q̇, x), checked."""
        if self.controller is None:
            u = self.actuation(t, q, v)
            return self._checked("actuation", "[N or N·m]", t, u, self.columns.size), EMPTY
        out = self.controller(t, q, v, x)
        if not (isinstance(out, tuple) and len(out) == 2):
            raise InputError(f"the controller must return (u, xdot) at t = {t:.6g} s, got {out!r}")
        size = self.columns.size + len(self.pushed)
        u = self._checked("actuation", "[N or N·m]", t, out[0], size)
        return u, self._checked("controller state rates", "", t, out[1], self.n_states)

    def sample_commands(
        self, t: np.ndarray, q: np.ndarray, v: np.ndarray, x: np.ndarray
    ) -> np.ndarray:
        """u (N, n_actuated + n_pushed) at the output samples t [s] (N,), q (N, nq), q̇ (N, nv),
        x (N, n_states): :meth:`command`'s u at each (in one call where the controller has
        ``at_samples``: :class:`Controller`), checked."""
        size = self.columns.size + len(self.pushed)
        many = getattr(self.controller, "at_samples", None)
        if many is None:
            samples = zip(t, q, v, x, strict=True)
            return np.array([self.command(*sample)[0] for sample in samples]).reshape(-1, size)
        u = check_finite(f"the controller's u at the {t.size} samples", many(t, q, v, x))
        if u.shape != (t.size, size):
            raise InputError(
                f"the controller's u at the {t.size} samples must be ({t.size}, {size}) finite "
                f"numbers [N or N·m], got shape {u.shape}"
            )
        return u

    def loads_dynamics(self, t: np.ndarray, pushes: np.ndarray) -> ChainDynamics:
        """The dynamics for a run's loads at its samples t [s] (N,), given the pushes [N]
        (N, n_pushed) the controller applied there (:meth:`command`'s last columns): the run's
        own, or, when the controller pushes force elements, a copy whose pushed elements carry
        those pushes as tables over t (:func:`~.pushed_elements.carrying`: exact at t)."""
        if not self.pushed:
            return self.dyn
        names = self.controller.pushes
        return carrying(self.dyn, t, dict(zip(names, pushes.T, strict=True)))

    @staticmethod
    def _checked(what: str, unit: str, t: float, u: object, size: int) -> np.ndarray:
        """``u`` if it is ``size`` finite floats, else converted or refused (``unit`` for the
        message)."""
        if not (type(u) is np.ndarray and u.dtype == np.float64 and np.isfinite(u).all()):
            # anything but finite floats (or not an array): converted or refused, the message
            # built only here (each evaluation of the right-hand side passes this way)
            u = check_finite(f"{what} at t = {t:.6g} s {unit}".rstrip(), u)
        if u.shape != (size,):
            raise InputError(
                f"{what} at t = {t:.6g} s must be {size} finite numbers {unit}".rstrip()
                + f", got {u!r}"
            )
        return u

    def forces(
        self, t: float, q: np.ndarray, v: np.ndarray, x: np.ndarray = EMPTY
    ) -> tuple[np.ndarray, float, np.ndarray]:
        """τ (nv,), the power [W] of the non-conservative forces and ẋ (n_states,)."""
        elements = self.dyn.elements
        if self.actuation is None:
            tau, power = elements.generalized(q, v, t) if elements else (self.zero, 0.0)
            return tau, power, EMPTY
        tau = np.zeros(self.model.nv)
        u, xdot = self.command(t, q, v, x)
        n = self.columns.size
        tau[self.columns] = u[:n]
        power = float(u[:n] @ v[self.columns])
        if self.pushed:  # Σ P_e g_e, and the pushes' power Σ P_e ℓ̇_e
            unit = elements.unit_pushes(self.pushed, q, t)
            tau += unit @ u[n:]
            power += float(u[n:] @ (v @ unit))
        if elements:
            generalized, element_power = elements.generalized(q, v, t)
            tau += generalized
            power += element_power
        return tau, power, xdot

    def evaluate(
        self, t: float, q: np.ndarray, v: np.ndarray, x: np.ndarray = EMPTY, sample: bool = False
    ) -> tuple[np.ndarray, float, np.ndarray, float]:
        """q̈ (nv,), the power [W] of the non-conservative forces, ẋ (n_states,) and the base's
        power [W] (0 on a base at rest) at (t, q, q̇, x); ``sample``: without Baumgarte's
        corrector (:meth:`sample_accelerations`)."""
        tau, power, xdot = self.forces(t, q, v, x)
        data, constraints, datas = (
            (self.sample_data, self.sample_constraints, self.sample_datas)
            if sample
            else (self.data, self.constraints, self.datas)
        )
        if self.moving is None:
            a = pin.constraintDynamics(self.model, data, q, v, tau, constraints, datas, PROXIMAL)
            return a, power, xdot, 0.0
        correction, rooted = self.moving.bias(data, t, q, v)
        a = pin.constraintDynamics(
            self.model, data, q, v, tau + correction, constraints, datas, PROXIMAL
        )
        return a, power, xdot, self.moving.power(rooted, a)

    def accelerations(
        self, t: float, q: np.ndarray, v: np.ndarray, x: np.ndarray = EMPTY
    ) -> tuple[np.ndarray, float]:
        """q̈ (nv,) and the power [W] of the non-conservative forces at (t, q, q̇, x)."""
        return self.evaluate(t, q, v, x)[:2]

    def sample_accelerations(
        self, t: float, q: np.ndarray, v: np.ndarray, x: np.ndarray = EMPTY
    ) -> np.ndarray:
        """q̈ (nv,) at an output sample (t, q, q̇, x): the closed chain's accelerations,
        J q̈ = −J̇ q̇, without Baumgarte's corrector, whose −K_p r − K_d J q̇ would open the
        acceleration rows by up to 4.4e-8 (K_p = 400 /s² times a residual at the drift
        tolerance, 1e-10) in a sample kept as integrated, beyond what the inverse dynamics of
        the samples accept (1e-9 of the sample's scale)."""
        return self.evaluate(t, q, v, x, sample=True)[0]

    def __call__(self, t: float, y: np.ndarray) -> np.ndarray:
        self.count += 1
        nq, nv = self.nq, self.nv
        q, v = y[:nq], y[nq : nq + nv]
        # the dynamics of the nearest unit circles and quaternions (module docstring)
        unit = pin.normalize(self.model, q) if self.normalize else q
        a, power, xdot, base_power = self.evaluate(t, unit, v, self.states(y))
        if not np.all(np.abs(a) < 1e154):  # NaN, inf, or as meaningless (a @ a would overflow)
            raise IntegrationError(
                f"the accelerations are not finite at t = {t:.6g} s (a singular pose, or forces "
                "that are not finite)"
            )
        out = np.empty(self.size)
        out[:nq] = v if self.rate is None else self.rate(q, v)
        out[nq : nq + nv] = a
        out[nq + nv] = power
        out[nq + nv + 1 : nq + nv + 1 + self.n_states] = xdot
        if self.moving is not None:
            out[-1] = base_power
        return out
