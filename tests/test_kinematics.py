"""Closed-form loop kinematics against the generic Newton assembly, finite differences and
geometry; reachability and bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder import (
    INDEPENDENT_JOINTS,
    TRANSMISSION_BAND_DEG,
    InputError,
    Partition,
    UnreachablePoseError,
    dependent_coordinates,
    required_stroke,
    stroke_ratio,
    transmission_angle,
)
from feeder.kinematics import arm_travel

ASSEMBLY_TOLERANCE = 1e-11
"""[rad], [m]: Newton stops at a 1e-13 m residual; the loop's condition number is ~10."""
FD_STEP = 1e-5
FD_TOLERANCE = 1e-8
"""Central differences with h = 1e-5: truncation ~h²·|f'''| ~ 1e-10, round-off ~1e-16/h."""


def random_independent(feeder, rng, count):
    p = feeder.params
    phi3 = rng.uniform(p.phi3_load, p.phi3_load + arm_travel(p.elevation_min), count)
    phi4 = rng.uniform(-p.phi4_limit, p.phi4_limit, count)
    return phi3, phi4


def test_closed_form_equals_generic_newton(feeder, rng):
    partition = Partition(feeder.chain, INDEPENDENT_JOINTS)
    for phi3, phi4 in zip(*random_independent(feeder, rng, 30), strict=True):
        dphi3, dphi4, ddphi3, ddphi4 = rng.normal(size=4)
        loop = dependent_coordinates(feeder.params, phi3, dphi3, ddphi3)
        guess = feeder.to_pinocchio([2.4, 0.35, phi3, phi4])
        q = partition.assemble(guess)
        q_closed = feeder.to_pinocchio([loop.phi1, loop.r2, phi3, phi4])
        np.testing.assert_allclose(q, q_closed, atol=ASSEMBLY_TOLERANCE)
        v = partition.velocity(q, feeder.to_pinocchio([0, 0, dphi3, dphi4])[partition.independent])
        np.testing.assert_allclose(
            v, feeder.to_pinocchio([loop.dphi1, loop.dr2, dphi3, dphi4]), atol=ASSEMBLY_TOLERANCE
        )
        a = partition.acceleration(
            q, v, feeder.to_pinocchio([0, 0, ddphi3, ddphi4])[partition.independent]
        )
        np.testing.assert_allclose(
            a,
            feeder.to_pinocchio([loop.ddphi1, loop.ddr2, ddphi3, ddphi4]),
            atol=ASSEMBLY_TOLERANCE * 10,
        )  # second derivative: one more condition factor


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
    np.testing.assert_allclose(transmission_angle(p, phi3), expected, atol=1e-7)
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
    """A pin 10 m away: Newton cannot converge; the message says so."""
    import dataclasses

    from feeder import load_feeder

    far = load_feeder(dataclasses.replace(feeder.params, L1=-10.0, r2_max=0.6))
    partition = Partition(far.chain, INDEPENDENT_JOINTS)
    with pytest.raises(UnreachablePoseError):
        partition.assemble(far.to_pinocchio([2.4, 0.35, 0.3, 0.0]))


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), [0.1, float("nan")]])
def test_non_finite_inputs(feeder, bad):
    with pytest.raises(InputError, match="finite"):
        dependent_coordinates(feeder.params, bad)
    with pytest.raises(InputError, match="finite"):
        dependent_coordinates(feeder.params, 0.3, dphi3=bad)
    with pytest.raises(InputError, match="finite"):
        feeder.chain.residual(np.full(4, np.nan))
