"""The equations of a forward run: the right-hand side (q̇, q̈, power) of a closed chain's state.

The state (q, q̇) follows the index-1 equations of the closed chain

    [M  Jᵀ] [ q̈]   [τ − b          ]
    [J  0 ] [−λ] = [−J̇ q̇ − K_d J q̇ − K_p r(q)]

with τ = Sᵀ u(t, q, q̇) (the actuated joints' drive, given by the caller: :data:`Actuation`) plus
the force elements' generalized forces (:mod:`~feeder.chain.dynamics.elements`), b the Coriolis,
centrifugal and gravity terms, and Baumgarte's corrector K_p = ω², K_d = 2ω on the loop residual
r (critically damped: an error decays like e^(−ω t)). The accelerations come from Pinocchio's
``constraintDynamics`` on the chain's own constraint models (its proximal solver takes the
redundant rows of a planar loop); q̇ from q̇ (the rotations' and the unit circles' rates for the
joints whose q is not a vector: :class:`~feeder.chain.kinematics.joints.ConfigurationRate`). The
power of the non-conservative forces (drives, dampers, pushes, pressures, loads) is the last
component, so that their work is integrated with the state.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pinocchio as pin

from ...exceptions import FeederError, InputError
from ...validation import check_finite
from ..kinematics.joints import ConfigurationRate
from .inverse import ChainDynamics

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


class IntegrationError(FeederError):
    """A forward run stopped: the integrator could not meet its tolerance (a singular pose, an
    unbounded acceleration), the run reached a singular pose where its loads cannot be computed,
    or the forces became NaN."""


class ForwardEquations:
    """The right-hand side of a run (module docstring) on one pinocchio.Data: called as
    f(t, y) with y = (q, q̇, W) of size nq + nv + 1, it returns the rate of q (nq,), q̈ (nv,) and
    the power [W]; ``count``: the calls so far."""

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
        u = self.actuation(t, q, v)
        if not (type(u) is np.ndarray and u.dtype == np.float64 and np.isfinite(u).all()):
            # anything but finite floats (or not an array): converted or refused, the message
            # built only here (each evaluation of the right-hand side passes this way)
            u = check_finite(f"actuation at t = {t:.6g} s [N or N·m]", u)
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
