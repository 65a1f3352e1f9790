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
