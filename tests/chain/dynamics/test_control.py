"""The computed-torque controller: the reference reproduced on a closed chain, its feedforward
the inverse dynamics of the reference, the error of one joint against the closed loop's linear
equation (closed forms, the roots of the lagged loop's characteristic polynomial, an
independent SciPy integration), saturation and rate limits, and the refusals."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import scipy.integrate

from feeder.chain import ClosedChain, Closure, load_closed_chain
from feeder.chain.assembly.partition import Partition
from feeder.chain.assembly.tracking import track
from feeder.chain.dynamics.control import ComputedTorque
from feeder.chain.dynamics.forward import simulate
from feeder.chain.dynamics.inverse import ChainDynamics, inverse_dynamics
from feeder.chain.model.control import ControlSpec
from feeder.chain.readers.motion_table import read_motion
from feeder.exceptions import InputError

from ...conftest import REPO

MASS, ARM = 2.0, 0.3
"""The pendulum's mass [kg] and the distance of its centre of gravity from the hinge [m]."""
MOMENT = 4e-3 + MASS * ARM**2
"""Its moment of inertia about the hinge I_O [kg·m²] (parallel axes from 4e-3 at the centre)."""
GRAVITY = 9.81

TIGHT = {"rtol": 1e-11, "atol": 1e-12}
"""Integrator tolerances of the comparisons with closed forms: their global error on errors of
~0.1 rad over ~1 s is ~1e-10 (measured), so the comparisons hold to 1e-8."""


def _spec(joint: str, t: np.ndarray, q, v, a, **settings) -> ControlSpec:
    arrays = [np.broadcast_to(np.asarray(x, dtype=float), t.shape).copy() for x in (q, v, a)]
    gains = {"kp": 100.0, "kd": 20.0} | settings
    return ControlSpec(joint, Path("reference.csv"), t, *arrays, **gains)


def _pendulum() -> ChainDynamics:
    """A rod on a hinge about z, its centre of gravity ARM along x, gravity −y: I_O θ̈ = u −
    m g ARM cos θ."""
    model = pin.Model()
    joint = model.addJoint(0, pin.JointModelRZ(), pin.SE3.Identity(), "hinge")
    inertia = pin.Inertia(MASS, np.array([ARM, 0.0, 0.0]), np.diag([1e-4, 4e-3, 4e-3]))
    model.appendBodyToJoint(joint, inertia, pin.SE3.Identity())
    model.gravity = pin.Motion(np.array([0.0, -GRAVITY, 0.0]), np.zeros(3))
    return ChainDynamics(ClosedChain(model, []), ["hinge"])


def _slider(mass: float = 3.0) -> ChainDynamics:
    """A mass on a prismatic joint along x, no gravity: m ẍ = u."""
    model = pin.Model()
    joint = model.addJoint(0, pin.JointModelPX(), pin.SE3.Identity(), "slide")
    model.appendBodyToJoint(
        joint, pin.Inertia(mass, np.zeros(3), np.eye(3) * 1e-3), pin.SE3.Identity()
    )
    model.gravity = pin.Motion.Zero()
    return ChainDynamics(ClosedChain(model, []), ["slide"])


def test_the_reference_is_reproduced_on_a_closed_chain_and_the_drive_is_its_inverse_dynamics():
    """The four-bar under gravity, started on its motion table (a crank turn per second): the run
    follows the reference to the integrator's tolerance, and the controller's torque is the
    inverse dynamics of the reference tracked by the kinematics alone."""
    chain = load_closed_chain(
        REPO / "examples" / "four_bar" / "four_bar.urdf",
        [Closure("coupler_tip", "rocker_tip", "revolute")],
    )
    chain.model.gravity = pin.Motion(np.array([0.0, -9.81, 0.0]), np.zeros(3))
    partition = Partition(chain, ["crank_joint"])
    table = read_motion(REPO / "examples" / "four_bar" / "motion.csv", ("crank_joint",))
    spec = _spec("crank_joint", table.t, table.x[:, 0], table.dx[:, 0], table.ddx[:, 0])
    dyn = ChainDynamics(chain, ["crank_joint"])
    controller = ComputedTorque(dyn, [spec])
    q0 = partition.assemble(np.array([table.x[0, 0], -0.35, 1.0]))
    v0 = partition.velocity(q0, table.dx[0])
    t = np.linspace(0.0, 1.0, 101)
    run = simulate(dyn, t, q0, v0, controller, **TIGHT)
    record = controller.record(t, run.q, run.v, run.controller)
    # the integrator's tolerance (rtol 1e-11 on angles of ~7 rad: ~1e-10 per step): 1e-9
    assert record.peak_error()[0] <= 1e-9
    # the reference's own motion (tracked by the kinematics at the table's samples) and its
    # inverse dynamics: the torque the controller commands on it
    motion = track(partition, q0, table.x, table.dx, table.ddx)
    reference = inverse_dynamics(dyn, motion.q, motion.v, motion.a).actuators["crank_joint"]
    every = slice(None, None, 1)  # the table's samples are the run's (0.01 s apart)
    torque = record.force[every, 0]
    # the run's state is off the reference by ~1e-10 rad, the feedback K_p e + K_d ė adds
    # ~1e-8 rad/s² × I (~1e-4 kg·m²) and the state's offset moves the inverse dynamics by
    # ~1e-10 of the torque's scale (0.07 N·m): 1e-9 N·m holds both with room
    np.testing.assert_allclose(torque, reference, rtol=0.0, atol=1e-9)
    np.testing.assert_allclose(run.loads.actuators["crank_joint"], torque, rtol=0.0, atol=1e-12)
    assert not record.saturated.any()


def test_a_pendulums_error_decays_as_the_linear_closed_loop_says():
    """Under gravity, a pendulum off its reference (a swing): e = θ_ref − θ obeys
    ë + K_d ė + K_p e = 0 exactly (the law cancels the nonlinear dynamics): damped oscillation,
    closed form."""
    dyn = _pendulum()
    t_table = np.linspace(0.0, 1.5, 301)
    w = 2.0 * math.pi
    spec = _spec(
        "hinge",
        t_table,
        0.4 * np.sin(w * t_table),
        0.4 * w * np.cos(w * t_table),
        -0.4 * w**2 * np.sin(w * t_table),
        kp=225.0,
        kd=6.0,  # ω = 15 rad/s, ζ = 0.2: an underdamped error
    )
    controller = ComputedTorque(dyn, [spec])
    e0 = 0.3  # [rad]: the pendulum starts at θ = −0.3 rad, at rest (ė0 = 0.4 w)
    t = np.linspace(0.0, 1.5, 151)
    run = simulate(dyn, t, np.array([-e0]), np.zeros(1), controller, **TIGHT)
    record = controller.record(t, run.q, run.v, run.controller)
    omega, zeta = 15.0, 0.2
    damped = omega * math.sqrt(1.0 - zeta**2)
    rate0 = 0.4 * w
    b = (rate0 + zeta * omega * e0) / damped
    exact = np.exp(-zeta * omega * t) * (e0 * np.cos(damped * t) + b * np.sin(damped * t))
    # the quintic reference between the table's samples is the law's own reference: the
    # closed form holds to the integrator's tolerance (1e-8 with room over 1.5 s)
    np.testing.assert_allclose(record.error[:, 0], exact, rtol=0.0, atol=1e-8)
    # the decay the gains predict: |e| below its envelope √(e0² + b²) e^(−ζωt)
    assert np.all(
        np.abs(record.error[:, 0]) <= math.hypot(e0, b) * np.exp(-zeta * omega * t) + 1e-8
    )


def _vandermonde_error(roots: np.ndarray, initial: np.ndarray, t: np.ndarray) -> np.ndarray:
    """e(t) = Σ c_i e^(s_i t) with (e, ė, ë)(0) = initial: the third-order loop's modes."""
    matrix = np.vander(roots, 3, increasing=True).T  # rows: 1, s, s²
    weights = np.linalg.solve(matrix, initial.astype(complex))
    return (np.exp(np.outer(t, roots)) @ weights).real


def test_a_lagged_actuator_follows_the_third_order_loop():
    """A mass on a slider held at a constant reference, its force through a first-order lag T:
    the error follows the roots of T s³ + s² + K_d s + K_p = 0 (numpy.roots), and the run its
    independent SciPy integration of the linear model (m ẍ = F, T Ḟ = m (K_p e − K_d ẋ) − F)."""
    mass, lag, kp, kd, target = 3.0, 0.02, 400.0, 30.0, 0.1
    dyn = _slider(mass)
    t_table = np.linspace(0.0, 2.0, 3)
    controller = ComputedTorque(
        dyn, [_spec("slide", t_table, target, 0.0, 0.0, kp=kp, kd=kd, lag=lag)]
    )
    assert controller.n_states == 1
    t = np.linspace(0.0, 2.0, 201)
    run = simulate(dyn, t, np.zeros(1), np.zeros(1), controller, **TIGHT)
    record = controller.record(t, run.q, run.v, run.controller)
    roots = np.roots([lag, 1.0, kd, kp])
    assert roots.real.max() < 0.0  # a stable loop at these gains
    # the actuator starts at its command m K_p e0: ë0 = −F0/m = −K_p e0
    exact = _vandermonde_error(roots, np.array([target, 0.0, -kp * target]), t)
    np.testing.assert_allclose(record.error[:, 0], exact, rtol=0.0, atol=1e-8)

    def linear(_, y):
        x, v, force = y
        return [v, force / mass, (mass * (kp * (target - x) - kd * v) - force) / lag]

    solution = scipy.integrate.solve_ivp(
        linear, (0.0, 2.0), [0.0, 0.0, mass * kp * target], t_eval=t, rtol=1e-12, atol=1e-14
    )
    np.testing.assert_allclose(run.q[:, 0], solution.y[0], rtol=0.0, atol=1e-8)
    # the force (m K_p e0 = 120 N at the start) to the integrators' tolerance: 1e-9 of it
    np.testing.assert_allclose(
        run.controller[:, 0], solution.y[2], rtol=0.0, atol=1e-9 * mass * kp * target
    )
    np.testing.assert_allclose(record.force[:, 0], run.controller[:, 0], rtol=0.0, atol=0.0)


def test_the_error_converges_faster_with_higher_gains_as_predicted():
    """Critically damped gains ω = 5, 10, 20 rad/s on the slider (no lag): e(t) = e0 (1 + ωt)
    e^(−ωt) for each; the time to settle within 1 % of e0 scales as 1/ω."""
    dyn = _slider()
    t_table = np.linspace(0.0, 3.0, 3)
    t = np.linspace(0.0, 3.0, 1501)
    settle = []
    for omega in (5.0, 10.0, 20.0):
        spec = _spec("slide", t_table, 0.05, 0.0, 0.0, kp=omega**2, kd=2.0 * omega)
        controller = ComputedTorque(dyn, [spec])
        run = simulate(dyn, t, np.zeros(1), np.zeros(1), controller, **TIGHT)
        error = controller.record(t, run.q, run.v, run.controller).error[:, 0]
        exact = 0.05 * (1.0 + omega * t) * np.exp(-omega * t)
        np.testing.assert_allclose(error, exact, rtol=0.0, atol=1e-9)
        settle.append(t[np.flatnonzero(np.abs(error) > 0.01 * 0.05)[-1] + 1])
    # (1 + x) e^(−x) = 0.01 at x = 6.638: settling at 6.638/ω, to the grid's 2 ms (0.04 × ω)
    np.testing.assert_allclose(np.array(settle) * [5.0, 10.0, 20.0], 6.638, atol=0.05)


def test_a_force_limit_below_the_need_saturates_and_is_reported():
    """Hold the pendulum level (θ_ref = 0) with a limit of half its weight's moment m g ARM: the
    demand exceeds it all along, the drive is the limit, and the pendulum falls as
    I_O θ̈ = L − m g ARM cos θ (SciPy, independently)."""
    dyn = _pendulum()
    limit = 0.5 * MASS * GRAVITY * ARM
    t_table = np.linspace(0.0, 0.3, 3)
    spec = _spec("hinge", t_table, 0.0, 0.0, 0.0, force_limit=(-limit, limit))
    controller = ComputedTorque(dyn, [spec])
    t = np.linspace(0.0, 0.3, 61)
    run = simulate(dyn, t, np.zeros(1), np.zeros(1), controller, **TIGHT)
    record = controller.record(t, run.q, run.v, run.controller)
    assert record.saturated.all()
    np.testing.assert_allclose(record.time_saturated(), [0.3], rtol=1e-12)
    np.testing.assert_allclose(record.force[:, 0], limit, rtol=1e-15)
    assert np.all(record.demand[:, 0] > limit)

    def falling(_, y):
        return [y[1], (limit - MASS * GRAVITY * ARM * math.cos(y[0])) / MOMENT]

    solution = scipy.integrate.solve_ivp(
        falling, (0.0, 0.3), [0.0, 0.0], t_eval=t, rtol=1e-12, atol=1e-14
    )
    np.testing.assert_allclose(run.q[:, 0], solution.y[0], rtol=0.0, atol=1e-8)
    assert "saturated 0.3 s (100.0% of the run)" in record.lines()[0]


def test_a_saturated_start_is_the_closed_loops_with_the_limit():
    """A pendulum started 0.5 rad below a level reference with a limit of 1.5 m g ARM: saturated
    at first, then within the limit. Against an independent SciPy integration of
    I_O θ̈ = clip(I_O (K_p e + K_d ė) + m g ARM cos θ, ±L) − m g ARM cos θ: the motion, and the
    time saturated within one sample interval of the independent switch time."""
    dyn = _pendulum()
    weight = MASS * GRAVITY * ARM
    limit, kp, kd = 1.5 * weight, 100.0, 20.0
    t_table = np.linspace(0.0, 1.0, 3)
    spec = _spec("hinge", t_table, 0.0, 0.0, 0.0, kp=kp, kd=kd, force_limit=(-limit, limit))
    controller = ComputedTorque(dyn, [spec])
    t = np.linspace(0.0, 1.0, 1001)
    run = simulate(dyn, t, np.array([-0.5]), np.zeros(1), controller, **TIGHT)
    record = controller.record(t, run.q, run.v, run.controller)

    def demand(y):
        return MOMENT * (kp * -y[0] - kd * y[1]) + weight * math.cos(y[0])

    def loop(_, y):
        return [y[1], (np.clip(demand(y), -limit, limit) - weight * math.cos(y[0])) / MOMENT]

    def release(_, y):  # the demand comes back within the limit
        return demand(y) - limit

    release.terminal = False
    solution = scipy.integrate.solve_ivp(
        loop, (0.0, 1.0), [-0.5, 0.0], t_eval=t, rtol=1e-12, atol=1e-14, events=release
    )
    # the switch makes the right-hand side kink: both integrators step over it, 1e-7 rad
    np.testing.assert_allclose(run.q[:, 0], solution.y[0], rtol=0.0, atol=1e-7)
    switch = solution.t_events[0][0]
    assert 0.0 < switch < 1.0 and record.saturated[0, 0] and not record.saturated[-1, 0]
    assert abs(record.time_saturated()[0] - switch) <= t[1] - t[0]


def test_a_rate_limit_holds_the_lagged_force_to_its_slope():
    """The lagged slider with a rate limit r below what its command asks: the force ramps at
    ±r (flagged) and the motion is that of an independent SciPy integration of the linear
    model with the clipped rate, Ḟ = clip((m (K_p e − K_d ẋ) − F) / T, ±r)."""
    mass, lag, kp, kd, target, rate = 3.0, 0.01, 400.0, 40.0, 0.1, 400.0
    dyn = _slider(mass)
    t_table = np.linspace(0.0, 0.5, 3)
    spec = _spec("slide", t_table, target, 0.0, 0.0, kp=kp, kd=kd, lag=lag, rate_limit=rate)
    controller = ComputedTorque(dyn, [spec])
    t = np.linspace(0.0, 0.5, 501)
    run = simulate(dyn, t, np.zeros(1), np.zeros(1), controller, **TIGHT)
    record = controller.record(t, run.q, run.v, run.controller)

    def linear(_, y):
        x, v, force = y
        wanted = (mass * (kp * (target - x) - kd * v) - force) / lag
        return [v, force / mass, np.clip(wanted, -rate, rate)]

    solution = scipy.integrate.solve_ivp(
        linear, (0.0, 0.5), [0.0, 0.0, mass * kp * target], t_eval=t, rtol=1e-12, atol=1e-14
    )
    # the clipped rate kinks the right-hand side: both integrators step over it, 1e-7 m
    np.testing.assert_allclose(run.q[:, 0], solution.y[0], rtol=0.0, atol=1e-7)
    flagged = record.rate_limited[:, 0]
    assert flagged.any() and not flagged.all()
    both = flagged[:-1] & flagged[1:]  # intervals flagged at both ends: a ramp at ±r
    slope = np.diff(record.force[:, 0]) / np.diff(t)
    np.testing.assert_allclose(np.abs(slope[both]), rate, rtol=1e-6)


@pytest.mark.parametrize(
    ("specs", "message"),
    [
        ([_spec("hinj", np.linspace(0.0, 1.0, 3), 0.0, 0.0, 0.0)], "did you mean 'hinge'"),
        ([_spec("hinge", np.linspace(0.0, 1.0, 3), 0.0, 0.0, 0.0)] * 2, "controlled twice"),
        ([_spec("hinge", np.linspace(0.0, 1.0, 3), 0.0, 0.0, 0.0, area=1e-3)], "prismatic"),
        ([], "one ControlSpec or more"),
    ],
)
def test_bad_controllers_are_refused_in_one_line(specs, message):
    with pytest.raises(InputError, match=message):
        ComputedTorque(_pendulum(), specs)


def test_a_run_beyond_the_reference_is_refused():
    controller = ComputedTorque(_pendulum(), [_spec("hinge", np.linspace(0.0, 1.0, 3), 0, 0, 0)])
    controller.check_covers(0.0, 1.0)
    with pytest.raises(InputError, match=r"covers t = 0 … 1 s, the run 0 … 2 s"):
        controller.check_covers(0.0, 2.0)


ROLL, FREQUENCY, HELD = 0.1, 5.0, 0.3
"""The rocking base's roll amplitude Φ [rad] and frequency Ω [rad/s], and the angle θ_ref [rad]
the pendulum is held at (test_forward_base's pendulum on the forward axis)."""


def held_on_rocking_base(dyn, controller):
    """Run ``controller`` holding test_forward_base's pendulum at θ_ref = HELD on its base
    rolling as φ = Φ cos Ωt for 2 s, from the reference (TIGHT), check that the error stays at
    the integrator's tolerance, and return the run, the controller's record and the hinge's
    moment by hand, u = m L² φ̈ + m g L sin(θ_ref + φ) (the absolute angle from hanging is
    θ + φ), at the run's samples."""
    from .test_forward_base import LENGTH, G
    from .test_forward_base import MASS as BOB

    t = np.linspace(0.0, 2.0, 201)
    run = simulate(dyn, t, np.array([HELD]), np.zeros(1), controller, **TIGHT)
    record = controller.record(t, run.q, run.v, run.controller)
    assert record.peak_error()[0] <= 1e-9  # the integrator's tolerance, as on a base at rest
    phi = ROLL * np.cos(FREQUENCY * t)
    drive = BOB * LENGTH**2 * -(FREQUENCY**2) * phi + BOB * G * LENGTH * np.sin(HELD + phi)
    return run, record, drive


def test_on_a_rocking_base_the_law_holds_the_joint_with_the_base_s_terms():
    """A point-mass pendulum hinged on the forward axis x of a base rolling as φ = Φ cos Ωt,
    held at θ_ref = 0.3 rad from the start: the law includes the base's terms (the run's own
    right-hand side), so the error stays at the integrator's tolerance and the drive is the
    hand-written u = m L² φ̈ + m g L sin(θ_ref + φ) (held_on_rocking_base)."""
    from feeder.chain import BaseMotion

    from .test_forward_base import Harmonic, pendulum

    base = BaseMotion((Harmonic(3, ROLL, FREQUENCY),))
    dyn = ChainDynamics(pendulum(), ["swing"], base=base)
    spec = _spec("swing", np.linspace(0.0, 2.0, 3), HELD, 0.0, 0.0)
    _, record, drive = held_on_rocking_base(dyn, ComputedTorque(dyn, [spec]))
    # the drive is ~1 N·m; the state's 1e-9 rad offset moves it by ~1e-8 N·m
    np.testing.assert_allclose(record.force[:, 0], drive, rtol=0.0, atol=1e-7)


def test_a_continuous_joint_s_error_is_the_short_way_round():
    """A wheel on a continuous joint (q = (cos θ, sin θ)) at θ = 3.1 rad, its reference at
    −3.1 rad: the error is 2π − 6.2 rad, not −6.2, and a run from there settles on the
    reference's angle the short way (θ passes π, not 0)."""
    model = pin.Model()
    joint = model.addJoint(0, pin.JointModelRUBZ(), pin.SE3.Identity(), "wheel")
    model.appendBodyToJoint(
        joint, pin.Inertia(1.0, np.zeros(3), np.eye(3) * 0.01), pin.SE3.Identity()
    )
    model.gravity = pin.Motion.Zero()
    dyn = ChainDynamics(ClosedChain(model, []), ["wheel"])
    controller = ComputedTorque(dyn, [_spec("wheel", np.linspace(0.0, 2.0, 3), -3.1, 0.0, 0.0)])
    q0 = np.array([math.cos(3.1), math.sin(3.1)])
    error, _ = controller.errors(controller.reference(0.0), q0, np.zeros(1))
    assert error[0] == pytest.approx(2.0 * math.pi - 6.2, abs=1e-14)
    t = np.linspace(0.0, 2.0, 21)
    run = simulate(dyn, t, q0, np.zeros(1), controller, **TIGHT)
    angle = np.arctan2(run.q[:, 1], run.q[:, 0])
    assert np.all(np.abs(angle) >= 3.1 - 1e-9)  # it never turned the long way, through 0
    assert abs(controller.record(t, run.q, run.v).error[-1, 0]) <= 1e-6
