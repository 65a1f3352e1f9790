"""The one-call cycle dynamics: the cycle.csv contract, peaks and summary, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder.cycle import feeding_cycle
from feeder.cycle_dynamics import cycle_dynamics
from feeder.exceptions import ElevationError, InputError
from feeder.results import read_csv, write_csv

from ._dynamics_cases import ELEVATIONS_DEG, cycle_result, device

CONTRACT = (
    "t stage payload q_phi1 q_r2 q_phi3 q_phi4 v_phi1 v_r2 v_phi3 v_phi4 a_phi1 a_r2 a_phi3 "
    "a_phi4 projectile_x projectile_y projectile_z projectile_speed projectile_axis_x "
    "projectile_axis_y projectile_axis_z transmission_angle_deg closure_residual piston_force "
    "forearm_torque cylinder_frame_force piston_arm_force arm_frame_force forearm_joint_force "
    "forearm_joint_moment forward_q_phi3 forward_q_phi4 forward_closure_residual"
).split()
"""REFERENCE.md's cycle.csv columns, without the lagrange_* ones (the Lagrange issue's)."""


@pytest.fixture(scope="session", params=ELEVATIONS_DEG, ids=lambda e: f"eps{e:g}")
def result(request):
    return cycle_result(request.param)


def test_columns_hold_the_contract(result):
    columns = result.columns()
    assert set(CONTRACT) <= set(columns)
    n = result.kinematics.t.size
    for name, values in columns.items():
        assert np.shape(values) == (n,), name
        assert np.all(np.isfinite(values)), name
    for name in ("cylinder_frame_force", "piston_arm_force", "forearm_joint_moment", "grip_force"):
        components = np.column_stack([columns[f"{name}_{axis}"] for axis in "xyz"])
        assert np.allclose(np.linalg.norm(components, axis=1), columns[name], rtol=1e-15, atol=0)


def test_kinematic_columns_are_the_cycle_s(result):
    kinematics = feeding_cycle(device(), result.kinematics.elevation).columns()
    columns = result.columns()
    for name, values in kinematics.items():
        assert np.array_equal(columns[name], values), name


def test_columns_round_trip_through_the_csv_writer(tmp_path):
    columns = cycle_result(ELEVATIONS_DEG[0]).columns()
    back = read_csv(write_csv(tmp_path / "cycle.csv", columns))
    assert list(back) == list(columns)
    assert all(np.array_equal(back[name], columns[name]) for name in columns)


def test_peaks_and_summary(result):
    columns = result.columns()
    t = columns["t"]
    for peak in result.peaks():
        values = columns[peak.name]
        k = int(np.argmax(np.abs(values)))
        assert peak.value == values[k] and peak.time == t[k]
    text = result.summary()
    for name in ("piston_force", "cylinder_cap_pressure", "forearm_torque", "arm_frame_force"):
        assert f"peak {name}" in text
    assert "bar" in text and "forward run" in text


def test_bad_elevation_is_refused():
    with pytest.raises(ElevationError, match="outside"):
        cycle_dynamics(device(), math.radians(75.0))
    with pytest.raises(InputError, match="finite"):
        cycle_dynamics(device(), float("nan"))
