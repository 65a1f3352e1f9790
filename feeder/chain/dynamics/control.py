"""Actuated joints under control: a computed-torque controller for forward runs.

The law (the computed-torque law: proportional–derivative feedback with the inverse dynamics of
the reference as feedforward). At the time t and state (q, q̇) each controlled joint j is
commanded the acceleration

    q̈*_j = q̈_ref,j + K_d (q̇_ref,j − q̇_j) + K_p (q_ref,j − q_j)

(K_p [1/s²], K_d [1/s]: the gains of :class:`~feeder.chain.model.control.ControlSpec`; a
continuous joint's error wrapped into [−π, π)), and the drives u are those that give the
controlled joints these accelerations in the closed chain's own equations of motion — the
constrained inverse dynamics at the current state, the other actuated joints undriven. The
accelerations of the forward run's equations (:mod:`.forward_equations`) are affine in the
drives, q̈(u) = q̈(0) + G u (G the constrained inverse inertia seen from the actuated joints),
so u solves G_cc u = q̈*_c − q̈_c(0) on the controlled rows c: q̈(0) is the run's own right-hand
side undriven (gravity, force elements, a moving base's terms), and G's columns the responses to
unit drives of the same Pinocchio ``constraintDynamics`` (its proximal solver, Baumgarte terms)
the run integrates. Hence:

* on the reference with no disturbance, u is the inverse dynamics of the reference and the run
  reproduces it to the integrator's tolerance;
* off it, each controlled joint's error e = q_ref − q obeys ë + K_d ė + K_p e = 0 exactly, for
  any inertia (K_p = ω², K_d = 2ζω: natural frequency ω, damping ratio ζ).

Limits and lag, per joint. The law's force (the *demand*) is clipped to the force limits [low,
high] (the *command*: a saturated actuator, flagged). Without a lag the command acts. With a
first-order lag T (a servo-valve's bandwidth 1/(2πT)) the acting force F is a state of the
controller (:class:`~.forward_equations.Controller`): Ḟ = (command − F) / T, clipped to the rate
limit ±r [N/s or N·m/s] (flagged when it is); F starts at the command of the first instant.
A lag, and a saturation, break the exact error equation: with a lag the one-joint loop is of
third order, T s³ + s² + K_d s + K_p = 0 on a joint of constant inertia.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ...exceptions import InputError
from ...validation import did_you_mean
from ..kinematics.joints import kind_of
from ..model.control import ControlSpec
from .forward_equations import BAUMGARTE_RATE, PROXIMAL, ForwardEquations, IntegrationError
from .hybrid_equations import Prescribed
from .inverse import ChainDynamics, check_dynamics


@dataclass(frozen=True)
class ControlRecord:
    """What the controller did at a run's samples (:meth:`ComputedTorque.record`), one column
    per controlled joint (in the order of :attr:`joints`).

    Attributes:
        joints: The controlled joints.
        units: Each one's unit of position: "rad" or "m".
        t: Times [s], (N,).
        reference, reference_rate: q_ref [rad or m] and q̇_ref, (N, n).
        error, error_rate: e = q_ref − q and ė, (N, n) (a continuous joint's e wrapped).
        demand: The law's force before the limits [N or N·m], (N, n).
        command: The demand clipped to the force limits, (N, n).
        force: The acting force (the command, or the lagged actuator's state), (N, n).
        saturated: Demand outside the force limits (bool, (N, n)).
        rate_limited: A lagged actuator's force rate at its limit (bool, (N, n)).
        pressure: Joint → the acting force / the piston area [Pa] (N,), for the joints with
            an area (hydraulic cylinders).
    """

    joints: tuple[str, ...]
    units: tuple[str, ...]
    t: np.ndarray
    reference: np.ndarray
    reference_rate: np.ndarray
    error: np.ndarray
    error_rate: np.ndarray
    demand: np.ndarray
    command: np.ndarray
    force: np.ndarray
    saturated: np.ndarray
    rate_limited: np.ndarray
    pressure: dict[str, np.ndarray]

    def peak_error(self) -> np.ndarray:
        """Largest |e| per joint [rad or m], (n,)."""
        return np.abs(self.error).max(axis=0)

    def rms_error(self) -> np.ndarray:
        """Root mean square of e over the run (trapezoidal in time) per joint [rad or m], (n,)."""
        span = self.t[-1] - self.t[0]
        return np.sqrt(np.trapezoid(self.error**2, self.t, axis=0) / span)

    def time_saturated(self) -> np.ndarray:
        """Time [s] with the demand outside the force limits per joint, (n,): the trapezoidal
        integral of the flag over the samples (each flag held for its half intervals)."""
        return np.trapezoid(self.saturated.astype(float), self.t, axis=0)

    def lines(self) -> list[str]:
        """The summary's lines: per joint the peak and RMS error, the time saturated, the time
        rate-limited and the peak pressure."""
        span = self.t[-1] - self.t[0]
        lines = []
        saturated_time = self.time_saturated()
        rows = zip(self.joints, self.units, self.peak_error(), self.rms_error(), saturated_time,
                   strict=True)  # fmt: skip
        for j, (joint, unit, peak, rms, saturated) in enumerate(rows):
            flags = self.saturated[:, j]
            text = (
                f"  control of {joint!r}: peak error {peak:.3g} {unit}, RMS error {rms:.3g} "
                f"{unit}; saturated {saturated:.4g} s ({saturated / span:.1%} of the run)"
            )
            if flags.any():
                times = self.t[flags]
                text += f", from t = {times[0]:.6g} s to {times[-1]:.6g} s"
            if self.rate_limited[:, j].any():
                text += f"; rate-limited at {int(self.rate_limited[:, j].sum())} samples"
            if joint in self.pressure:
                text += f"; peak pressure {np.abs(self.pressure[joint]).max() / 1e6:.4g} MPa"
            lines.append(text)
        return lines


class ComputedTorque:
    """The computed-torque controller of the module docstring, a
    :class:`~.forward_equations.Controller` for :func:`~.forward.simulate`.

    Args:
        dyn: The chain's dynamics (its actuated joints receive the drives).
        specs: The controlled joints (actuated, each once).
        rate: The Baumgarte rate ω [1/s] of the run's equations (:func:`~.forward.simulate`'s
            ``rate``): G and q̈(0) are those of the run.

    Attributes:
        n_states: One per lagged joint (its acting force [N or N·m]).

    Raises:
        InputError: No spec, a joint that is not actuated (with the nearest) or controlled
            twice, a piston area on a joint that is not prismatic.
    """

    def __init__(
        self, dyn: ChainDynamics, specs: Sequence[ControlSpec], rate: float = BAUMGARTE_RATE
    ):
        check_dynamics(dyn)
        specs = tuple(specs)
        if not specs or not all(isinstance(spec, ControlSpec) for spec in specs):
            raise InputError(f"specs must be one ControlSpec or more, got {specs!r}")
        model = dyn.chain.model
        channels = []
        for spec in specs:
            if spec.joint not in dyn.actuated:
                raise InputError(
                    f"{spec.where}: joint {spec.joint!r} is not actuated; "
                    f"{did_you_mean(spec.joint, dyn.actuated)}the actuated joints are "
                    f"{list(dyn.actuated)}"
                )
            if dyn.actuated.index(spec.joint) in channels:
                raise InputError(f"{spec.where}: joint {spec.joint!r} is controlled twice")
            channels.append(dyn.actuated.index(spec.joint))
            joint = model.joints[model.getJointId(spec.joint)]
            if spec.area is not None and kind_of(joint) != "prismatic":
                raise InputError(
                    f"{spec.where}: a piston area is for a prismatic joint (a cylinder); "
                    f"{spec.joint!r} is {kind_of(joint)}"
                )
        self.dyn, self.specs, self.joints = dyn, specs, tuple(spec.joint for spec in specs)
        kinds = [kind_of(model.joints[model.getJointId(joint)]) for joint in self.joints]
        self.units = tuple("m" if kind == "prismatic" else "rad" for kind in kinds)
        self.channels = np.array(channels, dtype=int)
        self.columns = np.array(dyn.columns, dtype=int)[self.channels]
        joints = [model.joints[model.getJointId(spec.joint)] for spec in specs]
        self.coordinates = np.array([joint.idx_q for joint in joints], dtype=int)
        self.turning = np.array([joint.nq == 2 for joint in joints])  # continuous: (cos, sin)
        self.curves = [Prescribed(s.t, s.q[:, None], s.v[:, None], s.a[:, None]) for s in specs]
        self.low = np.array([spec.force_limit[0] for spec in specs])
        self.high = np.array([spec.force_limit[1] for spec in specs])
        self.lag = np.array([spec.lag for spec in specs])
        self.lagged = self.lag > 0.0
        self.rate_limit = np.array([spec.rate_limit for spec in specs])[self.lagged]
        self.n_states = int(self.lagged.sum())
        self.n_actuated = len(dyn.actuated)
        self.equations = ForwardEquations(dyn, None, rate)

    def check_covers(self, t0: float, t1: float) -> None:
        """Refuse a run from t0 to t1 [s] beyond a reference table's times."""
        for spec in self.specs:
            if t0 < spec.t[0] or t1 > spec.t[-1]:
                raise InputError(
                    f"{spec.where}: the reference {spec.reference.name} covers t = "
                    f"{spec.t[0]:g} … {spec.t[-1]:g} s, the run {t0:g} … {t1:g} s: a shorter "
                    "run or a longer table"
                )

    def reference(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """q_ref [rad or m], q̇_ref, q̈_ref at time t [s], (n,) each: the quintic Hermite
        through each table's positions, rates and accelerations
        (:class:`~.hybrid_equations.Prescribed`)."""
        values = np.array([[part[0] for part in curve(t)] for curve in self.curves])
        return values[:, 0], values[:, 1], values[:, 2]

    def errors(self, reference: tuple, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, ...]:
        """e = q_ref − q and ė (n,) for the ``reference`` (q_ref, q̇_ref, q̈_ref) of
        :meth:`reference` and the state (q, v) (a continuous joint's e wrapped)."""
        position, rate, _ = reference
        i = self.coordinates
        angle = np.where(self.turning, np.arctan2(q[np.minimum(i + 1, q.size - 1)], q[i]), q[i])
        gap = position - angle
        gap = np.where(self.turning, np.mod(gap + np.pi, 2.0 * np.pi) - np.pi, gap)
        return gap, rate - v[self.columns]

    def demand(self, t: float, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """The law's drives (n,) [N or N·m] at time t [s] and state (q, v), before the limits
        (module docstring)."""
        reference = self.reference(t)
        error, error_rate = self.errors(reference, q, v)
        acceleration = reference[2]
        gains = np.array([(spec.kp, spec.kd) for spec in self.specs])
        target = acceleration + gains[:, 1] * error_rate + gains[:, 0] * error
        free = self.equations.accelerations(t, q, v)[0]  # the drives at 0: what else acts
        tau = np.zeros(v.size)
        zero = self._accelerations(q, v, tau)
        response = np.empty((self.columns.size, self.columns.size))
        for k, column in enumerate(self.columns):
            tau[column] = 1.0  # a unit drive [N or N·m]: G's column, the map being affine
            response[:, k] = (self._accelerations(q, v, tau) - zero)[self.columns]
            tau[column] = 0.0
        try:
            return np.linalg.solve(response, target - free[self.columns])
        except np.linalg.LinAlgError:
            raise IntegrationError(
                f"at t = {t:.6g} s the controlled joints {list(self.joints)} cannot be "
                "accelerated independently (a singular pose of the actuation)"
            ) from None

    def _accelerations(self, q: np.ndarray, v: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """q̈ (nv,) of the chain's constrained equations under the generalized forces tau alone
        (nv,): their differences give G."""
        e = self.equations
        return pin.constraintDynamics(e.model, e.data, q, v, tau, e.constraints, e.datas, PROXIMAL)

    def start(self, t0: float, q0: np.ndarray, v0: np.ndarray) -> np.ndarray:
        """The lagged actuators' forces at t0 [s] (n_states,): their commands there."""
        command = np.clip(self.demand(t0, q0, v0), self.low, self.high)
        return command[self.lagged]

    def _act(self, command: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, ...]:
        """The acting forces (n,), the states' rates (n_states,) and the rate-limited flags
        (n_states,) for the command (n,) and the states x."""
        force = command.copy()
        force[self.lagged] = x
        wanted = (command[self.lagged] - x) / self.lag[self.lagged]
        rate = np.clip(wanted, -self.rate_limit, self.rate_limit)
        return force, rate, rate != wanted

    def __call__(
        self, t: float, q: np.ndarray, v: np.ndarray, x: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """The actuated joints' drives (n_actuated,) [N or N·m] (0 for those not controlled)
        and the states' rates (n_states,) [N/s or N·m/s] at time t [s], state (q, v, x)."""
        command = np.clip(self.demand(t, q, v), self.low, self.high)
        force, rate, _ = self._act(command, x)
        u = np.zeros(self.n_actuated)
        u[self.channels] = force
        return u, rate

    def record(
        self, t: np.ndarray, q: np.ndarray, v: np.ndarray, x: np.ndarray | None = None
    ) -> ControlRecord:
        """What the controller did at a run's samples t (N,), q (N, nq), v (N, nv) and states
        x (N, n_states) (None without states)."""
        n = t.size
        x = np.zeros((n, 0)) if x is None else x
        columns = {name: np.empty((n, len(self.specs))) for name in ("ref", "rate", "e", "de")}
        demand = np.empty((n, len(self.specs)))
        force = np.empty_like(demand)
        limited = np.zeros((n, len(self.specs)), dtype=bool)
        for k in range(n):
            reference = self.reference(t[k])
            columns["ref"][k], columns["rate"][k] = reference[:2]
            columns["e"][k], columns["de"][k] = self.errors(reference, q[k], v[k])
            demand[k] = self.demand(t[k], q[k], v[k])
            command = np.clip(demand[k], self.low, self.high)
            force[k], _, limited[k, self.lagged] = self._act(command, x[k])
        command = np.clip(demand, self.low, self.high)
        pressure = {
            spec.joint: force[:, j] / spec.area
            for j, spec in enumerate(self.specs)
            if spec.area is not None
        }
        return ControlRecord(
            joints=self.joints,
            units=self.units,
            t=t,
            reference=columns["ref"],
            reference_rate=columns["rate"],
            error=columns["e"],
            error_rate=columns["de"],
            demand=demand,
            command=command,
            force=force,
            saturated=(demand < self.low) | (demand > self.high),
            rate_limited=limited,
            pressure=pressure,
        )
