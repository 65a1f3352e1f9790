"""Forward simulation of any closed chain driven by actuator forces.

The accelerations come from the closed chain's equations of motion with the closure rows of
:class:`~feeder.chain.model.closure.ClosedChain` (any mix of point, weld and revolute cuts):

    [M  Jᵀ] [ q̈]   [Sᵀ u(t, q, q̇) − b      ]
    [J  0 ] [−λ] = [−J̇ q̇ − 2ω J q̇ − ω² r(q)]

with M from CRBA, b = Coriolis, centrifugal and gravity terms (the model's gravity), u the
actuator forces (a function of time and state given by the caller), and Baumgarte's corrector
of rate ω (critically damped: the loop residual r decays like e^(−ω t)). The system is solved in
the least-squares sense, so redundant closure rows (a planar loop) are harmless.

The state is integrated with the classical fourth-order Runge–Kutta method on the caller's time
grid. Drift control: Baumgarte's corrector always, and optionally a projection after every step
(:class:`~feeder.chain.assembly.partition.Partition`: Newton back onto the closure at the step's
independent coordinates, and the velocity onto J q̇ = 0).

Reports: the closure residual at every sample (drift), the mechanical energy (kinetic plus
potential) against the work done by the actuators (the balance of a conservative chain), and the
tracking error against a reference motion.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ...exceptions import InputError, UnreachablePoseError
from ...validation import check_finite, check_number, check_vector
from ..assembly.partition import Partition
from ..kinematics.joints import angle_columns, angular_difference
from .inverse import ChainDynamics

BAUMGARTE_RATE = 20.0
"""Default Baumgarte rate ω [1/s]: a loop error decays in 1/ω = 50 ms, slow enough for steps of
a few milliseconds (hω ≪ 1) and fast compared with a mechanism's motion."""

START_TOLERANCE = 1e-9
"""Largest accepted closure residual [m, rad] of the initial state (and of its velocity rows,
per second): assembly closes loops to ~1e-13; 1e-9 leaves room for rounded data."""

Actuation = Callable[[float, np.ndarray, np.ndarray], np.ndarray]
"""u(t, q, q̇): the actuator forces [N or N·m] at time t [s], shape (n_actuated,)."""


@dataclass(frozen=True)
class ForwardRun:
    """A forward simulation's samples and reports.

    Attributes:
        t: Times [s], (N,).
        q: Configurations, (N, nq).
        v: Velocities, (N, nv).
        residual: Largest closure residual [m, rad] at each sample, (N,).
        energy: Kinetic plus potential energy [J], (N,).
        work: Work done by the actuators since t[0] [J], (N,) (trapezoidal rule).
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    residual: np.ndarray
    energy: np.ndarray
    work: np.ndarray

    def drift(self) -> float:
        """Largest closure residual over the run [m, rad]."""
        return float(self.residual.max())

    def energy_error(self) -> float:
        """Largest |E(t) − E(0) − W(t)| [J]: zero for an exact run of a conservative chain
        (no friction; the trapezoidal work is exact to O(h²))."""
        return float(np.abs(self.energy - self.energy[0] - self.work).max())

    def tracking(self, model: pin.Model, q_reference: np.ndarray) -> np.ndarray:
        """Largest |q ⊖ q_reference| of every velocity component over the run, (nv,): the
        difference on the model's Lie groups (a revolute angle wrapped by a turn, a quaternion
        of opposite sign, count as equal)."""
        reference = check_finite("q_reference", q_reference)
        if reference.shape != self.q.shape:
            raise InputError(f"q_reference must have shape {self.q.shape}, got {reference.shape}")
        angles = angle_columns(model)
        gaps = np.array(
            [
                angular_difference(model, r, q, angles)
                for r, q in zip(reference, self.q, strict=True)
            ]
        )
        return np.abs(gaps).max(axis=0)


def accelerations(
    dyn: ChainDynamics, q: np.ndarray, v: np.ndarray, u: np.ndarray, rate: float = BAUMGARTE_RATE
) -> tuple[np.ndarray, np.ndarray]:
    """q̈ (nv,) and the closure forces λ (nc,) of the closed chain under actuator forces ``u``
    (one state, checked by the caller; module docstring)."""
    chain, model, data = dyn.chain, dyn.chain.model, dyn.data
    mass = pin.crba(model, data, q)
    mass = np.triu(mass) + np.triu(mass, 1).T  # CRBA fills the upper triangle
    bias = pin.nonLinearEffects(model, data, q, v)
    tau = np.zeros(model.nv)
    tau[dyn.columns] = u
    jac = chain.jacobian(q)
    target = -chain.bias(q, v) - 2.0 * rate * (jac @ v) - rate**2 * chain.residual(q)
    nc = jac.shape[0]
    kkt = np.zeros((model.nv + nc, model.nv + nc))
    kkt[: model.nv, : model.nv] = mass
    kkt[: model.nv, model.nv :] = jac.T
    kkt[model.nv :, : model.nv] = jac
    solution = np.linalg.lstsq(kkt, np.concatenate([tau - bias, target]), rcond=None)[0]
    return solution[: model.nv], -solution[model.nv :]


def _energy(dyn: ChainDynamics, q: np.ndarray, v: np.ndarray) -> float:
    model, data = dyn.chain.model, dyn.data
    return float(
        pin.computeKineticEnergy(model, data, q, v) + pin.computePotentialEnergy(model, data, q)
    )


def simulate(
    dyn: ChainDynamics,
    actuation: Actuation,
    t: np.ndarray,
    q0: np.ndarray,
    v0: np.ndarray,
    *,
    rate: float = BAUMGARTE_RATE,
    projection: Partition | None = None,
) -> ForwardRun:
    """Integrate the closed chain driven by ``actuation`` from (q0, v0) over the times ``t``.

    Args:
        dyn: The chain's dynamics (its actuated joints receive ``actuation``'s forces).
        actuation: u(t, q, q̇) → actuator forces (n_actuated,) [N or N·m].
        t: Increasing sample times [s], (N,), N ≥ 2; the integration steps are their spacing.
        q0, v0: Initial state, (nq,), (nv,) (assembled: e.g. Partition.assemble/velocity).
        rate: Baumgarte rate ω [1/s] (0 turns the corrector off).
        projection: A partition of the chain to project every step back onto the closure with,
            or None for Baumgarte's corrector alone.

    Raises:
        InputError: Bad times, state or rate, an initial velocity that opens the loops, or
            actuation values that are not n_actuated finite numbers.
        UnreachablePoseError: An initial configuration that does not close the loops.
    """
    chain, model = dyn.chain, dyn.chain.model
    t = check_finite("t", t)
    if t.ndim != 1 or t.size < 2 or np.any(np.diff(t) <= 0.0):
        raise InputError(f"t must be increasing sample times, at least two, got shape {t.shape}")
    q, v = chain.check_q(q0), chain.check_v("v0", v0)
    rate = check_number("Baumgarte rate [1/s]", rate)
    if not rate >= 0.0:
        raise InputError(f"the Baumgarte rate must be ≥ 0 [1/s], got {rate!r}")
    gap = float(np.abs(chain.residual(q)).max(initial=0.0))
    if gap > START_TOLERANCE:
        raise UnreachablePoseError(
            f"q0 does not close the loops (residual {gap:.3e} > {START_TOLERANCE:g}): assemble "
            "it first (Partition.assemble)"
        )
    opening = float(np.abs(chain.jacobian(q) @ v).max(initial=0.0))
    if opening > START_TOLERANCE * max(1.0, float(np.abs(v).max())):
        raise InputError(
            f"v0 opens the loops at {opening:.3e} per second: use Partition.velocity for it"
        )
    n_act = len(dyn.columns)

    def drive(time: float, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        return check_vector(f"actuation at t = {time:.6g} s", actuation(time, q, v), n_act)

    def rates(time: float, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        u = drive(time, q, v)
        return v, accelerations(dyn, q, v, u, rate)[0]

    n = t.size
    qs, vs = np.empty((n, model.nq)), np.empty((n, model.nv))
    power = np.empty(n)
    qs[0], vs[0] = q, v
    power[0] = drive(t[0], q, v) @ v[dyn.columns]
    for k in range(n - 1):
        h = t[k + 1] - t[k]
        dq1, dv1 = rates(t[k], q, v)
        q2, v2 = pin.integrate(model, q, 0.5 * h * dq1), v + 0.5 * h * dv1
        dq2, dv2 = rates(t[k] + 0.5 * h, q2, v2)
        q3, v3 = pin.integrate(model, q, 0.5 * h * dq2), v + 0.5 * h * dv2
        dq3, dv3 = rates(t[k] + 0.5 * h, q3, v3)
        q4, v4 = pin.integrate(model, q, h * dq3), v + h * dv3
        dq4, dv4 = rates(t[k + 1], q4, v4)
        q = pin.integrate(model, q, h / 6.0 * (dq1 + 2.0 * dq2 + 2.0 * dq3 + dq4))
        v = v + h / 6.0 * (dv1 + 2.0 * dv2 + 2.0 * dv3 + dv4)
        if projection is not None:
            q = projection.assemble(q)
            v = projection.velocity(q, v[projection.independent])
        qs[k + 1], vs[k + 1] = q, v
        power[k + 1] = drive(t[k + 1], q, v) @ v[dyn.columns]
    residual = np.array([np.abs(chain.residual(x)).max(initial=0.0) for x in qs])
    energy = np.array([_energy(dyn, x, y) for x, y in zip(qs, vs, strict=True)])
    work = np.concatenate([[0.0], np.cumsum(0.5 * (power[1:] + power[:-1]) * np.diff(t))])
    return ForwardRun(t=t, q=qs, v=vs, residual=residual, energy=energy, work=work)
