"""Forward dynamics driven by the force rule: tracking, loop closure, order, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder.device.loop import loop_state
from feeder.dynamics.forward import (
    END_STOP_TOLERANCE,
    ForceRule,
    check_end_stops,
    simulate_feeder,
)
from feeder.dynamics.inverse import ActuatorLoads, actuator_loads, check_cycle_motion
from feeder.dynamics.models import BAUMGARTE_RATE, FeederDynamics
from feeder.exceptions import (
    ForwardDivergenceError,
    InputError,
    SingularPoseError,
    UnreachablePoseError,
)
from feeder.motion.cycle import feeding_cycle
from feeder.motion.laws import CycleSpec

from ..dynamics.cases import (
    ELEVATIONS_DEG,
    device,
    toggle_device,
)

TRACKING_TOLERANCE = 1e-4
"""[rad] Forward φ3, φ4 vs the prescribed motion over the whole cycle at 1 kHz (issue 3). The
force-driven arm is unstable (errors grow ~e^(5 t)), so this needs a high-order integrator:
ABM5 reaches ~6e-7 rad."""

CLOSURE_TOLERANCE = 1e-8
"""[m] Forward pin gap over the cycle (issue 3); Baumgarte keeps it at ~1e-14 m."""

ORDER = 4
"""The integrator must be at least fourth order: doubling the rate divides the error by 2⁴."""

GAP_RTOL = 1e-6
"""Relative: the pin gap Pinocchio measures at the start vs the piston offset along its axis
that made it; frame positions of ~1 m round to ~1e-16 m, 2e-7 of the 5e-10 m gap."""

DECAY_MARGIN = 2.0
"""Margin over the linear Baumgarte decay of the gap (the loads are the static ones, not those
of the offset pose)."""


def _rule(kin, loads) -> ForceRule:
    return ForceRule(kin.t, kin.stage, kin.gripped, loads.piston_force, loads.forearm_torque)


def _loads(dyn: FeederDynamics, q, v, a, gripped) -> ActuatorLoads:
    """The closed chain's inverse dynamics of a motion, checked first (the public path)."""
    return actuator_loads(dyn, check_cycle_motion(dyn, q, v, a, gripped))


def test_force_rule_reproduces_the_prescribed_motion(result):
    phi3, phi4 = result.tracking_error()
    assert phi3 <= TRACKING_TOLERANCE
    assert phi4 <= TRACKING_TOLERANCE
    assert result.closure_residual() <= CLOSURE_TOLERANCE
    assert result.forward.closure_residual[0] <= CLOSURE_TOLERANCE


def test_integrator_order(dyn):
    """Tracking error at 500 Hz vs 1 kHz: the ratio shows the order (≥ 4), and 500 Hz still
    meets the tracking requirement (the rate the docs recommend as the lowest)."""
    errors = []
    for rate in (500.0, 1000.0):
        kin = feeding_cycle(device(), math.radians(ELEVATIONS_DEG[1]), CycleSpec(rate=rate))
        loads = _loads(dyn, kin.q, kin.v, kin.a, kin.gripped)
        motion = simulate_feeder(dyn, _rule(kin, loads), kin.q[0], kin.v[0])
        errors.append(np.abs(motion.q - kin.q)[:, 2:].max())
    assert errors[0] / errors[1] >= 2.0**ORDER
    assert errors[0] <= TRACKING_TOLERANCE


def test_baumgarte_closes_a_small_initial_gap(dyn):
    """Start at rest with a 5e-10 m pin gap (inside the accepted 1e-9 m), held by the static
    loads: the critically damped corrector shrinks it by (1 + ω t) e^(−ω t) ≈ 5e-4 in 0.5 s."""
    p = dyn.feeder.params
    q = loop_state(p, np.array([0.3]), 0.2).q
    rest = np.zeros_like(q)
    loads = _loads(dyn, q, rest, rest, np.zeros(1))
    gap = 5e-10
    q0 = q[0].copy()
    q0[1] += gap  # the piston moves along its axis: the pin gap is the same distance
    t = np.arange(501) / 1000.0
    rule = ForceRule(
        t,
        np.ones(t.size),
        np.zeros(t.size),
        np.full(t.size, loads.piston_force[0]),
        np.full(t.size, loads.forearm_torque[0]),
    )
    motion = simulate_feeder(dyn, rule, q0, np.zeros(4))
    assert motion.closure_residual[0] == pytest.approx(gap, rel=GAP_RTOL)
    decay = (1.0 + BAUMGARTE_RATE * t[-1]) * math.exp(-BAUMGARTE_RATE * t[-1])
    assert decay <= 1e-3  # the corrector acts within the run
    assert motion.closure_residual[-1] <= DECAY_MARGIN * decay * gap


def test_nan_loads_are_refused(result):
    kin, loads = result.kinematics, result.loads
    force = loads.piston_force.copy()
    force[100] = np.nan
    with pytest.raises(InputError, match="piston_force"):
        ForceRule(kin.t, kin.stage, kin.gripped, force, loads.forearm_torque)


def test_bad_timing_is_refused(result):
    kin, loads = result.kinematics, result.loads
    t = kin.t.copy()
    t[10] += 1e-4
    with pytest.raises(InputError, match="uniform"):
        ForceRule(t, kin.stage, kin.gripped, loads.piston_force, loads.forearm_torque)
    stage = kin.stage.copy()
    stage[5:7] = 9
    rule = ForceRule(kin.t, stage, kin.gripped, loads.piston_force, loads.forearm_torque)
    with pytest.raises(InputError, match="steps"):
        rule.pieces()
    with pytest.raises(InputError, match="grip flags must be 0 or 1"):
        ForceRule(kin.t, kin.stage, kin.gripped * 3, loads.piston_force, loads.forearm_torque)


def test_non_closing_initial_state_is_refused(result, dyn):
    kin = result.kinematics
    rule = _rule(kin, result.loads)
    q0 = kin.q[0].copy()
    q0[1] += 1e-6
    with pytest.raises(UnreachablePoseError, match="does not close"):
        simulate_feeder(dyn, rule, q0, kin.v[0])
    v0 = kin.v[0].copy()
    v0[1] = 1e-3
    with pytest.raises(InputError, match="velocities of the initial state violate the closure"):
        simulate_feeder(dyn, rule, kin.q[0], v0)
    with pytest.raises(InputError, match="finite"):
        simulate_feeder(dyn, rule, kin.q[0] * np.nan, kin.v[0])


def test_initial_state_near_the_toggle_is_refused():
    feeder = toggle_device()
    p = feeder.params
    phi3 = math.atan2(p.L2, p.L1) - math.pi + math.radians(1.0)
    q0 = loop_state(p, phi3).q
    t = np.arange(11) / 1000.0
    rule = ForceRule(t, np.ones(11), np.zeros(11), np.zeros(11), np.zeros(11))
    with pytest.raises(SingularPoseError, match="toggle"):
        simulate_feeder(FeederDynamics(feeder), rule, q0, np.zeros(4))


def test_diverged_run_is_reported_as_such(dyn):
    """At 20 Hz the force-driven run drifts off the cycle until it passes the piston's end stop:
    a ForwardDivergenceError that names the joint and the time, not a toggle."""
    kin = feeding_cycle(device(), math.radians(30.0), CycleSpec(rate=20.0))
    loads = _loads(dyn, kin.q, kin.v, kin.a, kin.gripped)
    with pytest.raises(
        ForwardDivergenceError, match=r"end stop of piston_joint at t = \d+\.\d+ s"
    ):
        simulate_feeder(dyn, _rule(kin, loads), kin.q[0], kin.v[0])


def test_end_stops_and_blow_up_of_a_run(dyn):
    """check_end_stops: the URDF's limits (paper order) with END_STOP_TOLERANCE, and NaN."""
    t = np.arange(3) * 1e-3
    q = np.tile([2.4, 0.3, 0.5, 0.0], (3, 1))
    v = np.zeros_like(q)
    check_end_stops(dyn, t, q, v)
    limit = dyn.feeder.params.phi4_limit
    q[2, 3] = limit + 0.5 * END_STOP_TOLERANCE  # past the stop, within the tolerance
    check_end_stops(dyn, t, q, v)
    q[1, 3] = -limit - 2 * END_STOP_TOLERANCE
    with pytest.raises(ForwardDivergenceError, match=r"forearm_joint at t = 0\.0010 s"):
        check_end_stops(dyn, t, q, v)
    v[0, 1] = np.nan
    with pytest.raises(ForwardDivergenceError, match=r"blows up at t = 0\.0000 s"):
        check_end_stops(dyn, t, q, v)
