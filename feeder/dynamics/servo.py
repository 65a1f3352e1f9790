"""The device's drives under position control: the lift cylinder and the rack drive follow the
cycle's reference by the computed-torque law (feedforward plus proportional–derivative feedback).

For each actuated joint i (``piston_joint`` r2 [m], ``forearm_joint`` φ4 [rad]) the command is

    u_i = u_ff,i(t) + K_p,i (q_ref,i(t) − q_i) + K_d,i (q̇_ref,i(t) − q̇_i)

with u_ff the inverse dynamics of the reference (the cycle's piston force and forearm moment,
computed for the base standing level: the controller does not sense the hull), clipped to the
drive's limits (:class:`ServoGains`: the supply pressure on the cylinder's areas, the rack's
force), and optionally passed through a first-order lag of the drive (a servo-valve's bandwidth
ω_a: ẋ = ω_a (u_cmd − x), the force applied is x). Without a disturbance and with exact
feedforward the reference is a solution of the closed loop, so the run reproduces it to the
integration and interpolation errors (:class:`CycleServo`).

Why not the engine's :class:`~feeder.chain.dynamics.control.ComputedTorque`: that law meets its
commanded accelerations through the run's own equations, the moving base's terms included, so it
cancels the hull's motion exactly (a controller that measures the hull's accelerations and holds
the device's whole model), and the loading pose would be exact by construction. The device's
hydraulic loops do not sense the hull: their feedforward is fixed in advance (the prescribed
cycle's loads standing level), and the hull is a disturbance their PD terms reject.

Gains (:meth:`ServoGains.gains`): K_p = m ω², K_d = 2 ζ m ω per joint, where m is the largest
diagonal of the closed chain's inertia reduced to the actuated coordinates (Gᵀ M G, G the
velocity map from the actuated rates) over the cycle, ω = 2π f the position loop's bandwidth
and ζ its damping ratio: each joint alone is then a second-order loop of natural frequency ≥ f.
The gains are set for each load case (the empty tray in stage 1, the payload gripped after it:
:func:`feeder.dynamics.loading.controlled_cycle`), as a valve-controlled drive keeps its loop's
bandwidth, not its force gain, when the load changes (the valve meters flow, a velocity per
error); force gains set for the payload alone would make the empty tray's forearm loop 3.7 ×
faster and 3.7 × overdamped (its reduced inertia is 14 × smaller: 0.15 against 2.2 kg·m²), a
pole near −900 /s that held the integrator to 3 ms steps through stage 1 (measured).
Defaults (assumed, stated here): f = 5 Hz and ζ = 1 — valve-controlled cylinders' position loops
on mobile machines run at 2–10 Hz, limited by the oil column's hydraulic natural frequency
(Merritt, *Hydraulic Control Systems*, ch. 7: a loop's bandwidth at most about a third of it,
typically 10–30 Hz for such cylinders); no lag; the supply pressure 160 bar (the nominal
pressure of ISO 6020-2 compact cylinders, the rating notebook 06 assumes: 9 × the reference
cycle's peak cap pressure); the rack drive's force limit 5 kN (assumed: 2.4 × the 2.1 kN the
rack needs on the move across a slope, notebook 06).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..device.parameters import FeederParameters
from ..exceptions import InputError
from ..hermite import quintic_hermite
from ..validation import check_number
from .drives import piston_areas

BANDWIDTH_HZ = 5.0
"""Default position-loop bandwidth f [Hz] (module docstring: assumed, 2–10 Hz typical)."""

DAMPING = 1.0
"""Default damping ratio ζ of each position loop (critically damped: no overshoot)."""

SUPPLY_PRESSURE = 160e5
"""Default supply pressure [Pa] of the lift cylinder (module docstring: assumed)."""

RACK_FORCE_LIMIT = 5e3
"""Default largest rack force [N] of the rack drive (module docstring: assumed)."""


@dataclass(frozen=True)
class ServoGains:
    """The position loops of the lift cylinder and the rack drive (module docstring).

    Attributes:
        bandwidth_hz: Position-loop bandwidth f [Hz] (natural frequency of each loop), > 0.
        damping: Damping ratio ζ, > 0.
        actuator_hz: Bandwidth of a first-order lag of each drive [Hz] (a servo-valve), or None
            for an ideal force source.
        supply_pressure: Largest chamber pressure [Pa]: the cylinder's force is limited to
            [−p A_annulus, p A_cap].
        rack_force_limit: Largest |rack force| [N] of the rack drive.

    Raises:
        InputError: A value that is not a finite positive number.
    """

    bandwidth_hz: float = BANDWIDTH_HZ
    damping: float = DAMPING
    actuator_hz: float | None = None
    supply_pressure: float = SUPPLY_PRESSURE
    rack_force_limit: float = RACK_FORCE_LIMIT

    def __post_init__(self) -> None:
        names = ["bandwidth_hz", "damping", "supply_pressure", "rack_force_limit"]
        if self.actuator_hz is not None:
            names.append("actuator_hz")
        for name in names:
            value = getattr(self, name)
            if not check_number(f"servo {name}", value) > 0.0:
                raise InputError(f"servo {name} must be a positive number, got {value!r}")
            object.__setattr__(self, name, float(value))

    def describe(self) -> str:
        """One line for summaries."""
        lag = "no drive lag" if self.actuator_hz is None else f"drive lag {self.actuator_hz:g} Hz"
        return (
            f"position loops {self.bandwidth_hz:g} Hz, ζ = {self.damping:g}, {lag}, supply "
            f"{self.supply_pressure / 1e5:g} bar, rack ≤ {self.rack_force_limit:g} N"
        )

    def gains(self, inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """K_p [N/m, N·m/rad] and K_d [N·s/m, N·m·s/rad] for the reduced inertias ``inertia``
        [kg, kg·m²] of the piston and the forearm (module docstring): each of inertia's shape,
        (2,) or a row per load case (2, 2)."""
        omega = 2.0 * math.pi * self.bandwidth_hz
        inertia = np.asarray(inertia, dtype=float)
        return inertia * omega**2, 2.0 * self.damping * omega * inertia

    def limits(self, params: FeederParameters) -> tuple[np.ndarray, np.ndarray]:
        """Lowest and highest drive forces [N, N·m] (2,) each: the piston force, the forearm
        moment (the rack force times the pinion radius)."""
        cap, annulus = piston_areas(params)
        moment = self.rack_force_limit * params.pinion_radius
        p = self.supply_pressure
        return np.array([-p * annulus, -moment]), np.array([p * cap, moment])


def _channels(t: np.ndarray, q: np.ndarray, v: np.ndarray, a: np.ndarray, u: np.ndarray):
    """One piecewise polynomial of the 6 channels (q_ref (2), q̇_ref (2), u_ff (2)) over the
    samples ``t`` (n,) of one smooth piece: q_ref the quintic Hermite interpolant of q, q̇, q̈
    (:func:`feeder.hermite.quintic_hermite`, the one the engine's prescribed motions use; error
    O(h⁶) in q, O(h⁵) in q̇), q̇_ref its derivative, u_ff the not-a-knot cubic spline of the sampled
    loads (O(h⁴)). One evaluation per call gives them all."""
    from scipy.interpolate import CubicSpline, PPoly  # here: a cycle without this run skips it

    position = PPoly.from_bernstein_basis(quintic_hermite(t, q, v, a))
    rate = position.derivative()
    loads = CubicSpline(t, u)
    degree = position.c.shape[0]

    def padded(c: np.ndarray) -> np.ndarray:
        return np.concatenate([np.zeros((degree - c.shape[0], *c.shape[1:])), c])

    return PPoly(np.concatenate([position.c, padded(rate.c), padded(loads.c)], axis=2), t)


class CycleServo:
    """The computed-torque law of one smooth piece of the cycle (a stage, or the hold after
    it), a ``Controller`` of :func:`feeder.chain.simulate` (PROTOCOL: ``n_states``, ``start``,
    ``__call__``); q, q̇ in Pinocchio's order.

    Args:
        t: The piece's sample times [s], (n,), n ≥ 2 (the hold: its two ends).
        q, v, a: The reference's actuated coordinates, rates and accelerations at the samples
            (n, 2): [r2, φ4] [m, rad].
        u: The feedforward [piston force N, forearm moment N·m] at the samples, (n, 2).
        columns: The actuated joints' velocity indices in Pinocchio's v, (2,).
        kp, kd: Gains (2,) (:meth:`ServoGains.gains`).
        low, high: Drive limits (2,) (:meth:`ServoGains.limits`).
        actuator_hz: The drives' lag bandwidth [Hz], or None.
        x0: The drives' forces at the start (2,), carried from the previous piece (a lagged
            drive), or None: the command at the start.
    """

    def __init__(self, t, q, v, a, u, columns, kp, kd, low, high, actuator_hz=None, x0=None):
        self.reference = _channels(t, q, v, a, u)
        self.columns = np.asarray(columns, dtype=int)
        self.kp, self.kd, self.low, self.high = kp, kd, low, high
        self.rate = None if actuator_hz is None else 2.0 * math.pi * actuator_hz
        self.n_states = 0 if self.rate is None else 2
        self.x0 = x0
        self._none = np.zeros(0)

    def command(self, t, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """The unclipped command [N, N·m] at time t [s] and state q, q̇: (2,) for one instant
        (q, v (nv,)), (n, 2) for n (t (n,), q, v (n, nv))."""
        r = self.reference(t)
        columns = self.columns
        return (
            r[..., 4:]
            + self.kp * (r[..., :2] - q[..., columns])
            + self.kd * (r[..., 2:4] - v[..., columns])
        )

    def start(self, t0: float, q0: np.ndarray, v0: np.ndarray) -> np.ndarray:
        """The drives' forces at the start (2,), or no state without a lag."""
        if self.rate is None:
            return self._none
        if self.x0 is not None:
            return np.asarray(self.x0, dtype=float)
        return np.clip(self.command(t0, q0, v0), self.low, self.high)

    def __call__(self, t: float, q: np.ndarray, v: np.ndarray, x: np.ndarray):
        """(u, ẋ): the applied forces (2,) and the drives' state rates."""
        u = np.clip(self.command(t, q, v), self.low, self.high)
        if self.rate is None:
            return u, self._none
        return x, self.rate * (u - x)

    def at_samples(self, t: np.ndarray, q: np.ndarray, v: np.ndarray, x: np.ndarray):
        """The applied forces at N samples at once (the engine's ``Controller.at_samples``):
        (N, 2), given times (N,), states q, q̇ (N, nv) and the drives' forces x (N, n_states)."""
        if self.rate is None:
            return np.clip(self.command(t, q, v), self.low, self.high)
        return x
