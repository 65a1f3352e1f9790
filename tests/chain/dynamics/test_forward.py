"""Forward runs of any closed chain: the accelerations against an independent KKT solve, energy
and work balances, drift control, an analytic oscillator, the inverse dynamics' loads
reproducing their motion, and the refusals."""

from __future__ import annotations

import math
import re
import sys
import warnings

import numpy as np
import pinocchio as pin
import pytest
import scipy.interpolate

from feeder.chain import Closure, load_closed_chain
from feeder.chain.assembly.partition import Partition
from feeder.chain.assembly.tracking import track
from feeder.chain.dynamics import budget, forward
from feeder.chain.dynamics.forward import simulate
from feeder.chain.dynamics.forward_equations import ForwardEquations, IntegrationError
from feeder.chain.dynamics.inverse import ChainDynamics, inverse_dynamics
from feeder.chain.dynamics.loads_solve import MAX_FORCE_GAIN, load_gain, load_rank
from feeder.chain.dynamics.stiffness import element_rates
from feeder.chain.model.forces import Cylinder, JointSpring, Load, Spring, Table
from feeder.exceptions import FeederWarning, InputError

from ...conftest import REPO
from .delta import rod3_angle

ACCELERATION = 1e-10
"""Relative agreement of Pinocchio's constraintDynamics (proximal, accuracy 1e-13) with a
least-squares solve of the KKT system: both are exact to round-off of a system whose condition
number is ~1e3 (the four-bar's mass matrix spans 1e-5…1e-3 kg·m²)."""

ENERGY = 1e-7
"""[J] Energy balance of a 1 s run (rtol 1e-8, atol 1e-10) of a ~0.4 kg four-bar whose energy
swings by ~0.1 J: the integrator's global error (measured ~1e-9 J) with room; a first-order
error (dropping a term of the equations) is ~1e-3 J."""

DRIFT = 1e-8
"""[m] Closure residual of the interpolated samples before projection: the dense output's error
(~1e-10 m measured)."""


def _kkt_accelerations(chain, q, v, tau, rate):
    """q̈ from [M Jᵀ; J 0] solved by least squares (numpy), with the chain's own closure rows and
    Baumgarte's terms: independent of Pinocchio's constraintDynamics."""
    model, data = chain.model, chain.model.createData()
    mass = pin.crba(model, data, q)
    mass = np.triu(mass) + np.triu(mass, 1).T
    bias = pin.nonLinearEffects(model, data, q, v)
    jac = chain.jacobian(q)
    target = -chain.bias(q, v) - 2.0 * rate * (jac @ v) - rate**2 * chain.residual(q)
    nc = jac.shape[0]
    kkt = np.block([[mass, jac.T], [jac, np.zeros((nc, nc))]])
    return np.linalg.lstsq(kkt, np.concatenate([tau - bias, target]), rcond=None)[0][: model.nv]


def test_the_accelerations_are_those_of_the_kkt_system(four_bar):
    chain, partition, q0 = four_bar
    spring = JointSpring("coupler_joint", stiffness=0.3, rest=0.1, damping=0.01, preload=0.02)
    dyn = ChainDynamics(chain, ["crank_joint"], elements=[spring])
    equations = ForwardEquations(dyn, lambda t, q, v: np.array([0.05]), rate=20.0)
    v = partition.velocity(q0, np.array([3.0]))
    for q in (q0, pin.integrate(chain.model, q0, np.array([1e-6, -2e-6, 1e-6]))):  # off the loop
        tau = np.zeros(3)
        tau[0] = 0.05
        tau[1] = -spring.resistance(q[1], v[1])
        expected = _kkt_accelerations(chain, q, v, tau, 20.0)
        a = equations(0.0, np.concatenate([q, v, [0.0]]))[3:6]
        np.testing.assert_allclose(
            a, expected, rtol=0.0, atol=ACCELERATION * np.abs(expected).max()
        )
        # an output sample's: the closed chain's own, without Baumgarte's terms (J q̈ = −J̇ q̇)
        own = _kkt_accelerations(chain, q, v, tau, 0.0)
        np.testing.assert_allclose(
            equations.sample_accelerations(0.0, q, v),
            own,
            rtol=0.0,
            atol=ACCELERATION * np.abs(own).max(),
        )


def test_a_free_swing_keeps_its_energy_and_its_loop(four_bar):
    chain, _, q0 = four_bar
    dyn = ChainDynamics(chain, ["crank_joint"])
    run = simulate(dyn, np.linspace(0.0, 1.0, 101), q0, np.zeros(3))
    assert np.ptp(run.q[:, 0]) > 0.5  # it does swing
    assert np.abs(run.work).max() == 0.0  # nothing does work but gravity
    assert run.energy_error() <= ENERGY
    assert run.drift() <= DRIFT
    # No drive: the inverse dynamics of the run give a zero crank torque (to the loads' scale).
    torque = run.loads.actuators["crank_joint"]
    scale = np.abs(run.loads.closure_forces).max() * 0.04  # [N·m]: force × the 40 mm crank
    assert np.abs(torque).max() <= 1e-8 * scale


def test_the_samples_keep_the_loops_closed_whether_projected_or_not(four_bar):
    """Samples are projected only where the dense output opened the loops beyond
    drift_tolerance: at a tolerance below the dense output's error some are, at one above it
    none; either way every sample closes the loops to the tolerance, positions and velocities
    (the loads' inverse dynamics then read back the zero drive, as above)."""
    chain, _, q0 = four_bar
    dyn = ChainDynamics(chain, ["crank_joint"])
    t = np.linspace(0.0, 1.0, 101)
    for tolerance in (1e-12, 1e-8):  # below and above the ~1e-10 m of the dense output
        run = simulate(dyn, t, q0, np.zeros(3), drift_tolerance=tolerance)
        # the projection closes to Newton's tolerance (~1e-13), far inside either tolerance
        assert np.abs([chain.residual(q) for q in run.q]).max() <= tolerance
        opening = [np.abs(chain.jacobian(q) @ v).max() for q, v in zip(run.q, run.v, strict=True)]
        assert max(opening) <= tolerance * max(1.0, np.abs(run.v).max())
    assert run.drift() <= 1e-8  # the last run's samples, none projected, within that tolerance


def test_a_run_for_its_motion_alone_is_the_same_motion_without_the_loads(four_bar):
    """loads=False: the same integration (steps, evaluations), the same samples where neither
    run projects them and within the drift tolerance where the full run projects one for its
    loads; the actuation is the same function of them; no accelerations, loads or energies,
    and the balance is refused rather than computed from nothing."""
    chain, _, q0 = four_bar
    dyn = ChainDynamics(chain, ["crank_joint"])
    t = np.linspace(0.0, 1.0, 101)

    def drive(time, q, v):
        return np.array([0.02 * math.sin(3.0 * time) - 0.001 * v[0]])

    full = simulate(dyn, t, q0, np.zeros(3), drive)
    motion = simulate(dyn, t, q0, np.zeros(3), drive, loads=False)
    assert (motion.steps, motion.evaluations) == (full.steps, full.evaluations)
    np.testing.assert_array_equal(motion.residual, full.residual)  # the drift as integrated
    # a sample the full run projects for its loads moves by at most its drift (~1e-10 m),
    # its rates by the loops' opening in the dense output, the integrator's error (rtol 1e-8
    # of the rates: up to 5e-9 of them measured)
    speed = np.abs(full.v).max()
    np.testing.assert_allclose(motion.q, full.q, rtol=0, atol=10 * full.drift())
    np.testing.assert_allclose(motion.v, full.v, rtol=0, atol=1e-8 * speed)
    # the drive's damping term moves with the rates: 0.001 N·m·s of those
    np.testing.assert_allclose(motion.actuation, full.actuation, rtol=0, atol=1e-11 * speed)
    assert motion.a is None and motion.loads is None and motion.energy is None
    assert motion.kinetic is None
    with pytest.raises(InputError, match="motion alone"):
        motion.energy_error()
    with pytest.raises(InputError, match="loads must be True or False"):
        simulate(dyn, t, q0, np.zeros(3), drive, loads="no")


def test_outputs_far_apart_are_still_integrated_finely(four_bar):
    """The step is the integrator's, never the output spacing: 1 s between outputs."""
    chain, _, q0 = four_bar
    dyn = ChainDynamics(chain, ["crank_joint"])
    run = simulate(dyn, np.array([0.0, 1.0, 2.0]), q0, np.zeros(3))
    assert run.steps > 50 and run.energy_error() <= ENERGY


def test_springs_and_dampers_balance_energy_and_work(four_bar):
    """A point-to-point spring with a damper and a time-dependent push, a preloaded joint spring
    with a damper and a tabulated load: E(t) − E(0) equals the work of the non-conservative
    forces; without the dampers and the push, the energy is conserved."""
    chain, _, q0 = four_bar
    table = Table(np.array([0.0, 0.5, 1.0]), np.array([[0, 0, 0, 0, 0, 0.0], [0, 0, 0, 0, 0, 0.02],
                                                        [0.1, 0, 0, 0, 0, 0.0]]))  # fmt: skip
    lossy = [
        Spring(
            ("rocker_tip", "crank"),
            stiffness=40.0,
            rest_length=0.09,
            damping=0.5,
            force=lambda t: 0.2 * math.sin(5.0 * t),
        ),  # fmt: skip
        JointSpring("rocker_joint", stiffness=0.2, rest=1.0, damping=0.002, preload=0.01),
        Load("coupler_tip", table=table),
    ]
    conservative = [
        Spring(("rocker_tip", "crank"), stiffness=40.0, rest_length=0.09),
        JointSpring("rocker_joint", stiffness=0.2, rest=1.0, preload=0.01),
    ]
    t = np.linspace(0.0, 1.0, 51)
    lossless = simulate(ChainDynamics(chain, ["crank_joint"], elements=conservative), t, q0,
                        np.zeros(3))  # fmt: skip
    assert np.abs(lossless.work).max() == 0.0 and lossless.energy_error() <= ENERGY
    run = simulate(ChainDynamics(chain, ["crank_joint"], elements=lossy), t, q0, np.zeros(3))
    assert np.abs(run.work).max() > 1e-3  # the dampers and pushes do work
    assert run.energy_error() <= ENERGY
    assert set(run.loads.elements) == {"spring:rocker_tip-crank", "joint_spring:rocker_joint"}


def test_the_element_forces_of_the_inverse_dynamics_drive_the_forward_run(four_bar):
    """The forward run's samples, handed to the inverse dynamics with the same elements, need no
    drive at the (undriven) crank: the elements' wrenches enter both the same way."""
    chain, _, q0 = four_bar
    elements = [
        Spring(("rocker_tip", "crank"), stiffness=40.0, rest_length=0.09, damping=0.5),
        JointSpring("coupler_joint", stiffness=0.1, rest=0.0, damping=0.001, preload=-0.01),
        Load("coupler_tip", force=(0.0, -2.0, 0.0), moment=(0.0, 0.0, 0.01)),
    ]
    dyn = ChainDynamics(chain, ["crank_joint"], elements=elements)
    run = simulate(dyn, np.linspace(0.0, 0.5, 26), q0, np.zeros(3))
    loads = inverse_dynamics(dyn, run.q, run.v, run.a, t=run.t)
    scale = np.abs(loads.closure_forces).max() * 0.04
    assert np.abs(loads.actuators["crank_joint"]).max() <= 1e-7 * scale
    # The spring's tension from the inverse dynamics is k (ℓ − ℓ0) + c ℓ̇ at the samples.
    model, data = chain.model, chain.model.createData()
    a, b = chain.frame_id("rocker_tip"), chain.frame_id("crank")
    for k in (0, 10, 25):
        pin.forwardKinematics(model, data, run.q[k], run.v[k])
        gap = (
            pin.updateFramePlacement(model, data, b).translation
            - pin.updateFramePlacement(model, data, a).translation
        )
        rate = (
            (
                pin.getFrameVelocity(model, data, b, pin.LOCAL_WORLD_ALIGNED).linear
                - pin.getFrameVelocity(model, data, a, pin.LOCAL_WORLD_ALIGNED).linear
            )
            @ gap
            / np.linalg.norm(gap)
        )
        tension = 40.0 * (np.linalg.norm(gap) - 0.09) + 0.5 * rate
        assert loads.elements["spring:rocker_tip-crank"][k] == pytest.approx(tension, rel=1e-12)


def test_a_torsion_oscillator_has_its_analytic_period():
    """One link on a hinge with a torsion spring, no loop and no gravity: θ(t) = θ0 cos(ω t),
    ω = √(k / I_O)."""
    model = pin.Model()
    inertia = pin.Inertia(0.5, np.array([0.1, 0.0, 0.0]), np.diag([1e-4, 1e-3, 2e-3]))
    joint = model.addJoint(0, pin.JointModelRZ(), pin.SE3.Identity(), "hinge")
    model.appendBodyToJoint(joint, inertia, pin.SE3.Identity())
    model.addFrame(pin.Frame("tip", joint, 0, pin.SE3.Identity(), pin.FrameType.OP_FRAME))
    model.gravity = pin.Motion.Zero()
    from feeder.chain import ClosedChain

    chain = ClosedChain(model, [])
    k = 0.8  # [N·m/rad]
    moment = 2e-3 + 0.5 * 0.1**2  # I_O [kg·m²], parallel axes
    dyn = ChainDynamics(chain, ["hinge"], elements=[JointSpring("hinge", stiffness=k)])
    t = np.linspace(0.0, 0.5, 51)
    run = simulate(dyn, t, np.array([0.3]), np.zeros(1), rtol=1e-10, atol=1e-12)
    exact = 0.3 * np.cos(math.sqrt(k / moment) * t)
    np.testing.assert_allclose(run.q[:, 0], exact, rtol=0.0, atol=1e-8)  # tolerance-limited
    # its resistance, reported by the run, is k θ
    np.testing.assert_allclose(
        run.loads.elements["joint_spring:hinge"], k * run.q[:, 0], atol=1e-12
    )


def test_the_inverse_dynamics_torque_drives_its_motion(four_bar):
    """The torque of a prescribed turn (no gravity: the open-loop run is then stable), fed back
    through a forward run, follows the turn."""
    chain, partition, q0 = four_bar
    gravity = chain.model.gravity.copy()  # model.gravity is a view: keep its value
    chain.model.gravity = pin.Motion.Zero()
    try:
        dyn = ChainDynamics(chain, ["crank_joint"])
        fine = np.linspace(0.0, 1.0, 2001)
        x = (q0[0] + 2.0 * math.pi * fine + math.pi * fine**2)[:, None]
        dx = (2.0 * math.pi + 2.0 * math.pi * fine)[:, None]
        motion = track(partition, q0, x, dx, np.full_like(x, 2.0 * math.pi))
        q, v, a = motion.q, motion.v, motion.a
        torque = inverse_dynamics(dyn, q, v, a).actuators["crank_joint"]
        spline = scipy.interpolate.CubicSpline(fine, torque)
        drive = lambda time, q, v: np.array([spline(time)])  # noqa: E731
        run = simulate(dyn, fine[::20], q[0], v[0], drive, rtol=1e-10, atol=1e-12)
    finally:
        chain.model.gravity = gravity
    # The torque is a cubic spline through samples 0.5 ms apart (error O(h⁴)): the motion it
    # drives follows the prescribed one to 7e-9 rad (measured, at rtol 1e-8 and 1e-10 alike: the
    # spline's and the tracked samples' error); the motor's work (0.037 J) is the change of
    # energy to the integrator's tolerance (1.4e-11 J measured).
    assert run.tracking(chain.model, q[::20]).max() <= 5e-8
    assert run.energy_error() <= 1e-8 * np.abs(run.work).max()
    np.testing.assert_allclose(run.loads.actuators["crank_joint"], torque[::20], atol=1e-9)


def test_refusals(four_bar):
    chain, _, q0 = four_bar
    dyn = ChainDynamics(chain, ["crank_joint"])
    t = np.array([0.0, 0.1])
    with pytest.raises(InputError, match="increasing"):
        simulate(dyn, np.array([0.0, 0.0, 1.0]), q0, np.zeros(3))
    with pytest.raises(InputError, match="actuation at t = 0 s"):
        simulate(dyn, t, q0, np.zeros(3), lambda time, q, v: np.array([np.nan]))
    with pytest.raises(InputError, match="actuation"):
        simulate(dyn, t, q0, np.zeros(3), lambda time, q, v: np.zeros(2))
    with pytest.raises(InputError, match="Baumgarte"):
        simulate(dyn, t, q0, np.zeros(3), rate=-1.0)
    with pytest.raises(InputError, match="method"):
        simulate(dyn, t, q0, np.zeros(3), method="Euler")
    with pytest.raises(InputError, match="rtol"):
        simulate(dyn, t, q0, np.zeros(3), rtol=0.0)
    with pytest.raises(InputError, match="rtol 1e-20 is below what double precision can meet"):
        simulate(dyn, t, q0, np.zeros(3), rtol=1e-20)  # SciPy would run at 2.2e-14 instead
    short = Table(np.array([0.0, 0.05]), np.zeros((2, 6)), source="short.csv")
    loaded = ChainDynamics(chain, ["crank_joint"], elements=[Load("coupler_tip", table=short)])
    with pytest.raises(InputError, match="short.csv covers"):
        simulate(loaded, t, q0, np.zeros(3))
    with pytest.raises(InputError, match="no frame 'nowhere'"):
        ChainDynamics(chain, ["crank_joint"], elements=[Spring(("nowhere", "crank"))])


def test_forces_that_become_nan_stop_the_run_with_an_error(four_bar):
    """A push that turns NaN mid-run: an IntegrationError naming the time, never NaN results."""
    chain, _, q0 = four_bar
    push = lambda t: 0.1 if t < 0.05 else math.nan  # noqa: E731
    dyn = ChainDynamics(
        chain, ["crank_joint"], elements=[Spring(("rocker_tip", "crank"), force=push)]
    )
    with pytest.raises(IntegrationError, match=r"not finite at t = 0\.0[5-9]"):
        simulate(dyn, np.linspace(0.0, 0.1, 11), q0, np.zeros(3))


def test_projecting_every_step_keeps_the_run(four_bar):
    """A drift tolerance below round-off projects after every step, the last ones too (a
    restart there once asked SciPy for a first step beyond the end): the run is the same."""
    chain, _, q0 = four_bar
    dyn = ChainDynamics(chain, ["crank_joint"])
    t = np.linspace(0.0, 0.3, 7)
    plain = simulate(dyn, t, q0, np.zeros(3))
    projected = simulate(dyn, t, q0, np.zeros(3), drift_tolerance=1e-300)
    assert projected.projections > 0.9 * projected.steps > 10  # all but exact or final steps
    # both follow the same motion to the integrator's tolerance (rtol 1e-8 on ~1 rad)
    np.testing.assert_allclose(projected.q, plain.q, atol=1e-6)
    assert projected.energy_error() <= ENERGY


def test_a_run_into_a_dead_centre_stops_there_naming_the_time(delta):
    """Released, the delta falls until the two links of its third rod line up (20° apart at
    rest, a dead centre at t ≈ 0.050 s). Its loads' condition number passes MAX_FORCE_GAIN a few
    degrees before: the run stops there, naming the time (it used to go on, crawl through the
    dead centre in 69 308 steps losing 78 % of its kinetic energy in a projection, and end with
    its samples refused, without a time); a run that ends before that time is exact."""
    dyn, q0 = delta
    zero = np.zeros(dyn.chain.model.nv)
    with pytest.raises(IntegrationError, match=r"singular pose .* at t = 0\.04") as caught:
        simulate(dyn, np.linspace(0.0, 0.06, 5), q0, zero, singular="stop")
    message = str(caught.value)
    before = float(re.search(r"end the run before t = ([0-9.]+) s", message).group(1))
    stop = float(re.search(r"at t = ([0-9.]+) s", message).group(1))
    assert 0.0 < stop - before < 1e-5  # the crossing, to 1/1024 of a step (~1.5 ms)
    run = simulate(dyn, np.linspace(0.0, before, 5), q0, zero, singular="stop")
    # the integrator's tolerance (rtol 1e-8) with room; measured 3.5e-13 of the kinetic energy
    assert run.energy_error() <= 1e-9 * run.kinetic.max()
    rank = load_rank(dyn, q0)
    assert load_gain(dyn, run.q[-1], rank) <= MAX_FORCE_GAIN
    angles = [abs(rod3_angle(dyn.chain, q)) for q in (q0, run.q[-1])]
    assert math.radians(19.0) < angles[0] and math.radians(3.0) < angles[1] < math.radians(8.0)


def test_samples_refused_after_the_run_are_named_by_their_time(delta, monkeypatch):
    """Where the check after every step passes and an output sample's loads are still refused
    (here: the check turned off), the error names the sample's time."""
    dyn, q0 = delta
    monkeypatch.setattr(forward, "load_gain", lambda *args: 1.0)
    with pytest.raises(IntegrationError, match=r"loads cannot be computed at t = 0\.045 s"):
        simulate(
            dyn, np.linspace(0.0, 0.045, 10), q0, np.zeros(dyn.chain.model.nv), singular="stop"
        )


def test_a_spring_between_two_ground_frames_changes_nothing(tmp_path):
    """Both ends on the ground: no generalized force, no work, so the run is the run without it
    (the right-hand side once failed on such a line, its dℓ/dq having no moving end)."""
    text = (REPO / "examples" / "four_bar" / "four_bar.urdf").read_text(encoding="utf-8")
    anchor = (
        '<link name="ground"/>\n  <link name="anchor"/>\n'
        '  <joint name="anchor_joint" type="fixed"><origin xyz="0.3 0 0"/>'
        '<parent link="ground"/><child link="anchor"/></joint>'
    )
    (tmp_path / "four_bar.urdf").write_text(text.replace('<link name="ground"/>', anchor, 1))
    chain = load_closed_chain(
        tmp_path / "four_bar.urdf", [Closure("coupler_tip", "rocker_tip", "revolute")]
    )
    chain.model.gravity = pin.Motion(np.array([0.0, -9.81, 0.0]), np.zeros(3))
    q0 = Partition(chain, ["crank_joint"]).assemble(np.array([math.radians(40.0), -0.35, 1.0]))
    t = np.linspace(0.0, 0.1, 6)
    spring = Spring(("ground", "anchor"), stiffness=10.0, rest_length=0.5, damping=1.0)
    alone = simulate(ChainDynamics(chain, ["crank_joint"]), t, q0, np.zeros(3))
    run = simulate(ChainDynamics(chain, ["crank_joint"], elements=[spring]), t, q0, np.zeros(3))
    np.testing.assert_array_equal(run.q, alone.q)
    assert np.abs(run.work).max() == 0.0


# -- bounds: every run answers ------------------------------------------------------------------


def test_a_run_beyond_the_step_cap_stops_at_it_naming_the_time(four_bar, monkeypatch):
    """A run of 1e9 s (or 1e308 s) once went on for a million steps: it stops at the cap of
    steps (made small here, so that the stop comes from the cap and not from the test's
    patience), in one line naming the time it reached, which is the time to end it by."""
    chain, _, q0 = four_bar
    monkeypatch.setattr(budget, "MAX_STEPS", 300)
    dyn = ChainDynamics(chain, ["crank_joint"])
    for end in (1e9, 1e308):
        with pytest.raises(IntegrationError) as caught:
            simulate(dyn, np.array([0.0, end]), q0, np.zeros(3))
        message = str(caught.value)
        assert "\n" not in message and f"of {end:g} s" in message
        assert "reached the cap of 300 integration steps" in message
        reached = float(re.search(r"stopped at t = ([0-9.e+]+) s", message).group(1))
        assert 0.0 < reached < 100.0  # the swing takes ~90 steps per second of motion
        assert f"end it by t = {reached:.6g} s" in message


def test_requests_beyond_the_caps_are_refused_before_the_run(four_bar, monkeypatch):
    """More output times than the memory budget allows, or a longest step that needs more
    steps than the cap for the span, are refused before any step (the integrator is not even
    built), with the numbers and the remedy."""
    chain, _, q0 = four_bar
    dyn = ChainDynamics(chain, ["crank_joint"])
    monkeypatch.setattr(forward, "_integrate", lambda *args: pytest.fail("the run started"))
    cap = budget.SAMPLE_MEMORY // (budget.SAMPLE_BYTES * 3)  # the four-bar's 3 coordinates
    assert budget.max_samples(3) == cap
    with pytest.raises(InputError, match=rf"{cap + 1} output samples \(t\) are more than the "
                       rf"{cap} .* ask for at most {cap}"):  # fmt: skip
        simulate(dyn, np.linspace(0.0, 1.0, cap + 1), q0, np.zeros(3))
    with pytest.raises(InputError, match=r"max_step 1e-09 s needs at least 1e\+09 steps .* cap"):
        simulate(dyn, np.array([0.0, 1.0]), q0, np.zeros(3), max_step=1e-9)


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda c: ChainDynamics(c, ["crank_joint"], elements=Spring(("rocker_tip", "crank"))),
         "got the single element 'spring:rocker_tip-crank': put it in a list"),
        (lambda c: ChainDynamics(c, ["crank_joint"], elements=None), "elements must be a list"),
        (lambda c: ChainDynamics(c, ["crank_joint"], elements="spring"), "got 'spring'"),
        (lambda c: ChainDynamics(c, ["crank_joint"], elements=3), "elements must be a list"),
        (lambda c: ChainDynamics("chain", ["crank_joint"]), "chain must be a ClosedChain"),
        (lambda c: ChainDynamics(c, ["crank_joint"], stiffness=[1.0]), "stiffness must map"),
    ],
)  # fmt: skip
def test_bad_dynamics_are_refused_in_one_line(four_bar, call, message):
    chain, _, _ = four_bar
    with pytest.raises(InputError, match=re.escape(message)) as caught:
        call(chain)
    assert "\n" not in str(caught.value)


@pytest.mark.parametrize(
    "arguments, keywords, message",
    [
        (("dyn",), {}, "dyn must be a ChainDynamics"),
        ((None, lambda t, q, v: "0.5"), {}, "actuation at t = 0 s [N or N·m] must be numeric"),
        ((None, lambda t, q, v: [True]), {}, "must be numeric, got the truth value"),
        (
            (None, 0.5),
            {},
            "actuation must be a function u(t, q, v), a Controller or None, got 0.5",
        ),
        ((None,), {"rate": 1e300}, "rate (Baumgarte's) must be ≥ 0 and ≤ 1e+06"),
        ((None,), {"max_step": True}, "max_step [s] must be a number"),
        ((None,), {"t": np.array([-1e308, 1e308])}, "its length is not a finite number"),
    ],
)
def test_bad_run_arguments_are_refused_in_one_line(four_bar, arguments, keywords, message):
    """Each once a traceback from inside Python, NumPy or SciPy (AttributeError, ValueError,
    TypeError, OverflowError), or a truth value taken for 1 N·m."""
    chain, _, q0 = four_bar
    dyn = ChainDynamics(chain, ["crank_joint"])
    first, *rest = arguments
    t = keywords.pop("t", np.array([0.0, 0.01]))
    with pytest.raises(InputError, match=re.escape(message)) as caught:
        simulate(dyn if first is None else first, t, q0, np.zeros(3), *rest, **keywords)
    assert "\n" not in str(caught.value)
    if first is not None:
        with pytest.raises(InputError, match=re.escape(message)):
            inverse_dynamics(first, q0[None], np.zeros((1, 3)), np.zeros((1, 3)))


# -- stiffness ----------------------------------------------------------------------------------

DAMPER = 1e6
"""[N·s/m] A damper between the ground's origin and the rocker's tip of the four-bar: its rate,
~2.5e5 /s, is four orders above the swing's, so DOP853's steps are held by its stability."""


def _line_rate_terms(chain, q, frames):
    """gᵀ Z (ZᵀMZ)⁻¹ Zᵀ g [1/kg] of the line between two frames at the closed pose q: g = dℓ/dq
    by central differences of the frames' distance along the chain's free motions Z (from
    numpy's SVD of the closure rows), M from Pinocchio's CRBA — not the code under test."""
    model, data = chain.model, chain.model.createData()
    _, s, vt = np.linalg.svd(chain.jacobian(q))
    free = vt[int((s > 1e-9 * s.max()).sum()) :].T
    mass = pin.crba(model, data, q)
    mass = np.triu(mass) + np.triu(mass, 1).T

    def length(x):
        pin.framesForwardKinematics(model, data, x)
        a, b = (data.oMf[model.getFrameId(name)].translation for name in frames)
        return np.linalg.norm(b - a)

    h = 1e-6
    ahead = np.array([length(pin.integrate(model, q, h * e)) for e in free.T])
    behind = np.array([length(pin.integrate(model, q, -h * e)) for e in free.T])
    g = (ahead - behind) / (2.0 * h)  # dℓ/dz along the free motions, (d,)
    return float(g @ np.linalg.solve(free.T @ mass @ free, g))


def test_an_elements_rate_is_that_of_its_line_against_the_mass(four_bar):
    """At rest, a damper alone has the rate c gᵀM⁻¹g and a spring at its rest length (no
    tension, so no stiffness of its own direction) √(k gᵀM⁻¹g), M⁻¹ the closed chain's (on its
    free motions): the linearisation by central differences agrees to 1e-6 (its truncation error
    is ~1e-9 of the rates, the reference's differences in ℓ ~1e-10)."""
    chain, _, q0 = four_bar
    frames = ("ground", "rocker_tip")
    inverse_mass = _line_rate_terms(chain, q0, frames)
    model, data = chain.model, chain.model.createData()
    pin.framesForwardKinematics(model, data, q0)
    rest = np.linalg.norm(data.oMf[chain.frame_id("rocker_tip")].translation)
    elements = [Spring(frames, damping=DAMPER, name="damper"),
                Spring(frames, stiffness=4e4, rest_length=rest, name="spring")]  # fmt: skip
    rates = element_rates(ChainDynamics(chain, ["crank_joint"], elements=elements), q0,
                          np.zeros(3), 0.0)  # fmt: skip
    assert rates["damper"] == pytest.approx(DAMPER * inverse_mass, rel=1e-6)
    assert rates["spring"] == pytest.approx(math.sqrt(4e4 * inverse_mass), rel=1e-6)


def test_a_stiff_damper_is_named_and_radau_runs_it(four_bar):
    """With the damper, DOP853 is held by its stability (Hairer's test): a warning names the
    damper and the implicit method; Radau runs the same motion in a fraction of the steps and
    without the warning."""
    chain, _, q0 = four_bar
    damper = Spring(("ground", "rocker_tip"), damping=DAMPER)
    dyn = ChainDynamics(chain, ["crank_joint"], elements=[damper])
    t = np.linspace(0.0, 0.02, 5)
    with pytest.warns(FeederWarning) as caught:
        explicit = simulate(dyn, t, q0, np.zeros(3))
    (warning,) = [w for w in caught if "stiff" in str(w.message)]
    text = str(warning.message)
    assert "DOP853's steps" in text and "spring:ground-rocker_tip" in text
    assert "--method Radau" in text and "\n" not in text
    rate = float(re.search(r"at a rate of ≈ ([0-9.e+]+) /s", text).group(1))
    reference = DAMPER * _line_rate_terms(chain, explicit.q[0], ("ground", "rocker_tip"))
    assert rate == pytest.approx(reference, rel=0.1)  # Hairer's estimate, from one step
    with warnings.catch_warnings():
        warnings.simplefilter("error", FeederWarning)
        implicit = simulate(dyn, t, q0, np.zeros(3), method="Radau")
    assert implicit.steps * 10 < explicit.steps
    # both to their tolerance (rtol 1e-8) on a creep of ~1e-5 rad
    np.testing.assert_allclose(implicit.q, explicit.q, rtol=0.0, atol=1e-9)
    assert implicit.energy_error() <= 1e-9 * np.abs(implicit.work).max()


def test_the_progress_line_shows_on_a_terminal(four_bar, monkeypatch, capsys):
    """On a terminal, past its delay (none here), a run shows its simulated time, its steps
    against the cap and an estimate of the time left; off a terminal, or when not asked for,
    nothing."""
    chain, _, q0 = four_bar
    dyn = ChainDynamics(chain, ["crank_joint"])
    t = np.linspace(0.0, 0.5, 3)
    simulate(dyn, t, q0, np.zeros(3), progress=True)
    assert capsys.readouterr().err == ""  # pytest's stderr is no terminal
    monkeypatch.setattr(budget, "PROGRESS_DELAY", 0.0)
    monkeypatch.setattr(budget, "PROGRESS_INTERVAL", 0.0)
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    simulate(dyn, t, q0, np.zeros(3))
    assert capsys.readouterr().err == ""
    simulate(dyn, t, q0, np.zeros(3), progress=True)
    err = capsys.readouterr().err
    assert "simulate: 100%" in err and "0.5 of 0.5 s" in err and "left" in err
    assert re.search(r"\d+ of at most 200000 steps", err) and "samples: 100%" in err


def test_the_time_left_is_to_the_step_cap_when_it_comes_first():
    """Half the steps of the cap for a tenth of the span in 10 s: 10 s more, to the cap."""
    line = budget.Progress(0.0, 10.0, enabled=False)
    text = line._text(1.0, budget.MAX_STEPS // 2, 10.0)
    assert text.endswith("~00:10 left (the step cap comes first)")
    assert line._text(5.0, 10, 10.0).endswith("~00:10 left")


def test_a_run_at_the_step_cap_says_what_holds_its_steps(four_bar, monkeypatch):
    """At the cap (made small here): a stiff run says so, with its element and Radau; a run
    made fast by an element (a cylinder's bore of 80 mm typed as 80 m: 5 027 m² at 12 MPa on
    the 0.4 kg four-bar, which Radau does not help: measured 35 686 Radau steps against
    DOP853's 1 443 for 0.1 ms) names that element and asks to check it; a plain one neither."""
    chain, _, q0 = four_bar
    monkeypatch.setattr(budget, "MAX_STEPS", 200)
    elements = {
        "stiff": [Spring(("ground", "rocker_tip"), damping=DAMPER)],
        "fast": [Cylinder(("ground", "rocker_tip"), bore=80.0, rod=45.0, pressure=12e6)],
        "plain": [],
    }
    messages = {}
    for key, chosen in elements.items():
        dyn = ChainDynamics(chain, ["crank_joint"], elements=chosen)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", FeederWarning)  # the stiff run's own warning
            with pytest.raises(IntegrationError, match="cap of 200 integration steps") as caught:
                simulate(dyn, np.array([0.0, 1e3]), q0, np.zeros(3))
        messages[key] = str(caught.value)
    assert "held by stiffness from t = " in messages["stiff"]
    assert "from spring:ground-rocker_tip" in messages["stiff"] and "Radau" in messages["stiff"]
    fast = messages["fast"]
    assert "its fastest force element there, cylinder:ground-rocker_tip" in fast
    assert "check that element's values and units" in fast and "Radau" not in fast
    assert re.fullmatch(r"the run stopped .*; end it by t = [0-9.e-]+ s", messages["plain"])
