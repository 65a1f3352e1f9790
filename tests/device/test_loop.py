"""Closed-form loop kinematics against the generic Newton assembly, finite differences and
the geometry of the triangle B–A–P; reachability and bad input."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pinocchio as pin
import pytest

from feeder.chain.assembly.partition import POSITION_TOLERANCE, Partition
from feeder.chain.model.closure import ClosedChain
from feeder.device.feeder import CLOSURE, INDEPENDENT_JOINTS, Feeder
from feeder.device.loop import (
    CLOSURE_TOLERANCE,
    TRANSMISSION_BAND_DEG,
    arm_travel,
    check_closed,
    loop_residual,
    loop_state,
    required_stroke,
    transmission_angle,
)
from feeder.exceptions import InputError, UnreachablePoseError

from .helpers import stroke_ratio

ROUNDING = 1e-14
"""Double-precision rounding [SI] of the closed form and of the least-squares solves: a few tens
of ulps (2.2e-16) of O(1) numbers, times the gain 1/σ_min ≤ 2.5 (measured: ≤ 3e-15)."""
FD_STEP = 1e-5
FD_TOLERANCE = 1e-8
"""Central differences with h = 1e-5: truncation ~h²·|d³r2/dφ3³| ~ 1e-10, round-off ~1e-16/h."""
LENGTH_ROUNDING = 1e-15
"""[m] Two formulas for the same ≤ 0.7 m distance, each a few correctly rounded operations."""
ANGLE_ROUNDING = 1e-14
"""[rad] Both sides take a handful of correctly rounded operations (~10 ulps of π: 4e-15);
arccos amplifies its argument's rounding by 1/sin μ ≤ 1.5 inside [43°, 137°]. Measured 4e-16."""
ACCELERATION_ROUNDING = 10 * ROUNDING
"""[SI] J q̈ + J̇ q̇ sums products of up to three O(1) factors (lengths, rates, accelerations):
ten times the position-level rounding."""
LOWEST_ELEVATION_TRAVEL = math.radians(94.0)
"""Arm rotation [rad] from loading (arm horizontal) to ramming at the paper's lowest elevation
−4° (section I): the arm ends perpendicular to the barrel, 90° + 4°."""
GUESS = (2.4, 0.35)
"""Newton's starting φ1 [rad] and r2 [m]: inside the cylinder's swing and stroke, not a pose."""


def random_independent(
    feeder: Feeder, rng: np.random.Generator, count: int
) -> tuple[np.ndarray, np.ndarray]:
    """``count`` arm angles φ3 over the whole travel and forearm angles φ4 within its limits."""
    p = feeder.params
    phi3 = rng.uniform(p.phi3_load, p.phi3_load + arm_travel(p.elevation_min), count)
    phi4 = rng.uniform(-p.phi4_limit, p.phi4_limit, count)
    return phi3, phi4


def newton_pose(feeder: Feeder, phi3: float, phi4: float = 0.0) -> tuple[np.ndarray, float]:
    """The Pinocchio model assembled by Newton at (φ3, φ4) (no closed form involved), and the
    bound g · POSITION_TOLERANCE [m or rad] on the error of its dependent coordinates,
    g = 1/σ_min of the dependent Jacobian."""
    partition = Partition(feeder.chain, INDEPENDENT_JOINTS)
    q = partition.assemble(feeder.to_pinocchio([*GUESS, phi3, phi4]))
    jac_dep = feeder.chain.jacobian(q)[:, partition.dependent]
    gain = 1.0 / np.linalg.svd(jac_dep, compute_uv=False).min()
    return q, gain * POSITION_TOLERANCE


def test_closed_form_equals_generic_newton(feeder, rng):
    """Newton stops at a closure residual τ = POSITION_TOLERANCE, so its dependent coordinates
    err by δq ≤ g τ, g = 1/σ_min(J_dep) [1/m] (J_dep's columns are s·n and u: g = 1/s ≤ 2.5
    with s = r2 + d2 ≥ 0.41 m). That error propagates to first order through the velocity and
    acceleration solves: with the closure's second and third derivatives bounded by the loop's
    lengths (≤ 1 m), δv ≤ g (1 + g) |v| δq and δa ≤ g ((1 + g) |a| + (1 + 2g) |v|²) δq."""
    partition = Partition(feeder.chain, INDEPENDENT_JOINTS)
    for phi3, phi4 in zip(*random_independent(feeder, rng, 30), strict=True):
        dphi3, dphi4, ddphi3, ddphi4 = rng.normal(size=4)
        loop = loop_state(feeder.params, phi3, phi4, (dphi3, dphi4), (ddphi3, ddphi4))
        guess = feeder.to_pinocchio([*GUESS, phi3, phi4])
        q = partition.assemble(guess)
        q_closed = feeder.to_pinocchio(loop.q)
        v_closed = feeder.to_pinocchio(loop.v)
        a_closed = feeder.to_pinocchio(loop.a)
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
    loop = loop_state(feeder.params, phi3, phi4, (rates[0], 0.3), (rates[1], -0.2))
    assert loop.q.shape == loop.v.shape == loop.a.shape == (20, 4)
    np.testing.assert_array_equal(loop.q[:, 2:], np.column_stack([phi3, phi4]))
    np.testing.assert_array_equal(loop.v[:, 3], 0.3)
    np.testing.assert_array_equal(loop.a[:, 3], -0.2)
    for i in range(20):
        q = feeder.to_pinocchio(loop.q[i])
        v = feeder.to_pinocchio(loop.v[i])
        a = feeder.to_pinocchio(loop.a[i])
        jac = feeder.chain.jacobian(q)
        assert np.linalg.norm(feeder.chain.residual(q)) <= ROUNDING
        assert np.linalg.norm(jac @ v) <= ROUNDING * (1 + np.abs(v).max())
        assert np.linalg.norm(jac @ a + feeder.chain.bias(q, v)) <= ACCELERATION_ROUNDING * (
            1 + v @ v
        )


def test_stroke_ratio_is_the_derivative_of_r2(feeder):
    p = feeder.params
    phi3 = np.linspace(0.0, LOWEST_ELEVATION_TRAVEL, 50)
    numeric = (loop_state(p, phi3 + FD_STEP).q[:, 1] - loop_state(p, phi3 - FD_STEP).q[:, 1]) / (
        2 * FD_STEP
    )
    ratio = stroke_ratio(p, loop_state(p, phi3).q)
    np.testing.assert_allclose(ratio, numeric, atol=FD_TOLERANCE)


def test_transmission_angle_is_the_angle_between_piston_and_lever(feeder):
    """μ from the dot product of the piston axis and the lever; the pin distance B–P from the
    law of cosines on the triangle B–A–P (sides |BA|, d3, angle at the arm pivot A)."""
    p = feeder.params
    phi3 = np.linspace(0.0, LOWEST_ELEVATION_TRAVEL, 50)
    q = loop_state(p, phi3).q
    pin_xy = np.array([p.L1 + p.d3 * np.cos(phi3), p.L2 + p.d3 * np.sin(phi3)])
    piston = pin_xy / np.linalg.norm(pin_xy, axis=0)
    lever = np.array([np.cos(phi3), np.sin(phi3)])
    expected = np.arccos(np.clip(np.sum(piston * lever, axis=0), -1, 1))
    np.testing.assert_allclose(transmission_angle(q), expected, rtol=0, atol=ANGLE_ROUNDING)
    # Angle at A between A→B = −(L1, L2) and the lever A→P.
    pivot = math.hypot(p.L1, p.L2)
    cos_at_a = -(p.L1 * np.cos(phi3) + p.L2 * np.sin(phi3)) / pivot
    reach = np.sqrt(pivot**2 + p.d3**2 - 2 * pivot * p.d3 * cos_at_a)
    np.testing.assert_allclose(q[:, 1] + p.d2, reach, rtol=0, atol=LENGTH_ROUNDING)


@pytest.mark.parametrize("device", ["feeder", "charge_feeder"])
def test_transmission_angle_stays_in_band_over_whole_range(device, request):
    p = request.getfixturevalue(device).params
    phi3 = p.phi3_load + np.linspace(0.0, arm_travel(p.elevation_min), 2001)
    mu = np.degrees(transmission_angle(loop_state(p, phi3).q))
    low, high = TRANSMISSION_BAND_DEG
    assert low < mu.min() and mu.max() < high
    assert low > 30.0 and high < 150.0  # the band itself is well away from 0° and 180°


@pytest.mark.parametrize("device", ["feeder", "charge_feeder"])
def test_required_stroke_is_the_newton_piston_travel(device, request):
    """The stroke is the piston travel between the loading pose and ramming at −4°, read off the
    Pinocchio model assembled by Newton at both ends (no closed form involved); it fits between
    the piston's end stops, and the cylinder is longer than its stroke when retracted."""
    feeder = request.getfixturevalue(device)
    p = feeder.params
    assert p.elevation_min == pytest.approx(math.radians(-4.0), abs=ROUNDING)
    loading, load_error = newton_pose(feeder, p.phi3_load)
    ramming, ram_error = newton_pose(feeder, p.phi3_load + LOWEST_ELEVATION_TRAVEL)
    r2_load, r2_ram = loading[feeder.index[1]], ramming[feeder.index[1]]
    stroke = required_stroke(p)
    assert stroke == pytest.approx(r2_ram - r2_load, abs=load_error + ram_error + ROUNDING)
    assert p.r2_min < r2_load < r2_ram < p.r2_max
    retracted = r2_load + p.d2  # pin-to-pin length at loading
    assert 0.1 < stroke < 0.5
    assert retracted > stroke


def test_unreachable_arm_angles(feeder):
    with pytest.raises(UnreachablePoseError, match="end stops"):
        loop_state(feeder.params, math.radians(120.0))
    # −4.9° is inside the arm's end stops (−5°) but needs the piston past its end stop.
    with pytest.raises(UnreachablePoseError, match="stroke"):
        loop_state(feeder.params, math.radians(-4.9))
    partition = Partition(feeder.chain, INDEPENDENT_JOINTS)
    with pytest.raises(UnreachablePoseError, match="piston_joint"):
        partition.assemble(feeder.to_pinocchio([*GUESS, math.radians(-4.9), 0.0]))


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
        partition.assemble(feeder.to_pinocchio([*GUESS, 0.3, 0.0]))


def test_cylinder_swing_is_a_limit_of_the_loop(feeder):
    """φ1 outside [phi1_min, phi1_max] is refused like the stroke (the URDF's joint limit)."""
    narrow = dataclasses.replace(feeder.params, phi1_max=math.radians(130.0))
    phi1 = loop_state(feeder.params, 0.0).q[..., 0]
    assert math.degrees(float(phi1)) > 130.0
    with pytest.raises(UnreachablePoseError, match="φ1 = 13[0-9].[0-9]*°, outside its swing"):
        loop_state(narrow, 0.0)


def test_loop_residual_is_the_pin_gap(feeder):
    """Zero at the closed form; sliding the piston by δ along its axis opens the pin by |δ|, and
    check_closed names the first sample that does not close."""
    p = feeder.params
    q = loop_state(p, np.linspace(0.0, LOWEST_ELEVATION_TRAVEL, 5)).q
    assert np.all(loop_residual(p, q) <= LENGTH_ROUNDING)
    check_closed(p, q)
    slid = q.copy()
    slid[:, 1] += np.array([0.0, 0.01, -0.02, 0.0, 0.0])
    np.testing.assert_allclose(
        loop_residual(p, slid), [0.0, 0.01, 0.02, 0.0, 0.0], rtol=0, atol=LENGTH_ROUNDING
    )
    with pytest.raises(UnreachablePoseError, match="sample 2 does not close"):
        check_closed(p, slid)
    barely = q.copy()
    barely[:, 1] += CLOSURE_TOLERANCE / 2  # data rounded to 9 digits still closes
    check_closed(p, barely)


@pytest.mark.parametrize(
    "changes, message",
    [
        ({"rates": (np.ones(2), 0.0)}, r"dphi3 \[rad/s\] must .* phi3's shape \(3,\), got \(2,\)"),
        ({"accelerations": (np.ones((3, 1)), 0.0)}, r"ddphi3 .* got \(3, 1\)"),
        ({"phi4": np.ones(4)}, r"phi4 \[rad\] .* got \(4,\)"),
        ({"rates": (0.0, np.ones((2, 3)))}, r"dphi4 .* got \(2, 3\)"),
    ],
)
def test_inputs_of_another_shape_are_refused(feeder, changes, message):
    """Rates, accelerations and φ4 must be scalars or broadcast to φ3's shape, not widen it."""
    phi3 = np.linspace(0.1, 0.5, 3)
    with pytest.raises(InputError, match=message):
        loop_state(feeder.params, phi3, **changes)


def test_scalars_and_inputs_of_the_same_shape_are_accepted(feeder):
    phi3 = np.linspace(0.1, 0.5, 3)
    loop = loop_state(feeder.params, phi3, 0.1, (0.2, np.ones(3)), (np.ones(3), 0.0))
    assert loop.q.shape == (3, 4)
    np.testing.assert_array_equal(loop.v[:, 2:], np.column_stack([np.full(3, 0.2), np.ones(3)]))
    np.testing.assert_array_equal(loop.a[:, 2:], np.column_stack([np.ones(3), np.zeros(3)]))


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), [0.1, float("nan")]])
def test_non_finite_inputs(feeder, bad):
    with pytest.raises(InputError, match="finite"):
        loop_state(feeder.params, bad)
    with pytest.raises(InputError, match="finite"):
        loop_state(feeder.params, 0.3, rates=(bad, 0.0))
    with pytest.raises(InputError, match="finite"):
        loop_state(feeder.params, 0.3, phi4=bad)
    with pytest.raises(InputError, match="finite"):
        feeder.chain.residual(np.full(4, np.nan))


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"phi3": "0.3"}, "phi3"),
        ({"phi3": ["0.1", "0.3"]}, "phi3"),
        ({"phi3": 0.3, "phi4": "0"}, "phi4"),
        ({"phi3": 0.3, "accelerations": (0.0, "1")}, "ddphi4"),
    ],
)
def test_text_inputs_are_refused(feeder, kwargs, name):
    """numpy would parse "0.3"; a number typed as text is the caller's mistake."""
    with pytest.raises(InputError, match=f"{name} .* must be numeric"):
        loop_state(feeder.params, **kwargs)
