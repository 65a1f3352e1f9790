"""The standard study (feeder.study.cycle_study): Pinocchio and the Lagrange equations side by
side, written to disk by feeder.outputs."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder.motion.laws import CycleSpec
from feeder.outputs import write_cycle_outputs
from feeder.paper.lagrange import LagrangeLoads
from feeder.study.csv import read_csv
from feeder.study.cycle_study import CycleStudy, run_cycle_study
from feeder.study.peaks import cycle_peaks

LOAD_AGREEMENT = 1e-8
"""Relative agreement of the two computations of the actuator loads (issue 4)."""
MIN_FIGURE_BYTES = 10_000
"""A written figure (960 × 504 PNG with curves) is far larger; a blank canvas is ~3 kB."""
STUDY_ELEVATION = math.radians(10.0)
STUDY_SPEC = CycleSpec(rate=500.0)
"""500 Hz: the slowest rate whose forward run tracks within its tolerance (feeder.dynamics.cycle),
so the study stays quick."""


@pytest.fixture(scope="module")
def study(feeder):
    return run_cycle_study(feeder, STUDY_ELEVATION, STUDY_SPEC)


def test_study_holds_both_computations_of_one_cycle(feeder, study):
    assert isinstance(study, CycleStudy)
    assert study.feeder is feeder
    assert isinstance(study.lagrange, LagrangeLoads)
    assert study.dynamics.forward is not None
    samples = study.dynamics.kinematics.t.size
    assert study.lagrange.tau.shape == (samples, 4)
    assert study.peaks() == cycle_peaks(study.dynamics)


def test_lagrange_and_pinocchio_agree_in_the_table(study):
    columns = study.columns()
    for name in ("piston_force", "forearm_torque"):
        scale = np.abs(columns[name]).max()
        np.testing.assert_allclose(
            columns[f"lagrange_{name}"], columns[name], rtol=0, atol=LOAD_AGREEMENT * scale
        )
    force, torque = study.cross_check()
    assert force <= LOAD_AGREEMENT * np.abs(columns["piston_force"]).max()
    assert torque <= LOAD_AGREEMENT * np.abs(columns["forearm_torque"]).max()


def test_multipliers_are_the_pin_force_on_the_arm(study):
    """λ of the closure equations f1 (x), f2 (y) is the force of the piston on the arm."""
    columns = study.columns()
    scale = columns["piston_arm_force"].max()
    np.testing.assert_allclose(
        columns["lagrange_lambda1"],
        columns["piston_arm_force_x"],
        rtol=0,
        atol=LOAD_AGREEMENT * scale,
    )
    np.testing.assert_allclose(
        columns["lagrange_lambda2"],
        columns["piston_arm_force_y"],
        rtol=0,
        atol=LOAD_AGREEMENT * scale,
    )


def test_summary_reports_every_peak_and_the_cross_check(study):
    text = study.summary()
    for peak in study.peaks():
        assert f"peak {peak.name} " in text
    assert "Lagrange equations vs Pinocchio" in text
    assert "forward run (force rule): |Δφ3|" in text


def test_written_table_round_trips(study, tmp_path):
    paths = write_cycle_outputs(study, tmp_path)
    assert paths[0] == tmp_path / "cycle.csv"
    table = read_csv(paths[0])
    assert list(table) == list(study.columns())
    for name, values in study.columns().items():
        np.testing.assert_array_equal(table[name], values, err_msg=name)
    assert len(paths) > 1
    assert all(path.stat().st_size > MIN_FIGURE_BYTES for path in paths[1:])
