"""A user's mechanism run forward (feeder.study.simulate): the side-file's and an extra file's
force elements act, and the table says what the run did."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from feeder.chain import ChainDynamics, simulate
from feeder.exceptions import FeederWarning, InputError
from feeder.study.analyze import mount_mechanism
from feeder.study.simulate import simulate_mechanism

from ..conftest import REPO

FOUR_BAR = REPO / "examples" / "four_bar"


def test_a_damped_four_bar_loses_the_energy_its_damper_takes(tmp_path):
    """The four-bar released under gravity with a joint damper from a --forces file: the energy
    falls by the damper's (negative) work, to the integrator's tolerance."""
    forces = tmp_path / "damper.toml"
    forces.write_text(
        '[[force]]\ntype = "joint_spring"\njoint = "rocker_joint"\ndamping = 0.01\n',
        encoding="utf-8",
    )
    simulation = simulate_mechanism(FOUR_BAR / "closures.toml", 1.0, forces=forces, samples=101)
    columns = simulation.columns()
    assert columns["work"][-1] < -1e-3  # the damper took energy out
    # DOP853 at rtol 1e-8: the balance holds to ~1e-9 J (measured); the work is ~1e-2 J
    assert np.abs(columns["energy_balance"]).max() <= 1e-7
    assert np.all(columns["joint_spring_rocker_joint_force"] * columns["v_rocker_joint"] >= 0.0)
    assert "force elements: joint_spring:rocker_joint" in simulation.summary()


def test_bad_settings_are_refused():
    with pytest.raises(InputError, match="duration must be > 0"):
        simulate_mechanism(FOUR_BAR / "closures.toml", 0.0)
    with pytest.raises(InputError, match="samples must be"):
        simulate_mechanism(FOUR_BAR / "closures.toml", 1.0, samples=1)
    with pytest.raises(InputError, match="method must be one of"):
        simulate_mechanism(FOUR_BAR / "closures.toml", 1.0, method="Euler")
    with pytest.raises(InputError, match="rates must map joint names"):
        simulate_mechanism(FOUR_BAR / "closures.toml", 1.0, rates=[("crank_joint", 1.0)])
    with pytest.raises(InputError, match="duration 5e-324 s is too short for 1001 distinct"):
        simulate_mechanism(FOUR_BAR / "closures.toml", 5e-324)  # once "t must be increasing"


def test_gravity_assumed_is_said_and_gravity_doing_no_work_is_warned(tmp_path):
    """Without ``gravity`` the four-bar (moving in the x–y plane) gets the URDF's −z, whose
    generalized force is exactly zero: the summary says it was assumed and a warning says it
    does no work. The shipped file's −y does work: no warning, the summary says where from."""
    text = (FOUR_BAR / "closures.toml").read_text()
    lines = [line for line in text.splitlines() if not line.startswith("gravity")]
    (tmp_path / "closures.toml").write_text("\n".join(lines) + "\n")
    with pytest.warns(
        FeederWarning, match=r"gravity \[0\.0, 0\.0, -9\.81\] m/s² \(assumed.*does no work"
    ):
        simulation = simulate_mechanism(
            tmp_path / "closures.toml", 0.1, model=FOUR_BAR / "four_bar.urdf", samples=3
        )
    assert "gravity [0.0, 0.0, -9.81] m/s² (assumed" in simulation.summary()
    with warnings.catch_warnings():
        warnings.simplefilter("error", FeederWarning)
        simulation = simulate_mechanism(FOUR_BAR / "closures.toml", 0.1, samples=3)
    assert "gravity [0.0, -9.81, 0.0] m/s² (from the mechanism file)" in simulation.summary()


def test_a_free_four_bar_with_long_steps_and_coarse_outputs_runs_correctly():
    """Issue 19: with a 1 s step over 2 s the free four-bar once returned q ≈ 1e106 and a NaN
    energy without an error. The step limit is now an upper bound of the adaptive step: the run
    with max_step = 1 s and three outputs is the run without a limit, to the integrator's
    tolerance (1e-8 relative on ~1 rad: 1e-6 rad leaves room for the dense output)."""
    spec, chain, _, _, assembled = mount_mechanism(FOUR_BAR / "closures.toml", None, None)
    dyn = ChainDynamics(chain, spec.actuated)
    t = np.array([0.0, 1.0, 2.0])
    coarse = simulate(dyn, t, assembled, np.zeros(3), max_step=1.0)
    free = simulate(dyn, t, assembled, np.zeros(3))
    assert np.all(np.isfinite(coarse.q)) and np.all(np.isfinite(coarse.energy))
    np.testing.assert_allclose(coarse.q, free.q, rtol=0.0, atol=1e-6)
    assert coarse.energy_error() <= 1e-7  # [J] of ~0.1 J swings (tests/chain/dynamics ENERGY)


def test_a_run_that_does_not_move_says_so(tmp_path):
    """Gravity along −z on the four-bar moving in the x–y plane: it stays where it is released
    (to ~1e-12 rad), and the summary says so, with the balance in joules only — once "relative 1"
    (its balance against a kinetic energy of 1e-22 J, both round-off)."""
    text = (FOUR_BAR / "closures.toml").read_text()
    lines = [line for line in text.splitlines() if not line.startswith("gravity")]
    (tmp_path / "closures.toml").write_text("\n".join(lines) + "\n")
    with pytest.warns(FeederWarning, match="does no work"):
        simulation = simulate_mechanism(
            tmp_path / "closures.toml", 0.5, model=FOUR_BAR / "four_bar.urdf", samples=11
        )
    line = simulation.energy_line()
    assert "the mechanism stays at rest" in line and "no energy to compare" in line
    assert "of the energy the run moves" not in line and line in simulation.summary()


def test_the_energy_balance_is_measured_against_the_energy_the_run_moves():
    """The free four-bar swings: its balance is given relative to the largest of its kinetic
    energy, its |work| and its potential energy's change (here the swing's ~6.5e-3 J; once the
    kinetic energy alone, which is zero for a run held still while its potential changes)."""
    simulation = simulate_mechanism(FOUR_BAR / "closures.toml", 0.05, samples=11)
    run = simulation.run
    potential = run.energy - run.kinetic
    scale = max(run.kinetic.max(), np.abs(run.work).max(), np.ptp(potential))
    line = simulation.energy_line()
    ratio = float(line.split(" J, ")[1].split(" of the energy the run moves")[0])
    assert ratio == pytest.approx(run.energy_error() / scale, rel=0.05)  # printed to 2 digits
    assert f"|change of potential energy| {np.ptp(potential):.4g} J" in line


def test_more_samples_than_the_memory_allows_are_refused_before_the_run(monkeypatch):
    """10¹² samples once meant an array of 8 TB (a MemoryError), 10⁷ a run of hours: refused
    with the cap before any array is made."""
    import feeder.study.simulate as study
    from feeder.chain.dynamics import budget

    monkeypatch.setattr(study, "simulate", lambda *args, **kw: pytest.fail("the run started"))
    cap = budget.SAMPLE_MEMORY // (budget.SAMPLE_BYTES * 3)  # the four-bar's 3 coordinates
    for samples in (10**7, 10**12):
        with pytest.raises(InputError, match=rf"{samples} output samples \(samples\) are more "
                           rf"than the {cap} .* ask for at most {cap}"):  # fmt: skip
            simulate_mechanism(FOUR_BAR / "closures.toml", 1.0, samples=samples)


@pytest.mark.parametrize(
    "name", ["four_bar/closures.toml", "andrews_squeezer/squeezer.toml",
             "slider_crank/closures.toml", "bricard/bricard.toml"],
)  # fmt: skip
def test_the_examples_are_not_found_stiff(name):
    """Their steps follow their motion (Hairer's h λ at most 3.3 over them): no warning."""
    duration = 0.03 if "squeezer" in name else 0.5
    with warnings.catch_warnings():
        warnings.simplefilter("error", FeederWarning)
        simulate_mechanism(REPO / "examples" / name, duration, samples=3)


PENDULUM_URDF = """<?xml version="1.0"?>
<robot name="pendulum">
  <link name="ground"/>
  <link name="rod">
    <inertial><origin xyz="0.5 0 0" rpy="0 0 0"/><mass value="2.0"/>
      <inertia ixx="1e-4" ixy="0" ixz="0" iyy="0.1666666666666667" iyz="0"
               izz="0.1666666666666667"/></inertial>
  </link>
  <joint name="hinge" type="continuous"><origin xyz="0 0 0" rpy="0 0 0"/>
    <parent link="ground"/><child link="rod"/><axis xyz="0 0 1"/></joint>
  <link name="tip"/>
  <joint name="tip_joint" type="fixed"><origin xyz="1 0 0" rpy="0 0 0"/>
    <parent link="rod"/><child link="tip"/></joint>
</robot>
"""
"""A compound pendulum: a 1 m rod of 2 kg (I = m L²/12 about its centre, m L²/3 = 2/3 kg·m²
about the hinge) hung at one end, horizontal at q = 0, swinging in the x–y plane."""

HINGE_INERTIA, MASS, CENTRE, G = 2.0 / 3.0, 2.0, 0.5, 9.81


@pytest.fixture
def pendulum(tmp_path):
    """The pendulum's mechanism file: nothing actuated, started at 1.5 rad/s."""
    (tmp_path / "pendulum.urdf").write_text(PENDULUM_URDF)
    path = tmp_path / "pendulum.toml"
    path.write_text(
        '[mechanism]\nurdf = "pendulum.urdf"\nactuated = []\nindependent = ["hinge"]\n'
        "gravity = [0.0, -9.81, 0.0]\nrates = {hinge = 1.5}\n\n"
        '[[point]]\nname = "tip"\nframe = "tip"\n\n'
        '[[point]]\nname = "middle"\nbody = "rod"\noffset = [0.5, 0.0, 0.0]\n'
    )
    return path


def test_a_passive_pendulum_keeps_the_energy_of_its_initial_rate(pendulum):
    """No actuated joint: it runs from its file's rate, its energy ½ I ω² + m g y_G (closed form,
    from the table's angle and rate) stays ½ I ω₀² to the integrator's tolerance, and the
    summary says there is no closure instead of a velocity gain of 0."""
    simulation = simulate_mechanism(pendulum, 1.0, samples=101)
    cols = simulation.columns()
    energy = 0.5 * HINGE_INERTIA * cols["v_hinge"] ** 2 + MASS * G * CENTRE * np.sin(
        cols["q_hinge"]
    )
    start = 0.5 * HINGE_INERTIA * 1.5**2
    assert cols["v_hinge"][0] == 1.5 and simulation.run.kinetic[0] == pytest.approx(start)
    # DOP853 at rtol 1e-8 over a swing of ~10 J: ~2e-7 J measured
    np.testing.assert_allclose(energy, start, rtol=0.0, atol=1e-6)
    assert np.ptp(cols["q_hinge"]) > 1.0  # it swings
    summary = simulation.summary()
    assert "no velocity gain: an open tree, no closure" in summary
    assert "velocity gain 0" not in summary and "actuated joints" not in summary
    assert "used as given (an open tree: no closure to meet)" in summary
    assert "forward run: 1 s at the initial rates above" in summary


def test_a_rate_given_in_the_call_overrides_the_file_s(pendulum):
    simulation = simulate_mechanism(pendulum, 0.01, samples=3, rates={"hinge": -0.5})
    assert simulation.start.given == {"hinge": -0.5}
    assert simulation.run.kinetic[0] == pytest.approx(0.5 * HINGE_INERTIA * 0.25)


def test_rates_that_contradict_the_closure_are_warned_and_summarised():
    with pytest.warns(FeederWarning, match="contradict the closure: projected"):
        simulation = simulate_mechanism(
            FOUR_BAR / "closures.toml", 0.01, samples=3,
            rates={"crank_joint": 3.0, "rocker_joint": 1.0},
        )  # fmt: skip
    start = simulation.start
    np.testing.assert_allclose(simulation.run.v[0], start.v, rtol=0.0, atol=1e-12)
    assert "they contradict the closure: projected onto it" in simulation.summary()


def test_a_joint_given_a_rate_must_be_the_model_s(pendulum):
    text = pendulum.read_text().replace("rates = {hinge", "rates = {hing")
    pendulum.write_text(text)
    with pytest.raises(InputError, match=r"rates: no joint 'hing' .*did you mean 'hinge'\?"):
        simulate_mechanism(pendulum, 0.01, samples=3)


def test_the_pendulum_s_points_move_as_by_hand(pendulum):
    """The tip (a frame) and the middle of the rod (its body at an offset) at radius r from the
    hinge: r (cos θ, sin θ), r ω (−sin θ, cos θ) and r (−ω² cos θ − α sin θ, −ω² sin θ +
    α cos θ), with α = −m g c cos θ / I (the pendulum's equation, by hand) and θ, ω from the
    run's table."""
    cols = simulate_mechanism(pendulum, 1.0, samples=101).columns()
    theta, omega = cols["q_hinge"], cols["v_hinge"]
    alpha = -MASS * G * CENTRE * np.cos(theta) / HINGE_INERTIA
    c, s = np.cos(theta), np.sin(theta)
    for name, r in (("tip", 1.0), ("middle", 0.5)):
        expected = {
            "": (r * c, r * s),
            "_velocity": (-r * omega * s, r * omega * c),
            "_acceleration": (
                r * (-(omega**2) * c - alpha * s),
                r * (-(omega**2) * s + alpha * c),
            ),
        }
        for what, (x, y) in expected.items():
            # the table's θ, ω to the integrator's tolerance; α the closed form's to round-off
            np.testing.assert_allclose(cols[f"point_{name}{what}_x"], x, rtol=0.0, atol=1e-9)
            np.testing.assert_allclose(cols[f"point_{name}{what}_y"], y, rtol=0.0, atol=1e-9)
            assert np.abs(cols[f"point_{name}{what}_z"]).max() == 0.0
