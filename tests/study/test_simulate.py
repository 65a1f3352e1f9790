"""A user's mechanism run forward (feeder.study.simulate): the side-file's and an extra file's
force elements act, and the table says what the run did."""

from __future__ import annotations

import numpy as np
import pytest

from feeder.exceptions import InputError
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
    assert np.all(columns["joint_spring:rocker_joint_force"] * columns["v_rocker_joint"] >= 0.0)
    assert "force elements: joint_spring:rocker_joint" in simulation.summary()


def test_bad_settings_are_refused():
    with pytest.raises(InputError, match="duration must be > 0"):
        simulate_mechanism(FOUR_BAR / "closures.toml", 0.0)
    with pytest.raises(InputError, match="samples must be"):
        simulate_mechanism(FOUR_BAR / "closures.toml", 1.0, samples=1)
    with pytest.raises(InputError, match="method must be one of"):
        simulate_mechanism(FOUR_BAR / "closures.toml", 1.0, method="Euler")
