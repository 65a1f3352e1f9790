"""``feeder simulate`` with actuated joints under control (feeder.study.simulate with
``[[control]]`` tables or a ``--control`` file): the four-bar started on its reference follows
it, the table gains the controller's columns, the summary its errors and saturation."""

from __future__ import annotations

import numpy as np
import pytest

from feeder.chain import Closure, load_closed_chain
from feeder.chain.assembly.partition import Partition
from feeder.exceptions import InputError
from feeder.study.simulate import simulate_mechanism

from ..conftest import REPO, four_bar_file

FOUR_BAR = REPO / "examples" / "four_bar"


def start() -> str:
    """The four-bar's pose and rates at its motion table's first sample (the crank at 0.698 rad,
    2π rad/s): its closed pose written whole, the nearest closed pose to itself."""
    chain = load_closed_chain(
        FOUR_BAR / "four_bar.urdf", [Closure("coupler_tip", "rocker_tip", "revolute")]
    )
    q = Partition(chain, ["crank_joint"]).assemble(np.array([0.6981317007977318, -0.35, 1.0]))
    joints = ", ".join(f"{chain.model.names[j]} = {float(q[j - 1])!r}" for j in (1, 2, 3))
    return f"pose = {{{joints}}}\nrates = {{crank_joint = 6.283185307179586}}\n"


def write(tmp_path, control: str):
    return four_bar_file(tmp_path, control, mechanism=start())


CONTROL = (
    f'[[control]]\njoint = "crank_joint"\nreference = "{(FOUR_BAR / "motion.csv").as_posix()}"\n'
    "omega = 20.0\n"
)


def test_the_four_bar_on_its_reference_follows_it(tmp_path):
    simulation = simulate_mechanism(write(tmp_path, CONTROL), 1.0, samples=101, rtol=1e-10)
    columns = simulation.columns()
    # started on the reference: the error is the integrator's (rtol 1e-10 on ~7 rad; measured
    # 3e-11 rad)
    assert np.abs(columns["error_crank_joint"]).max() <= 1e-8
    np.testing.assert_allclose(
        columns["q_crank_joint"] + columns["error_crank_joint"], columns["q_ref_crank_joint"],
        rtol=0.0, atol=1e-15 * 8,
    )  # fmt: skip
    # the drive is the controller's command, read back by the inverse dynamics of the run
    np.testing.assert_allclose(
        columns["tau_crank_joint"], columns["command_crank_joint"], rtol=0.0, atol=1e-10
    )
    assert not columns["saturated_crank_joint"].any()
    summary = simulation.summary()
    assert "control of 'crank_joint': peak error" in summary and "saturated 0 s" in summary
    assert "not driven" not in summary and "peak actuator load crank_joint" in summary


def test_a_control_file_replaces_the_mechanism_file_s_tables(tmp_path):
    """A --control file with a force limit below the drive's need: the drive saturates at it,
    the flags and the time saturated say so."""
    path = write(tmp_path, CONTROL)
    control = tmp_path / "control.toml"
    control.write_text(CONTROL.replace("omega = 20.0", "kp = 400\nkd = 40\nforce_limit = 0.02"))
    simulation = simulate_mechanism(path, 0.5, samples=51, control=control)
    columns = simulation.columns()
    saturated = columns["saturated_crank_joint"] == 1.0
    assert saturated.any()
    np.testing.assert_allclose(np.abs(columns["tau_crank_joint"][saturated]), 0.02, rtol=1e-9)
    assert np.all(np.abs(columns["demand_crank_joint"][saturated]) > 0.02)
    assert np.all(np.abs(columns["tau_crank_joint"]) <= 0.02 * (1.0 + 1e-9))
    record = simulation.control
    assert record.time_saturated()[0] > 0.0
    assert f"saturated {record.time_saturated()[0]:.4g} s" in simulation.summary()


def test_a_cylinder_s_pressure_is_reported(tmp_path):
    """The slider-crank's slider driven as a cylinder (its piston area given), pulled 4 mm from
    its assembled 0.239 m (the crank at 0.6 rad, far from the dead centres): pressure = force /
    area."""
    crank = REPO / "examples" / "slider_crank"
    (tmp_path / "ref.csv").write_text(
        "t,q_slider_joint\n0,0.235\n0.5,0.235\n1,0.235\n", encoding="utf-8"
    )
    text = (crank / "closures.toml").read_text(encoding="utf-8")
    text = text.replace(
        'urdf = "slider_crank.urdf"', f'urdf = "{(crank / "slider_crank.urdf").as_posix()}"'
    )
    text = text.replace('actuated = ["crank_joint"]', 'actuated = ["slider_joint"]\n'
                        "pose = {crank_joint = 1.5}")  # fmt: skip
    text = text.replace('independent = ["crank_joint"]', 'independent = ["slider_joint"]')
    path = tmp_path / "closures.toml"
    path.write_text(
        text + '\n[[control]]\njoint = "slider_joint"\nreference = "ref.csv"\nomega = 10\n'
        "area = 2e-4\n",
        encoding="utf-8",
    )
    simulation = simulate_mechanism(path, 0.2, samples=11)
    columns = simulation.columns()
    np.testing.assert_allclose(
        columns["pressure_slider_joint"] * 2e-4, columns["tau_slider_joint"], rtol=1e-9, atol=1e-12
    )
    assert "peak pressure" in simulation.summary()


def test_a_run_beyond_the_reference_is_refused(tmp_path):
    with pytest.raises(InputError, match=r"covers t = 0 … 1 s, the run 0 … 2 s"):
        simulate_mechanism(write(tmp_path, CONTROL), 2.0, samples=11)


def test_on_a_terrain_ride_the_controlled_crank_still_follows_its_table(tmp_path):
    """The four-bar on a rolling, heaving hull ([base]: a 5° slope and a terrain ride), started
    on its reference: the law takes the base's terms from the run's own equations, so the
    error stays at the integrator's tolerance, and the energy balance of the absolute motion
    closes with the drive's work and the base's."""
    base = '\n[base]\nroll_deg = 5.0\n\n[[base.profile]]\ntype = "terrain"\nheave = 0.04\n'
    simulation = simulate_mechanism(write(tmp_path, CONTROL + base), 0.5, samples=51, rtol=1e-10)
    columns = simulation.columns()
    assert np.abs(columns["base_work"]).max() > 1e-4  # the ride does work on the mechanism
    # as on a base at rest: rtol 1e-10 on angles of ~4 rad (measured 3e-11 rad)
    assert np.abs(columns["error_crank_joint"]).max() <= 1e-8
    # energies of ~0.3 J at rtol 1e-10: the balance to 1e-8 J with room (measured 2e-11 J)
    assert np.abs(columns["energy_balance"]).max() <= 1e-8
