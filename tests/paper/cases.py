"""What the tests of the hand-derived equations share: random assembled states of both devices,
a per-sample Pinocchio reference in paper order, central differences, poses near the toggle.

Cached functions (as in tests/dynamics/cases.py), so that the test modules of feeder.paper
build each device's states and Pinocchio models once per session.

Closure forces: Pinocchio solves M a + b − τ = Jᵀ λ_c with J = R_c1ᵀ ∂(p_piston_pin −
p_arm_pin)/∂q (the CONTACT_3D in the LOCAL frame c1 of ``piston_pin``, rotation R_c1 = R_z(φ1)),
the paper M q̈ + C q̇ + g − τ = −J_fᵀ λ with J_f = ∂f/∂q the x, y rows of the same difference in
world axes (its z row is identically zero). Equating, J_fᵀ (−λ) = J_fᵀ (R_c1 λ_c)_{x,y} and J_f
has full row rank, so λ = −(R_c1 λ_c)_{x,y} = −R_c1[:2, :] λ_c. Likewise λ = −(the world-frame
force of the arm on the piston) of :class:`feeder.dynamics.inverse.ActuatorLoads`.
"""

from __future__ import annotations

import math
from functools import cache
from typing import NamedTuple

import numpy as np
import pinocchio as pin

from feeder.device.feeder import Feeder, load_feeder
from feeder.device.loop import arm_travel, loop_state, solve_loop, transmission_sine
from feeder.device.parameters import FeederParameters
from feeder.dynamics.inverse import actuator_loads, check_cycle_motion
from feeder.dynamics.models import FeederDynamics

DEVICE_NAMES = ("projectile", "charge")
"""Both built-in devices: the charge feeder is mirrored (c, z5 < 0) with another payload."""

N_STATES = 200
FD_STEP = 1e-6
FD_RTOL = 1e-8
"""Central differences with h = 1e-6 [rad or m], error relative to the function's size |f|:
round-off ~10 ε |f| / h ≈ 2e-9 |f|, truncation h² |f‴| / 6 ≈ 2e-10 |f| for lengths ≳ 0.1 m."""
PROXIMAL = pin.ProximalSettings(1e-14, 1e-8, 50)
"""mu > 0: the planar loop's out-of-plane closure row is redundant (mu = 0 gives NaN)."""
BISECTION_STEPS = 60
"""Halvings of a bracket of < 1 rad: 2⁻⁶⁰ rad, below double-precision spacing of the angle."""


class States(NamedTuple):
    """N_STATES random assembled states, paper order: q, q̇ (J q̇ = 0), q̈ (closure-consistent),
    grip flags (0/1) and random actuator forces τ = [0, F, 0, τ4]."""

    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    gripped: np.ndarray
    tau: np.ndarray


@cache
def device(name: str) -> Feeder:
    return load_feeder(name)


@cache
def random_states(name: str) -> States:
    p = device(name).params
    rng = np.random.default_rng(20240614)
    phi3 = rng.uniform(p.phi3_load, p.phi3_load + arm_travel(p.elevation_min), N_STATES)
    phi4 = rng.uniform(-p.phi4_limit, p.phi4_limit, N_STATES)
    rates = rng.normal(0.0, 1.0, (N_STATES, 2))
    accelerations = rng.normal(0.0, 3.0, (N_STATES, 2))
    loop = loop_state(
        p, phi3, phi4, (rates[:, 0], rates[:, 1]), (accelerations[:, 0], accelerations[:, 1])
    )
    gripped = rng.integers(0, 2, N_STATES)
    tau = np.column_stack(
        [
            np.zeros(N_STATES),
            rng.normal(0, 3000, N_STATES),
            np.zeros(N_STATES),
            rng.normal(0, 30, N_STATES),
        ]
    )
    return States(loop.q, loop.v, loop.a, gripped, tau)


def relative_error(value: np.ndarray, reference: np.ndarray, axes: tuple[int, ...]) -> np.ndarray:
    """max |value − reference| / max |reference| over ``axes``."""
    return np.max(np.abs(value - reference), axis=axes) / np.max(np.abs(reference), axis=axes)


def assert_derivative(derivative, function, x, step=FD_STEP):
    """``derivative`` (..., *shape, 4) equals the central difference of ``function`` at x
    ((..., 4) → (..., *shape)) within FD_RTOL of the function's size."""
    columns = []
    for k in range(x.shape[-1]):
        dx = np.zeros(x.shape[-1])
        dx[k] = step
        columns.append((function(x + dx) - function(x - dx)) / (2.0 * step))
    scale = max(1.0, float(np.max(np.abs(function(x)))))
    np.testing.assert_allclose(
        derivative, np.stack(columns, axis=-1), rtol=0, atol=FD_RTOL * scale
    )


class PinocchioReference:
    """Per-sample Pinocchio dynamics of the feeder, with and without the payload, paper order.

    Pinocchio is called directly (crba, nonLinearEffects, computeGeneralizedGravity,
    constraintDynamics) on the two models of :class:`feeder.dynamics.models.FeederDynamics`
    (the payload merged into the forearm body, and without it), so that the hand-derived
    equations and this reference share only the parameter set.
    """

    def __init__(self, feeder: Feeder):
        self.feeder = feeder
        self.dynamics_models = FeederDynamics(feeder)
        self.models = {k: case.model for k, case in enumerate(self.dynamics_models.cases)}
        self.datas = {k: m.createData() for k, m in self.models.items()}
        self.cmodels = feeder.chain.constraint_models
        self.cdatas = {}
        for k, model in self.models.items():
            self.cdatas[k] = pin.StdVec_RigidConstraintData()
            self.cdatas[k].append(self.cmodels[0].createData())
            pin.initConstraintDynamics(model, self.datas[k], self.cmodels, self.cdatas[k])

    def _paper(self, matrix):
        return matrix[np.ix_(self.feeder.index, self.feeder.index)]

    def dynamics(self, q, v, held):
        """M (4, 4), C q̇ (4,), g (4,) in paper order."""
        f, model, data = self.feeder, self.models[held], self.datas[held]
        qp, vp = f.to_pinocchio(q), f.to_pinocchio(v)
        mass = self._paper(pin.crba(model, data, qp))
        gravity = pin.computeGeneralizedGravity(model, data, qp).copy()
        coriolis = pin.nonLinearEffects(model, data, qp, vp) - gravity
        return mass, f.to_paper(coriolis), f.to_paper(gravity)

    def forward(self, q, v, tau, held):
        """constraintDynamics: q̈ (4,) and λ (2,) in the paper's convention."""
        f, model, data = self.feeder, self.models[held], self.datas[held]
        a = pin.constraintDynamics(
            model,
            data,
            f.to_pinocchio(q),
            f.to_pinocchio(v),
            f.to_pinocchio(tau),
            self.cmodels,
            self.cdatas[held],
            PROXIMAL,
        )
        assert PROXIMAL.iter < PROXIMAL.max_iter
        return f.to_paper(a), -self.cdatas[held][0].oMc1.rotation[:2, :] @ data.lambda_c

    def inverse(self, q, v, a, gripped):
        """The product's Pinocchio inverse dynamics: columns F, τ4, λ1, λ2, shape (N, 4)."""
        dyn = self.dynamics_models
        loads = actuator_loads(dyn, check_cycle_motion(dyn, q, v, a, gripped))
        return np.column_stack(
            [loads.piston_force, loads.forearm_torque, -loads.closure_force[:, :2]]
        )


@cache
def pinocchio_reference(name: str) -> PinocchioReference:
    return PinocchioReference(device(name))


def pose_near_toggle(p: FeederParameters, degrees: float):
    """An assembled loop state (q, q̇, q̈ of shape (4,)) whose transmission angle is ``degrees``
    from the toggle where the piston axis runs along the arm lever (φ1 = φ3, the pin beyond
    the arm pivot A on the line B–A), with φ4 = 0 and unit rates and accelerations.

    The toggle arm angle is atan2(L2, L1); |sin(φ1 − φ3)| grows from 0 there as the arm turns
    away (up to 60° further on, far from the other toggle), so bisection on φ3 finds it. The
    pose ignores the end stops: the hand-derived equations do not check them.
    """
    target = math.sin(math.radians(degrees))

    def sine(phi3):
        return transmission_sine(solve_loop(p, phi3).q) - target

    low, high = math.atan2(p.L2, p.L1), math.atan2(p.L2, p.L1) + math.radians(60.0)
    assert sine(low) < 0.0 < sine(high)
    for _ in range(BISECTION_STEPS):
        middle = 0.5 * (low + high)
        low, high = (middle, high) if sine(middle) < 0.0 else (low, middle)
    loop = solve_loop(p, 0.5 * (low + high), 0.0, (1.0, 1.0), (1.0, 1.0))
    return loop.q, loop.v, loop.a
