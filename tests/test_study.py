"""The standard study: Pinocchio and the Lagrange equations side by side, written to disk."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder import (
    CycleSpec,
    ElevationError,
    InputError,
    cycle_dynamics,
    read_csv,
    run_cycle_study,
    write_cycle_study,
)
from feeder.study import elevation_sweep

LOAD_AGREEMENT = 1e-8
"""Relative agreement of the two computations of the actuator loads (issue 4)."""


@pytest.fixture(scope="module")
def study(feeder):
    return run_cycle_study(feeder, math.radians(10.0), CycleSpec(rate=500.0))


def test_lagrange_and_pinocchio_agree_in_the_table(study):
    columns = study.columns()
    for name in ("piston_force", "forearm_torque"):
        scale = np.abs(columns[name]).max()
        np.testing.assert_allclose(
            columns[f"lagrange_{name}"], columns[name], atol=LOAD_AGREEMENT * scale
        )
    force, torque = study.cross_check()
    assert force <= LOAD_AGREEMENT * np.abs(columns["piston_force"]).max()
    assert torque <= LOAD_AGREEMENT * np.abs(columns["forearm_torque"]).max()


def test_multipliers_are_the_pin_force_on_the_arm(study):
    """λ of the closure equations f1 (x), f2 (y) is the force of the piston on the arm."""
    columns = study.columns()
    scale = columns["piston_arm_force"].max()
    np.testing.assert_allclose(
        columns["lagrange_lambda1"], columns["piston_arm_force_x"], atol=LOAD_AGREEMENT * scale
    )
    np.testing.assert_allclose(
        columns["lagrange_lambda2"], columns["piston_arm_force_y"], atol=LOAD_AGREEMENT * scale
    )


def test_written_table_round_trips(study, feeder, tmp_path):
    paths = write_cycle_study(study, feeder, tmp_path)
    table = read_csv(paths[0])
    for name, values in study.columns().items():
        np.testing.assert_array_equal(table[name], values, err_msg=name)
    assert all(path.stat().st_size > 10_000 for path in paths[1:])


def test_sweep_peaks_are_the_cycles_peaks(feeder, capsys):
    """The sweep needs no forward run (so no minimum rate), and is quiet off a terminal."""
    spec = CycleSpec(rate=100.0)
    elevations = np.radians([-4.0, 50.0])
    sweep = elevation_sweep(feeder, elevations, spec)
    assert capsys.readouterr().err == ""
    for k, elevation in enumerate(elevations):
        for peak in cycle_dynamics(feeder, elevation, spec, forward=False).peaks():
            assert sweep.peaks[peak.name][k] == peak.value
            assert sweep.times[peak.name][k] == peak.time
            assert sweep.units[peak.name] == peak.unit


@pytest.mark.parametrize("bad", [[], np.zeros((2, 2)), 0.1, [0.1, float("nan")]])
def test_sweep_needs_a_list_of_finite_elevations(feeder, bad):
    with pytest.raises(InputError, match="elevations"):
        elevation_sweep(feeder, bad)


def test_sweep_checks_every_elevation_first(feeder):
    with pytest.raises(ElevationError, match="80.000°"):
        elevation_sweep(feeder, np.radians([10.0, 80.0]))
