"""Closed-form loop kinematics against the generic Newton assembly, finite differences and
geometry; reachability and bad input."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from feeder import (
    CLOSURE,
    INDEPENDENT_JOINTS,
    TRANSMISSION_BAND_DEG,
    ClosedChain,
    InputError,
    Partition,
    UnreachablePoseError,
    dependent_coordinates,
    required_stroke,
    stroke_ratio,
    transmission_angle,
)
from feeder.assembly import POSITION_TOLERANCE
from feeder.kinematics import arm_travel

ROUNDING = 1e-14
"""Double-precision rounding [SI] of the closed form and of the least-squares solves: a few tens
of ulps (2.2e-16) of O(1) numbers, times the gain 1/σ_min ≤ 2.5 (measured: ≤ 3e-15)."""
FD_STEP = 1e-5
FD_TOLERANCE = 1e-8
"""Central differences with h = 1e-5: truncation ~h²·|f'''| ~ 1e-10, round-off ~1e-16/h."""


def random_independent(feeder, rng, count):
    p = feeder.params
    phi3 = rng.uniform(p.phi3_load, p.phi3_load + arm_travel(p.elevation_min), count)
    phi4 = rng.uniform(-p.phi4_limit, p.phi4_limit, count)
    return phi3, phi4


def test_closed_form_equals_generic_newton(feeder, rng):
    """Newton stops at a closure residual τ = POSITION_TOLERANCE, so its dependent coordinates
    err by δq ≤ g τ, g = 1/σ_min(J_dep) [1/m] (J_dep's columns are s·n and u: g = 1/s ≤ 2.5
    with s = r2 + d2 ≥ 0.41 m). That error propagates to first order through the velocity and
    acceleration solves: with the closure's second and third derivatives bounded by the loop's
    lengths (≤ 1 m), δv ≤ g (1 + g) |v| δq and δa ≤ g ((1 + g) |a| + (1 + 2g) |v|²) δq."""
    partition = Partition(feeder.chain, INDEPENDENT_JOINTS)
    for phi3, phi4 in zip(*random_independent(feeder, rng, 30), strict=True):
        dphi3, dphi4, ddphi3, ddphi4 = rng.normal(size=4)
        loop = dependent_coordinates(feeder.params, phi3, dphi3, ddphi3)
        guess = feeder.to_pinocchio([2.4, 0.35, phi3, phi4])
        q = partition.assemble(guess)
        q_closed = feeder.to_pinocchio([loop.phi1, loop.r2, phi3, phi4])
        v_closed = feeder.to_pinocchio([loop.dphi1, loop.dr2, dphi3, dphi4])
        a_closed = feeder.to_pinocchio([loop.ddphi1, loop.ddr2, ddphi3, ddphi4])
        jac_dep = feeder.chain.jacobian(q)[:, partition.dependent]
        gain = 1.0 / np.linalg.svd(jac_dep, compute_uv=False).min()
        dq = gain * POSITION_TOLERANCE
        speed, accel = np.linalg.norm(v_closed), np.linalg.norm(a_closed)
        np.testing.assert_allclose(q, q_closed, rtol=0, atol=dq + ROUNDING)
        v = partition.velocity(q, v_closed[partition.independent])
        tol_v = gain * (1 + gain) * speed * dq + ROUNDING * (1 + speed)
        np.testing.assert_allclose(v, v_closed, rtol=0, atol=tol_v)
        a = partition.acceleration(q, v, a_closed[partition.independent])
        tol_a = gain * ((1 + gain) * accel + (1 + 2 * gain) * speed**2) * dq
        np.testing.assert_allclose(
            a, a_closed, rtol=0, atol=tol_a + ROUNDING * (1 + accel + speed**2)
        )


def test_velocity_and_acceleration_levels_close_the_loop(feeder, rng):
    """J q̇ = 0 and J q̈ + J̇ q̇ = 0 with Pinocchio's Jacobian at the closed-form states."""
    phi3, phi4 = random_independent(feeder, rng, 20)
    rates = rng.normal(size=(2, 20))
    loop = dependent_coordinates(feeder.params, phi3, rates[0], rates[1])
    for i in range(20):
        q = feeder.to_pinocchio([loop.phi1[i], loop.r2[i], phi3[i], phi4[i]])
        v = feeder.to_pinocchio([loop.dphi1[i], loop.dr2[i], rates[0, i], 0.3])
        a = feeder.to_pinocchio([loop.ddphi1[i], loop.ddr2[i], rates[1, i], -0.2])
        jac = feeder.chain.jacobian(q)
        assert np.linalg.norm(feeder.chain.residual(q)) <= 1e-15 * 10
        assert np.linalg.norm(jac @ v) <= 1e-14 * (1 + np.abs(v).max())
        assert np.linalg.norm(jac @ a + feeder.chain.bias(q, v)) <= 1e-13 * (1 + v @ v)


def test_stroke_ratio_is_the_derivative_of_r2(feeder):
    phi3 = np.linspace(0.0, math.radians(94.0), 50)
    numeric = (
        dependent_coordinates(feeder.params, phi3 + FD_STEP).r2
        - dependent_coordinates(feeder.params, phi3 - FD_STEP).r2
    ) / (2 * FD_STEP)
    np.testing.assert_allclose(stroke_ratio(feeder.params, phi3), numeric, atol=FD_TOLERANCE)


def test_transmission_angle_is_the_angle_between_piston_and_lever(feeder):
    p = feeder.params
    phi3 = np.linspace(0.0, math.radians(94.0), 50)
    loop = dependent_coordinates(p, phi3)
    pin_xy = np.array([p.L1 + p.d3 * np.cos(phi3), p.L2 + p.d3 * np.sin(phi3)])
    piston = pin_xy / np.linalg.norm(pin_xy, axis=0)
    lever = np.array([np.cos(phi3), np.sin(phi3)])
    expected = np.arccos(np.clip(np.sum(piston * lever, axis=0), -1, 1))
    # Both sides take a handful of correctly rounded operations (~10 ulps of π: 4e-15); arccos
    # amplifies its argument's rounding by 1/sin μ ≤ 1.5 inside [43°, 137°]. Measured 4e-16.
    np.testing.assert_allclose(transmission_angle(p, phi3), expected, rtol=0, atol=1e-14)
    np.testing.assert_allclose(loop.r2 + p.d2, np.linalg.norm(pin_xy, axis=0), atol=1e-15)


@pytest.mark.parametrize("device", ["feeder", "charge_feeder"])
def test_transmission_angle_stays_in_band_over_whole_range(device, request):
    p = request.getfixturevalue(device).params
    phi3 = p.phi3_load + np.linspace(0.0, arm_travel(p.elevation_min), 2001)
    mu = np.degrees(transmission_angle(p, phi3))
    low, high = TRANSMISSION_BAND_DEG
    assert low < mu.min() and mu.max() < high
    assert low > 30.0 and high < 150.0  # the band itself is well away from 0° and 180°


def test_required_stroke_is_a_plausible_cylinder(feeder):
    p = feeder.params
    stroke = required_stroke(p)
    ends = dependent_coordinates(p, np.array([p.phi3_load, p.phi3_load + math.radians(94)]))
    assert stroke == pytest.approx(ends.r2[1] - ends.r2[0], abs=1e-15)
    retracted = ends.r2[0] + p.d2  # pin-to-pin length at loading
    assert 0.1 < stroke < 0.5
    assert retracted > stroke  # a cylinder is longer than its stroke when retracted


def test_unreachable_arm_angles(feeder):
    with pytest.raises(UnreachablePoseError, match="end stops"):
        dependent_coordinates(feeder.params, math.radians(120.0))
    # −4.9° is inside the arm's end stops (−5°) but needs the piston past its end stop.
    with pytest.raises(UnreachablePoseError, match="stroke"):
        dependent_coordinates(feeder.params, math.radians(-4.9))
    partition = Partition(feeder.chain, INDEPENDENT_JOINTS)
    with pytest.raises(UnreachablePoseError, match="piston_joint"):
        partition.assemble(feeder.to_pinocchio([2.4, 0.35, math.radians(-4.9), 0.0]))


def test_loop_that_cannot_close_at_all(feeder):
    """The arm pivot moved 0.1 m out of the loop's plane: the pins can never meet (every
    rotation is about z, the piston slides in the x–y plane); Newton cannot converge."""
    model = pin.Model(feeder.model)
    arm = model.getJointId("arm_joint")
    model.jointPlacements[arm] = pin.SE3(
        model.jointPlacements[arm].rotation, model.jointPlacements[arm].translation + [0, 0, 0.1]
    )
    partition = Partition(ClosedChain(model, [CLOSURE]), INDEPENDENT_JOINTS)
    with pytest.raises(UnreachablePoseError, match="does not close"):
        partition.assemble(feeder.to_pinocchio([2.4, 0.35, 0.3, 0.0]))


def test_cylinder_swing_is_a_limit_of_the_loop(feeder):
    """φ1 outside [phi1_min, phi1_max] is refused like the stroke (the URDF's joint limit)."""
    import dataclasses

    narrow = dataclasses.replace(feeder.params, phi1_max=math.radians(130.0))
    loop = dependent_coordinates(feeder.params, 0.0)
    assert math.degrees(float(loop.phi1)) > 130.0
    with pytest.raises(UnreachablePoseError, match="φ1 = 13[0-9].[0-9]*°, outside its swing"):
        dependent_coordinates(narrow, 0.0)


def test_rates_of_another_shape_are_refused(feeder):
    phi3 = np.linspace(0.1, 0.5, 3)
    dependent_coordinates(feeder.params, phi3, 0.2, np.ones(3))  # scalar or φ3's shape: fine
    with pytest.raises(InputError, match=r"dphi3 must .* shape of phi3 \(3,\), got \(2,\)"):
        dependent_coordinates(feeder.params, phi3, np.ones(2))
    with pytest.raises(InputError, match=r"ddphi3 .* got \(3, 1\)"):
        dependent_coordinates(feeder.params, phi3, 0.0, np.ones((3, 1)))


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), [0.1, float("nan")]])
def test_non_finite_inputs(feeder, bad):
    with pytest.raises(InputError, match="finite"):
        dependent_coordinates(feeder.params, bad)
    with pytest.raises(InputError, match="finite"):
        dependent_coordinates(feeder.params, 0.3, dphi3=bad)
    with pytest.raises(InputError, match="finite"):
        feeder.chain.residual(np.full(4, np.nan))
