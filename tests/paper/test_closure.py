"""The loop closure of the hand-derived model (feeder.paper.closure): f, J_f and J̇_f q̇ against
the pipeline's closed-form loop, Pinocchio's closure Jacobian and finite differences."""

from __future__ import annotations

import numpy as np

from feeder.paper import closure

from . import cases

ASSEMBLY_ATOL = 1e-15
"""|f| [m] of states assembled by the closed form (feeder.device.loop): lengths < 1 m, so a
few ε · 1 m."""
JACOBIAN_ATOL = 1e-15
"""J_f against Pinocchio's frame Jacobians: entries are lengths < 1 m times sines and cosines of
the same angles, agreement to a few ε."""
ACCELERATION_ATOL = 1e-12
"""J_f q̈ + J̇_f q̇ [m/s²] of the closed-form q̈: each term is ≲ 10 m/s² (rates ~1 rad/s,
accelerations ~3 rad/s², lengths < 1 m), their sum vanishes to ~100 ε of that."""
PINOCCHIO_SAMPLES = 10
"""States of the per-sample Pinocchio comparison (a Python call each)."""


def test_residual_vanishes_on_assembled_states(device, states):
    assert np.max(np.abs(closure.closure_residual(device.params, states.q))) <= ASSEMBLY_ATOL


def test_residual_sees_an_open_loop(device, states):
    """Moving the piston by δ opens the pin by δ along the cylinder axis (c1, s1)."""
    p, q = device.params, states.q.copy()
    delta = 1e-3  # [m]: a 1 mm piston move, 1e12 times the assembled residual
    q[:, 1] += delta
    axis = np.column_stack([np.cos(q[:, 0]), np.sin(q[:, 0])])
    np.testing.assert_allclose(
        closure.closure_residual(p, q), delta * axis, rtol=0, atol=ASSEMBLY_ATOL
    )


def test_jacobian_is_the_residual_derivative_and_pinocchio_closure_jacobian(device, states):
    p, q = device.params, states.q
    jac = closure.closure_jacobian(p, q)
    cases.assert_derivative(jac, lambda x: closure.closure_residual(p, x), q)
    for i in range(PINOCCHIO_SAMPLES):
        world = device.chain.jacobian(device.to_pinocchio(q[i]))
        np.testing.assert_allclose(jac[i], device.to_paper(world[:2]), rtol=0, atol=JACOBIAN_ATOL)


def test_bias_closes_the_acceleration_level(device, states):
    """f̈ = J_f q̈ + J̇_f q̇ = 0 along the closure-consistent motion; J̇_f q̇ by differences in t."""
    p, (q, qd, qdd) = device.params, states[:3]
    jac = closure.closure_jacobian(p, q)
    bias = closure.closure_bias(p, q, qd)
    np.testing.assert_allclose(
        np.einsum("nij,nj->ni", jac, qdd), -bias, rtol=0, atol=ACCELERATION_ATOL
    )
    step = cases.FD_STEP
    jac_dot = (
        closure.closure_jacobian(p, q + step * qd) - closure.closure_jacobian(p, q - step * qd)
    ) / (2 * step)
    scale = np.max(np.abs(jac)) * np.max(np.abs(qd)) ** 2
    np.testing.assert_allclose(
        np.einsum("nij,nj->ni", jac_dot, qd), bias, rtol=0, atol=cases.FD_RTOL * scale
    )
