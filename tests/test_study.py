"""The standard study: Pinocchio and the Lagrange equations side by side, written to disk."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder import CycleSpec, read_csv, run_cycle_study, write_cycle_study

LOAD_AGREEMENT = 1e-8
"""Relative agreement of the two computations of the actuator loads (issue 4)."""


@pytest.fixture(scope="module")
def study(feeder):
    return run_cycle_study(feeder, math.radians(10.0), CycleSpec(rate=500.0))


def test_lagrange_and_pinocchio_agree_in_the_table(study):
    columns = study.columns()
    for name in ("piston_force", "forearm_torque"):
        scale = np.abs(columns[name]).max()
        np.testing.assert_allclose(columns[f"lagrange_{name}"], columns[name],
                                   atol=LOAD_AGREEMENT * scale)
    force, torque = study.cross_check()
    assert force <= LOAD_AGREEMENT * np.abs(columns["piston_force"]).max()
    assert torque <= LOAD_AGREEMENT * np.abs(columns["forearm_torque"]).max()


def test_multipliers_are_the_pin_force_on_the_arm(study):
    """λ of the closure equations f1 (x), f2 (y) is the force of the piston on the arm."""
    columns = study.columns()
    scale = columns["piston_arm_force"].max()
    np.testing.assert_allclose(columns["lagrange_lambda1"], columns["piston_arm_force_x"],
                               atol=LOAD_AGREEMENT * scale)
    np.testing.assert_allclose(columns["lagrange_lambda2"], columns["piston_arm_force_y"],
                               atol=LOAD_AGREEMENT * scale)


def test_written_table_round_trips(study, feeder, tmp_path):
    paths = write_cycle_study(study, feeder, tmp_path)
    table = read_csv(paths[0])
    for name, values in study.columns().items():
        np.testing.assert_array_equal(table[name], values, err_msg=name)
    assert all(path.stat().st_size > 10_000 for path in paths[1:])
