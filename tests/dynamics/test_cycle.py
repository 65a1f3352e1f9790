"""The one-call cycle dynamics: the cycle.csv contract, peaks and summary, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder.dynamics.cycle import FORWARD_TOLERANCE, CycleDynamics, cycle_dynamics
from feeder.exceptions import ElevationError, ForwardDivergenceError, InputError
from feeder.motion.cycle import feeding_cycle
from feeder.motion.laws import CycleSpec
from feeder.paper.lagrange import lagrange_loads
from feeder.study.columns import kinematic_columns
from feeder.study.csv import read_csv, write_csv
from feeder.study.cycle_study import CycleStudy

from ..dynamics.cases import ELEVATIONS_DEG, cycle_result, device

CONTRACT = (
    "t stage payload q_phi1 q_r2 q_phi3 q_phi4 v_phi1 v_r2 v_phi3 v_phi4 a_phi1 a_r2 a_phi3 "
    "a_phi4 projectile_x projectile_y projectile_z projectile_speed projectile_axis_x "
    "projectile_axis_y projectile_axis_z transmission_angle_deg closure_residual piston_force "
    "forearm_torque cylinder_frame_force piston_arm_force arm_frame_force forearm_joint_force "
    "forearm_joint_moment forward_q_phi3 forward_q_phi4 forward_closure_residual"
).split()
"""REFERENCE.md's cycle.csv columns, without the lagrange_* ones (the Lagrange issue's)."""

NORM_ROUNDING = 1e-15
"""Relative: a magnitude column vs the norm of its three component columns (a few ulps)."""


def _study(d: CycleDynamics) -> CycleStudy:
    """The projectile feeder's cycle as the study presents it (the columns, peaks and summary
    of cycle.csv), with the hand-derived loads on the same motion."""
    k = d.kinematics
    return CycleStudy(device(), d, lagrange_loads(device().params, k.q, k.v, k.a, k.gripped))


def test_columns_hold_the_contract(result):
    columns = _study(result).columns()
    assert set(CONTRACT) <= set(columns)
    n = result.kinematics.t.size
    for name, values in columns.items():
        assert np.shape(values) == (n,), name
        assert np.all(np.isfinite(values)), name
    for name in ("cylinder_frame_force", "piston_arm_force", "forearm_joint_moment", "grip_force"):
        components = np.column_stack([columns[f"{name}_{axis}"] for axis in "xyz"])
        norm = np.linalg.norm(components, axis=1)
        assert np.allclose(norm, columns[name], rtol=NORM_ROUNDING, atol=0), name


def test_kinematic_columns_are_the_cycle_s(result):
    kinematics = kinematic_columns(feeding_cycle(device(), result.kinematics.elevation))
    columns = _study(result).columns()
    for name, values in kinematics.items():
        assert np.array_equal(columns[name], values), name


def test_columns_round_trip_through_the_csv_writer(tmp_path):
    columns = _study(cycle_result(ELEVATIONS_DEG[0])).columns()
    back = read_csv(write_csv(tmp_path / "cycle.csv", columns))
    assert list(back) == list(columns)
    assert all(np.array_equal(back[name], columns[name]) for name in columns)


def test_peaks_and_summary(result):
    study = _study(result)
    columns = study.columns()
    t = columns["t"]
    for peak in study.peaks():
        values = columns[peak.name]
        k = int(np.argmax(np.abs(values)))
        assert peak.value == values[k] and peak.time == t[k]
    text = study.summary()
    for name in ("piston_force", "cylinder_cap_pressure", "forearm_torque", "arm_frame_force"):
        assert f"peak {name}" in text
    assert "bar" in text and "forward run" in text


def test_bad_elevation_is_refused():
    with pytest.raises(ElevationError, match="outside"):
        cycle_dynamics(device(), math.radians(75.0))
    with pytest.raises(InputError, match="finite"):
        cycle_dynamics(device(), float("nan"))


def test_forward_run_that_drifts_is_refused():
    """The force-driven forward run amplifies a coarse step's error: at 50 Hz it passes an end
    stop, at 250 Hz (ε = 30°, where it stays inside the end stops) it ends far from the
    prescribed motion (~5e-4 rad, the rate table of feeder.dynamics.cycle), refused with the
    figures; the kinematics, loads and reactions alone need no minimum rate."""
    slow = CycleSpec(rate=50.0)
    with pytest.raises(ForwardDivergenceError, match="forward run"):
        cycle_dynamics(device(), 0.0, slow)
    with pytest.raises(ForwardDivergenceError, match=r"drifted .*\(tolerance 0\.0001 rad"):
        cycle_dynamics(device(), math.radians(30.0), CycleSpec(rate=250.0))
    result = cycle_dynamics(device(), 0.0, slow, forward=False)
    assert result.forward is None and result.kinematics.t.size == 201
    assert np.all(np.isfinite(result.loads.piston_force))
    short = cycle_dynamics(device(), 0.0, CycleSpec(durations=(0.5, 0.5, 1.0), rate=500.0))
    assert max(short.tracking_error()) <= FORWARD_TOLERANCE


def test_cycle_without_forward_run():
    full = cycle_result(ELEVATIONS_DEG[1])
    spec = full.kinematics.spec
    bare = cycle_dynamics(device(), full.kinematics.elevation, spec, forward=False)
    bare_study, full_study = _study(bare), _study(full)
    columns, full_columns = bare_study.columns(), full_study.columns()
    forward = {"forward_q_phi3", "forward_q_phi4", "forward_closure_residual"}
    assert set(full_columns) - set(columns) == forward
    for name, values in columns.items():
        assert np.array_equal(values, full_columns[name]), name
    assert bare_study.peaks() == full_study.peaks()
    assert "forward run (force rule): skipped" in bare_study.summary()
    with pytest.raises(InputError, match="forward=False"):
        bare.tracking_error()
    with pytest.raises(InputError, match="forward=False"):
        bare.closure_residual()


def test_no_cylinder_frame_moment_column(result):
    """Its constraint moment is zero by construction (planar cylinder, λz = 0): no column, no
    peak (test_reactions checks that it is zero)."""
    study = _study(result)
    assert not any(name.startswith("cylinder_frame_moment") for name in study.columns())
    assert "cylinder_frame_moment" not in {peak.name for peak in study.peaks()}


def test_progress_bar_is_quiet_off_a_terminal(capsys):
    """progress=True shows the bar only on a terminal: pytest's captured stderr is not one."""
    cycle_dynamics(device(), 0.0, CycleSpec(rate=100.0), progress=True, forward=False)
    assert capsys.readouterr().err == ""
