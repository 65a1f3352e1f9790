"""Forward dynamics of the closed chain driven by the actuator loads (the paper's "force rule").

Section V of the paper proposes to drive the simulation with the piston force (Fig. 14) and the
forearm moment (Fig. 15) instead of the motion laws. Here the loads are sampled time series
(:class:`ForceRule`), the accelerations come from Pinocchio's constrained dynamics
(``constraintDynamics`` with proximal settings, the pin as a ``CONTACT_3D`` constraint) and the
state is integrated at the samples' rate.

**Integrator**: :mod:`feeder.dynamics.integrator`, not the generic adaptive run
(:func:`feeder.chain.simulate`). Measured on the projectile cycle at 30° and 1 kHz (the loads
given at the samples only): the generic run on a cubic spline of the sampled loads, piece by piece,
ends 1.5e-5 rad off the prescribed φ4 at rtol 1e-10 … 1e-12 (each piece alone is within 1e-10;
the force-driven mechanism amplifies the ~1e-9 rad/s left at a piece's end some 5000-fold over
stage 3) and takes 0.5 s, most of it the tables every generic run computes at its 4 000 output
samples; this fixed-step run ends 3.3e-7 rad off in 0.05 s. So two forward integrators remain:
this one checks the force rule at its own samples, the generic one runs users' mechanisms.

**Loop closure.** Baumgarte stabilisation inside ``constraintDynamics``: the pin constraint's
acceleration target is −Kp e − Kd ė with Kp = ω², Kd = 2ω, ω = 20 rad/s
(:data:`feeder.chain.BAUMGARTE_RATE`, the generic run's: critically damped, time constant
1/ω = 50 ms, hω = 0.02 well inside the integrator's stability region). It costs nothing per step
and leaves the motion untouched while the loop is closed (e ~ 1e-13 m). Projection onto the
constraint manifold (a Newton solve of :class:`~feeder.chain.Partition` every step) would cost
several Jacobian evaluations per step and is not needed: the integrator's own drift is ~1e-13 m.

**Grip.** At a change of the grip flag the model switches (with or without the payload's
inertia). The cycle grips at rest, so no impact is modelled. The loads jump there; the sample at
the switch holds the value after the grip, and the value before it (needed to finish the last
step of the previous piece) is extrapolated (quartic) from that piece's last five samples.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..device.feeder import PAPER_JOINTS
from ..device.loop import check_closed, check_closed_velocity, check_transmission
from ..exceptions import ForwardDivergenceError, InputError
from ..validation import check_finite, check_vector
from .integrator import ADAMS_ORDER, MIN_PIECE_STEPS, integrate_piece, lagrange_weights
from .models import FeederDynamics

END_STOP_TOLERANCE = 1e-3
"""How far [rad or m] the forward run may pass a joint's end stop before it counts as diverged:
10× the 1e-4 rad to which a valid run tracks the cycle
(:data:`~feeder.dynamics.cycle.FORWARD_TOLERANCE`), so that only a run that has left the
prescribed motion trips it."""


@dataclass(frozen=True)
class ForceRule:
    """Actuator loads sampled at uniform times: the paper's force rule.

    Attributes:
        t: Sample times [s], uniform step, shape (N,).
        stage: Stage number per sample, shape (N,); a change starts a new smooth piece.
        gripped: 1 once the payload is gripped, else 0, shape (N,).
        piston_force: Force on ``piston_joint`` [N], shape (N,).
        forearm_torque: Moment on ``forearm_joint`` [N·m], shape (N,).
    """

    t: np.ndarray
    stage: np.ndarray
    gripped: np.ndarray
    piston_force: np.ndarray
    forearm_torque: np.ndarray

    def __post_init__(self) -> None:
        n = np.shape(self.t)
        for name in ("t", "stage", "gripped", "piston_force", "forearm_torque"):
            value = check_finite(name, getattr(self, name))
            if value.shape != n or value.ndim != 1:
                raise InputError(f"{name} must have shape {n}, got {value.shape}")
            object.__setattr__(self, name, value)
        if n[0] < MIN_PIECE_STEPS + 1:
            raise InputError(
                f"a force rule needs at least {MIN_PIECE_STEPS + 1} samples, got {n[0]}: sample "
                "faster, or skip the forward run (feeder cycle --no-forward)"
            )
        steps = np.diff(self.t)
        if steps[0] <= 0.0 or np.abs(steps - steps[0]).max() > 1e-9 * steps[0]:
            raise InputError(
                f"sample times must be uniform and increasing, got steps in "
                f"[{steps.min():.6g}, {steps.max():.6g}] s"
            )
        if not np.all((self.gripped == 0) | (self.gripped == 1)):
            raise InputError(f"grip flags must be 0 or 1, got {np.unique(self.gripped)}")

    @property
    def step(self) -> float:
        """Sample interval h [s]."""
        return float(self.t[1] - self.t[0])

    def pieces(self) -> list[tuple[int, int]]:
        """Smooth pieces as (first, last) sample indices; consecutive pieces share a sample."""
        change = (np.diff(self.stage) != 0) | (np.diff(self.gripped) != 0)
        edges = np.flatnonzero(change) + 1
        firsts = np.concatenate([[0], edges])
        lasts = np.concatenate([edges, [self.t.size - 1]])
        pieces = [(int(a), int(b)) for a, b in zip(firsts, lasts, strict=True)]
        for first, last in pieces:
            if last - first < MIN_PIECE_STEPS:
                raise InputError(
                    f"the smooth piece t = {self.t[first]:.4f} … {self.t[last]:.4f} s has "
                    f"{last - first} steps; at least {MIN_PIECE_STEPS} are needed"
                )
        return pieces


@dataclass(frozen=True)
class ForwardMotion:
    """Motion integrated from a force rule, N samples, paper order.

    Attributes:
        t: Times [s], shape (N,).
        q, v: [φ1, r2, φ3, φ4] and their rates, shape (N, 4).
        closure_residual: Distance between ``piston_pin`` and ``arm_pin`` [m] (Pinocchio's
            constraint error at each sample), shape (N,).
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    closure_residual: np.ndarray


def constrained_dynamics(
    dyn: FeederDynamics, gripped: int, q: np.ndarray, v: np.ndarray, tau: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Accelerations and pin force of the closed chain under generalized forces (one sample).

    Args:
        dyn: The device's dynamics models.
        gripped: 1 with the payload, 0 without.
        q, v, tau: Configuration, velocity and generalized forces [N, N·m], paper order (4,).

    Returns:
        q̈ (4,) in paper order and λ (3,), the force [N] the arm exerts on the piston at the
        pin, world frame.
    """
    case = dyn.cases[gripped]
    acceleration = pin.constraintDynamics(
        case.model,
        case.data,
        dyn.to_pinocchio(q),
        dyn.to_pinocchio(v),
        dyn.to_pinocchio(tau),
        case.constraint_models,
        case.constraint_datas,
        case.prox,
    )
    world = case.constraint_datas[0].oMc1.rotation @ case.data.lambda_c[:3]
    return dyn.to_paper(acceleration), world


def _piece_loads(rule: ForceRule, first: int, last: int, dyn: FeederDynamics) -> np.ndarray:
    """Generalized forces (Pinocchio order) at the samples first … last of one piece, (n+1, 4).

    The last sample's loads are replaced by the extrapolated left limit at a grip.
    """
    forces = np.column_stack(
        [rule.piston_force[first : last + 1], rule.forearm_torque[first : last + 1]]
    )
    if rule.gripped[last] != rule.gripped[first]:
        back = np.arange(ADAMS_ORDER) - ADAMS_ORDER
        forces[-1] = lagrange_weights(back, 0.0) @ forces[-1 - ADAMS_ORDER : -1]
    tau = np.zeros((forces.shape[0], 4))
    tau[:, dyn.index[1]] = forces[:, 0]
    tau[:, dyn.index[3]] = forces[:, 1]
    return tau


def check_initial_state(
    dyn: FeederDynamics, q0: np.ndarray, v0: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Refuse an initial state off the closure or at the toggle; return q0, v0 as arrays.

    Raises:
        InputError: NaN/inf or misshaped, or velocities violating the closure.
        UnreachablePoseError: q0 does not close the loop.
        SingularPoseError: q0 within 5° of the toggle.
    """
    q0, v0 = check_vector("q0", q0, 4), check_vector("v0", v0, 4)
    check_closed(dyn.feeder.params, q0[None, :], "the initial state")
    check_transmission(q0[None, :])
    check_closed_velocity(dyn.feeder.params, q0[None, :], v0[None, :], "the initial state")
    return q0, v0


def simulate_feeder(
    dyn: FeederDynamics, rule: ForceRule, q0: np.ndarray, v0: np.ndarray
) -> ForwardMotion:
    """Integrate the closed chain driven by ``rule`` from the closed state (q0, v0).

    Args:
        dyn: The device's dynamics models.
        rule: The sampled actuator loads (the integration step is their sample interval).
        q0, v0: Initial configuration and velocity [φ1, r2, φ3, φ4], paper order, (4,).

    Raises:
        InputError: NaN/inf loads or state, non-uniform times, too short pieces, velocities
            violating the closure.
        UnreachablePoseError: q0 does not close the loop.
        SingularPoseError: q0 or the integrated motion within 5° of the toggle.
        ForwardDivergenceError: The integrated motion blows up or passes a joint's end stop
            (:func:`check_end_stops`).
    """
    q0, v0 = check_initial_state(dyn, q0, v0)
    h = rule.step
    n = rule.t.size
    states = np.empty((n, 8))
    errors = np.empty((n, 3))
    state = np.concatenate([dyn.to_pinocchio(q0), dyn.to_pinocchio(v0)])
    for first, last in rule.pieces():
        case = dyn.cases[int(rule.gripped[first])]
        tau = _piece_loads(rule, first, last, dyn)
        piece_states, piece_errors = integrate_piece(case, state, tau, h)
        states[first : last + 1] = piece_states
        errors[first : last + 1] = piece_errors
        state = piece_states[-1]
    q, v = dyn.to_paper(states[:, :4]), dyn.to_paper(states[:, 4:])
    check_end_stops(dyn, rule.t, q, v)
    check_transmission(q, rule.t)
    return ForwardMotion(t=rule.t, q=q, v=v, closure_residual=np.linalg.norm(errors, axis=1))


def check_end_stops(dyn: FeederDynamics, t: np.ndarray, q: np.ndarray, v: np.ndarray) -> None:
    """Raise :class:`ForwardDivergenceError` at the first sample of a forward run that is not
    finite or passes a joint's end stop (the URDF's limits) by more than
    :data:`END_STOP_TOLERANCE`.

    Args:
        dyn: The device's dynamics models.
        t: Sample times [s], shape (N,).
        q, v: The run's coordinates and rates in paper order, shape (N, 4).
    """
    model = dyn.feeder.model
    low, high = dyn.to_paper(model.lowerPositionLimit), dyn.to_paper(model.upperPositionLimit)
    finite = np.all(np.isfinite(q) & np.isfinite(v), axis=1)
    outside = (q < low - END_STOP_TOLERANCE) | (q > high + END_STOP_TOLERANCE)
    bad = ~finite | np.any(outside, axis=1)
    if not np.any(bad):
        return
    k = int(np.argmax(bad))
    advice = (
        "the force-driven mechanism is unstable and the integration has diverged from the "
        "motion the loads were computed for (sample more finely, or shorten the cycle)"
    )
    if not finite[k]:
        raise ForwardDivergenceError(f"the forward run blows up at t = {t[k]:.4f} s: {advice}")
    i = int(np.argmax(outside[k]))
    raise ForwardDivergenceError(
        f"the forward run passes the end stop of {PAPER_JOINTS[i]} at t = {t[k]:.4f} s "
        f"({q[k, i]:.6g} outside [{low[i]:.6g}, {high[i]:.6g}]): {advice}"
    )
