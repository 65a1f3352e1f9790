"""Forward dynamics of the closed chain driven by the actuator loads (the paper's "force rule").

Section V of the paper proposes to drive the simulation with the piston force (Fig. 14) and the
forearm moment (Fig. 15) instead of the motion laws. Here the loads are sampled time series
(:class:`ForceRule`), the accelerations come from Pinocchio's constrained dynamics
(``constraintDynamics`` with proximal settings, the pin as a ``CONTACT_3D`` constraint) and the
state is integrated at the samples' rate.

**Integrator.** Adams–Bashforth–Moulton of order 5 in PECE mode: two ``constraintDynamics``
calls per step, loads needed only at the samples. Every smooth piece of the force rule (a stage;
the loads' slope, or at the grip their value, jumps at its ends, which a multistep history must
not straddle) starts with four classical Runge–Kutta 4 steps, whose midpoint loads come from
quartic Lagrange interpolation inside the piece. A high order is needed because the force-driven
mechanism is unstable: a given force does not hold a load in place, and a deviation grows like
e^(4…6 t) in stages 2–3. Over the 4 s cycle at 1 kHz, Heun's second-order method ends ~0.5 rad
off the prescribed motion, ABM4 ~2e-4 rad, ABM5 ~6e-7 rad (φ4, the worst).

**Loop closure.** Baumgarte stabilisation inside ``constraintDynamics``: the pin constraint's
acceleration target is −Kp e − Kd ė with Kp = ω², Kd = 2ω, ω = 20 rad/s
(:data:`~feeder.dynamics.BAUMGARTE_RATE`: critically damped, time constant 1/ω = 50 ms,
hω = 0.02 well inside the integrator's stability region). It costs nothing per step and leaves
the motion untouched while the loop is closed (e ~ 1e-13 m). Projection onto the constraint
manifold (a Newton solve of :class:`~feeder.assembly.Partition` every step) would cost several
Jacobian evaluations per step and is not needed: the integrator's own drift is ~1e-13 m.

**Grip.** At a change of the payload flag the model switches (with or without the payload's
inertia). The cycle grips at rest, so no impact is modelled. The loads jump there; the sample at
the switch holds the value after the grip, and the value before it (needed to finish the last
step of the previous piece) is extrapolated (quartic) from that piece's last five samples.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from .device import PAPER_JOINTS
from .dynamics import (
    VELOCITY_TOLERANCE,
    FeederDynamics,
    InertiaCase,
    check_closure,
)
from .exceptions import ForwardDivergenceError, InputError, check_finite
from .kinematics import check_transmission

ADAMS_ORDER = 5
"""Order of the Adams–Bashforth–Moulton pair; the RK4 starter makes ADAMS_ORDER − 1 steps."""

MIN_PIECE_STEPS = ADAMS_ORDER
"""Fewest steps in a smooth piece of the force rule (the starter's steps + one Adams step)."""

END_STOP_TOLERANCE = 1e-3
"""How far [rad or m] the forward run may pass a joint's end stop before it counts as diverged:
10× the 1e-4 rad to which a valid run tracks the cycle
(:data:`~feeder.cycle_dynamics.FORWARD_TOLERANCE`), so that only a run that has left the
prescribed motion trips it."""

_BASHFORTH = np.array([251.0, -1274.0, 2616.0, -2774.0, 1901.0]) / 720.0  # f_{k−4} … f_k
_MOULTON = np.array([-19.0, 106.0, -264.0, 646.0, 251.0]) / 720.0  # f_{k−3} … f_{k+1}


def _lagrange_weights(nodes: np.ndarray, x: float) -> np.ndarray:
    """Weights w with p(x) = Σ w_i f(nodes_i) for the interpolating polynomial through nodes."""
    nodes = np.asarray(nodes, dtype=float)
    weights = np.ones(nodes.size)
    for i, node in enumerate(nodes):
        others = np.delete(nodes, i)
        weights[i] = np.prod((x - others) / (node - others))
    return weights


@dataclass(frozen=True)
class ForceRule:
    """Actuator loads sampled at uniform times: the paper's force rule.

    Attributes:
        t: Sample times [s], uniform step, shape (N,).
        stage: Stage number per sample, shape (N,); a change starts a new smooth piece.
        payload: 1 once the payload is gripped, else 0, shape (N,).
        piston_force: Force on ``piston_joint`` [N], shape (N,).
        forearm_torque: Moment on ``forearm_joint`` [N·m], shape (N,).
    """

    t: np.ndarray
    stage: np.ndarray
    payload: np.ndarray
    piston_force: np.ndarray
    forearm_torque: np.ndarray

    def __post_init__(self) -> None:
        n = np.shape(self.t)
        for name in ("t", "stage", "payload", "piston_force", "forearm_torque"):
            value = check_finite(name, getattr(self, name))
            if value.shape != n or value.ndim != 1:
                raise InputError(f"{name} must have shape {n}, got {value.shape}")
            object.__setattr__(self, name, value)
        if n[0] < MIN_PIECE_STEPS + 1:
            raise InputError(f"a force rule needs at least {MIN_PIECE_STEPS + 1} samples")
        steps = np.diff(self.t)
        if steps[0] <= 0.0 or np.abs(steps - steps[0]).max() > 1e-9 * steps[0]:
            raise InputError(
                f"sample times must be uniform and increasing, got steps in "
                f"[{steps.min():.6g}, {steps.max():.6g}] s"
            )
        if not np.all((self.payload == 0) | (self.payload == 1)):
            raise InputError(f"payload flags must be 0 or 1, got {np.unique(self.payload)}")

    @property
    def step(self) -> float:
        """Sample interval h [s]."""
        return float(self.t[1] - self.t[0])

    def pieces(self) -> list[tuple[int, int]]:
        """Smooth pieces as (first, last) sample indices; consecutive pieces share a sample."""
        change = (np.diff(self.stage) != 0) | (np.diff(self.payload) != 0)
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
    dyn: FeederDynamics, payload: int, q: np.ndarray, v: np.ndarray, tau: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Accelerations and pin force of the closed chain under generalized forces (one sample).

    Args:
        dyn: The device's dynamics models.
        payload: 1 with the payload, 0 without.
        q, v, tau: Configuration, velocity and generalized forces [N, N·m], paper order (4,).

    Returns:
        q̈ (4,) in paper order and λ (3,), the force [N] the arm exerts on the piston at the
        pin, world frame.
    """
    case = dyn.cases[payload]
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
    if rule.payload[last] != rule.payload[first]:
        back = np.arange(ADAMS_ORDER) - ADAMS_ORDER
        forces[-1] = _lagrange_weights(back, 0.0) @ forces[-1 - ADAMS_ORDER : -1]
    tau = np.zeros((forces.shape[0], 4))
    tau[:, dyn.index[1]] = forces[:, 0]
    tau[:, dyn.index[3]] = forces[:, 1]
    return tau


def _integrate_piece(
    case: InertiaCase, state: np.ndarray, tau: np.ndarray, h: float
) -> tuple[np.ndarray, np.ndarray]:
    """Integrate one smooth piece from ``state`` = [q, v] (Pinocchio order, (8,)).

    Args:
        case: The model in force over the piece.
        state: Initial [q, v], shape (8,).
        tau: Generalized forces at the piece's samples, shape (n+1, 4).
        h: Step [s].

    Returns:
        States at the piece's samples (n+1, 8) and the constraint position errors (n+1, 3)
        evaluated there.
    """
    model, data = case.model, case.data
    constraints, datas, prox = case.constraint_models, case.constraint_datas, case.prox
    error = datas[0].contact_placement_error
    dynamics = pin.constraintDynamics
    order = ADAMS_ORDER
    n = tau.shape[0] - 1
    states = np.empty((n + 1, 8))
    rates = np.empty((n + 1, 8))
    errors = np.empty((n + 1, 3))
    states[0] = state
    nodes = np.arange(order)
    weights = np.array([_lagrange_weights(nodes, k + 0.5) for k in range(order - 1)])
    midpoints = weights @ tau[:order]
    half, sixth, h2_6 = 0.5 * h, h / 6.0, h * h / 6.0
    for k in range(order - 1):  # classical RK4 starter
        q, v = states[k, :4], states[k, 4:]
        a1 = dynamics(model, data, q, v, tau[k], constraints, datas, prox)
        errors[k] = error.linear
        rates[k, :4], rates[k, 4:] = v, a1
        v2 = v + half * a1
        a2 = dynamics(model, data, q + half * v, v2, midpoints[k], constraints, datas, prox)
        v3 = v + half * a2
        a3 = dynamics(model, data, q + half * v2, v3, midpoints[k], constraints, datas, prox)
        v4 = v + h * a3
        a4 = dynamics(model, data, q + h * v3, v4, tau[k + 1], constraints, datas, prox)
        states[k + 1, :4] = q + h * v + h2_6 * (a1 + a2 + a3)
        states[k + 1, 4:] = v + sixth * (a1 + 2.0 * (a2 + a3) + a4)
    k = order - 1
    q, v = states[k, :4], states[k, 4:]
    rates[k, :4], rates[k, 4:] = v, dynamics(model, data, q, v, tau[k], constraints, datas, prox)
    errors[k] = error.linear
    predictor, corrector = h * _BASHFORTH, h * _MOULTON
    back = order - 1
    for k in range(order - 1, n):
        guess = states[k] + predictor @ rates[k - back : k + 1]
        rates[k + 1, :4] = guess[4:]
        rates[k + 1, 4:] = dynamics(
            model, data, guess[:4], guess[4:], tau[k + 1], constraints, datas, prox
        )
        state = states[k + 1] = states[k] + corrector @ rates[k - back + 1 : k + 2]
        rates[k + 1, :4] = state[4:]
        rates[k + 1, 4:] = dynamics(
            model, data, state[:4], state[4:], tau[k + 1], constraints, datas, prox
        )
        errors[k + 1] = error.linear
    return states, errors


def check_initial_state(
    dyn: FeederDynamics, q0: np.ndarray, v0: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Refuse an initial state off the closure or at the toggle; return q0, v0 as arrays.

    Raises:
        InputError: NaN/inf or misshaped, or velocities violating the closure.
        UnreachablePoseError: q0 does not close the loop.
        SingularPoseError: q0 within 5° of the toggle.
    """
    q0 = check_finite("q0", q0)
    v0 = check_finite("v0", v0)
    if q0.shape != (4,) or v0.shape != (4,):
        raise InputError(f"q0 and v0 must have shape (4,), got {q0.shape} and {v0.shape}")
    check_closure(dyn.feeder, q0[None, :], "the initial state")
    check_transmission(q0[None, :])
    jacobian = dyn.feeder.chain.jacobian(dyn.to_pinocchio(q0))
    rate = float(np.linalg.norm(jacobian @ dyn.to_pinocchio(v0)))
    if rate > VELOCITY_TOLERANCE:
        raise InputError(
            f"the initial velocity violates the closure: |J v0| = {rate:.3e} m/s > "
            f"{VELOCITY_TOLERANCE:g} m/s at v0 = {np.round(v0, 6)}"
        )
    return q0, v0


def simulate(
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
        case = dyn.cases[int(rule.payload[first])]
        tau = _piece_loads(rule, first, last, dyn)
        piece_states, piece_errors = _integrate_piece(case, state, tau, h)
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
