"""Joints under control, driven by their actuators or by force elements' pushes: a
computed-torque controller for forward runs.

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

A force element's push. A spec with an ``element`` (a :class:`~feeder.chain.model.forces.Spring`
or :class:`~feeder.chain.model.forces.Cylinder` of the chain) tracks its joint's reference with
the element's push P [N] (extending) instead of the joint's actuator: the joint need not be
actuated (it must not be: one drive per joint), and the element must move it. The push enters
the run's τ as P g_e(q), g_e = dℓ/dq the element's generalized force per newton
(:meth:`~.elements.BoundElements.unit_pushes`), so the accelerations stay affine in the drives
and pushes together, τ = S u_joints + Σ_e g_e(q) P_e, and G's column of a push is the response
to g_e: the law, the limits (in N, N/s) and the lag are those of a drive. The element's push law
is the controller's: one with a push or pressure of its own (not the constant 0) is refused,
rather than silently replaced; its spring and damper act as before. A cylinder's push
P = p_cap A_cap − p_rod A_ann is reported as the chamber pressures that give it: p_cap = P/A_cap
for P ≥ 0, p_rod = −P/A_ann for P < 0, the other chamber at zero gauge [Pa]. The run's loads are
those of the pushes applied (:meth:`~.forward_equations.ForwardEquations.loads_dynamics`). A
push that cannot accelerate the joints it controls (a line across the joint's motion, both ends
on the ground) makes G singular: refused at the start, stopped in the run
(:data:`RANK_TOLERANCE`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pinocchio as pin

from ...exceptions import InputError
from ...validation import did_you_mean
from ..kinematics.joints import kind_of
from ..model.control import ControlSpec
from ..model.forces import Cylinder
from .control_record import ControlRecord
from .elements import LineElement
from .forward_equations import BAUMGARTE_RATE, PROXIMAL, ForwardEquations, IntegrationError
from .hybrid_equations import Prescribed
from .inverse import ChainDynamics, check_dynamics
from .pushed_elements import chambers, pushed_element, pushed_joint

RANK_TOLERANCE = 1e-8
"""G_cc is taken as singular when its smallest singular value, each column divided by the norm
of its drive's whole response q̈ (nv,), is below this: the share of a drive's effect that reaches
the controlled joints. The proximal solver's regularisation (μ = 1e-10) and round-off leave
responses of ~1e-10 and less relative to the column where a drive cannot act on a joint; a drive
that acts reaches it by far more than 1e-8."""


class ComputedTorque:
    """The computed-torque controller of the module docstring, a
    :class:`~.forward_equations.Controller` for :func:`~.forward.simulate`.

    Args:
        dyn: The chain's dynamics (its actuated joints receive the drives, its spring and
            cylinder elements named by the specs the pushes).
        specs: The controlled joints (each once): actuated ones driven themselves, others by
            the push of a force element (:attr:`ControlSpec.element`, each element once).
        rate: The Baumgarte rate ω [1/s] of the run's equations (:func:`~.forward.simulate`'s
            ``rate``): G and q̈(0) are those of the run.

    Attributes:
        n_states: One per lagged joint (its acting force [N or N·m]).
        pushes: The force elements it pushes (the Controller's optional attribute): its u is
            the actuated joints' drives, then these pushes [N].

    Raises:
        InputError: No spec, a joint that is not actuated (with the nearest) or controlled
            twice, a piston area on a joint that is not prismatic; for an element: an unknown one
            (with the nearest), one that is not a spring or a cylinder, has a push or pressure
            law of its own, or is pushed for two joints, a joint that is unknown, not of one
            coordinate or actuated (then its table drives the joint itself), an area.
    """

    def __init__(
        self, dyn: ChainDynamics, specs: Sequence[ControlSpec], rate: float = BAUMGARTE_RATE
    ):
        check_dynamics(dyn)
        specs = tuple(specs)
        if not specs or not all(isinstance(spec, ControlSpec) for spec in specs):
            raise InputError(f"specs must be one ControlSpec or more, got {specs!r}")
        model = dyn.chain.model
        self.n_actuated = len(dyn.actuated)
        lines: list[LineElement] = []
        channels, columns = [], []
        for spec in specs:
            if spec.element is None:
                columns.append(_driven_joint(dyn, spec))
                channels.append(dyn.actuated.index(spec.joint))
            else:
                columns.append(pushed_joint(dyn, spec))
                line = pushed_element(dyn, spec, lines)
                channels.append(self.n_actuated + len(lines))
                lines.append(line)
            if spec.joint in [other.joint for other in specs[: len(channels) - 1]]:
                raise InputError(f"{spec.where}: joint {spec.joint!r} is controlled twice")
        self.dyn, self.specs, self.joints = dyn, specs, tuple(spec.joint for spec in specs)
        self.elements = tuple(spec.element for spec in specs)
        self.lines = tuple(lines)
        self.pushes = tuple(line.name for line in lines)
        kinds = [kind_of(model.joints[model.getJointId(joint)]) for joint in self.joints]
        self.units = tuple("m" if kind == "prismatic" else "rad" for kind in kinds)
        self.channels = np.array(channels, dtype=int)
        self.columns = np.array(columns, dtype=int)
        """The controlled joints' velocity columns (n,)."""
        joints = [model.joints[model.getJointId(spec.joint)] for spec in specs]
        self.coordinates = np.array([joint.idx_q for joint in joints], dtype=int)
        self.turning = np.array([joint.nq == 2 for joint in joints])  # continuous: (cos, sin)
        self.curves = [Prescribed(s.t, s.q[:, None], s.v[:, None], s.a[:, None]) for s in specs]
        self.kp = np.array([spec.kp for spec in specs])
        self.kd = np.array([spec.kd for spec in specs])
        self.low = np.array([spec.force_limit[0] for spec in specs])
        self.high = np.array([spec.force_limit[1] for spec in specs])
        self.lag = np.array([spec.lag for spec in specs])
        self.lagged = self.lag > 0.0
        self.rate_limit = np.array([spec.rate_limit for spec in specs])[self.lagged]
        self.n_states = int(self.lagged.sum())
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

    def inputs(self, q: np.ndarray, t: float) -> np.ndarray:
        """The generalized forces (nv, n) of a unit drive of each spec at q: 1 N or N·m on an
        actuated joint's coordinate, or the element's g_e = dℓ/dq for a unit push (1 N);
        t [s] for the messages."""
        out = np.zeros((self.dyn.chain.model.nv, len(self.specs)))
        pushed = self.channels >= self.n_actuated
        joints = np.flatnonzero(~pushed)
        out[self.columns[joints], joints] = 1.0
        if self.lines:
            out[:, pushed] = self.dyn.elements.unit_pushes(self.lines, q, t)
        return out

    def demand(self, t: float, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """The law's drives and pushes (n,) [N or N·m] at time t [s] and state (q, v), before
        the limits (module docstring).

        Raises:
            IntegrationError: The drives cannot accelerate the controlled joints independently
                (G_cc singular, :data:`RANK_TOLERANCE`).
        """
        reference = self.reference(t)
        error, error_rate = self.errors(reference, q, v)
        target = reference[2] + self.kd * error_rate + self.kp * error
        free = self.equations.accelerations(t, q, v)[0]  # the drives at 0: what else acts
        zero = self._accelerations(q, v, np.zeros(v.size))
        inputs = self.inputs(q, t)
        response = np.empty((self.columns.size, self.columns.size))
        reach = np.empty(self.columns.size)
        for k in range(self.columns.size):  # a unit drive: G's column, the map being affine
            whole = self._accelerations(q, v, inputs[:, k]) - zero
            response[:, k], reach[k] = whole[self.columns], np.linalg.norm(whole)
        if not (np.isfinite(response).all() and np.isfinite(free).all()):
            raise IntegrationError(
                f"the accelerations are not finite at t = {t:.6g} s (a singular pose, bodies "
                "without mass, or forces that are not finite)"
            )
        reach = np.where(reach > 0.0, reach, 1.0)
        # G_cc = S D (D: each drive's reach): one decomposition of the shares S = U Σ Vᵀ tests
        # them and solves G_cc u = b as u = D⁻¹ V Σ⁻¹ Uᵀ b
        left, singular, right = np.linalg.svd(response / reach)
        if singular.min() < RANK_TOLERANCE:
            drives = ", ".join(
                f"the drive of {joint!r}" if element is None else f"the push of {element!r}"
                for joint, element in zip(self.joints, self.elements, strict=True)
            )
            raise IntegrationError(
                f"at t = {t:.6g} s the controlled joints {list(self.joints)} cannot be "
                f"accelerated independently by {drives} (a singular pose of the actuation, or a "
                "force element whose push cannot move its joint)"
            )
        return (right.T @ ((left.T @ (target - free[self.columns])) / singular)) / reach

    def _accelerations(self, q: np.ndarray, v: np.ndarray, tau: np.ndarray) -> np.ndarray:
        """q̈ (nv,) of the chain's constrained equations under the generalized forces tau alone
        (nv,): their differences give G."""
        e = self.equations
        return pin.constraintDynamics(e.model, e.data, q, v, tau, e.constraints, e.datas, PROXIMAL)

    def start(self, t0: float, q0: np.ndarray, v0: np.ndarray) -> np.ndarray:
        """The lagged actuators' forces at t0 [s] (n_states,): their commands there.

        Raises:
            InputError: The drives cannot accelerate the controlled joints at the start (an
                element that cannot move its joint: :meth:`demand`).
        """
        try:
            demand = self.demand(t0, q0, v0)
        except IntegrationError as exc:
            raise InputError(f"at the start of the run: {exc}") from None
        command = np.clip(demand, self.low, self.high)
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
        then the pushes [N] of :attr:`pushes`, and the states' rates (n_states,) [N/s or
        N·m/s] at time t [s], state (q, v, x)."""
        command = np.clip(self.demand(t, q, v), self.low, self.high)
        force, rate, _ = self._act(command, x)
        u = np.zeros(self.n_actuated + len(self.lines))
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
        cylinders = {line.name: line.element for line in self.lines}
        cylinder_pressures = {
            spec.joint: chambers(cylinders[spec.element], force[:, j])
            for j, spec in enumerate(self.specs)
            if isinstance(cylinders.get(spec.element), Cylinder)
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
            elements=self.elements,
            chambers=cylinder_pressures,
        )


def _driven_joint(dyn: ChainDynamics, spec: ControlSpec) -> int:
    """The velocity column of the actuated joint a spec drives itself, checked."""
    if spec.joint not in dyn.actuated:
        raise InputError(
            f"{spec.where}: joint {spec.joint!r} is not actuated; "
            f"{did_you_mean(spec.joint, dyn.actuated)}the actuated joints are "
            f"{list(dyn.actuated)} (or name a force element that moves it: element = …)"
        )
    model = dyn.chain.model
    joint = model.joints[model.getJointId(spec.joint)]
    if spec.area is not None and kind_of(joint) != "prismatic":
        raise InputError(
            f"{spec.where}: a piston area is for a prismatic joint (a cylinder); "
            f"{spec.joint!r} is {kind_of(joint)}"
        )
    return joint.idx_v
