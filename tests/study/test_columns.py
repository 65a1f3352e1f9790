"""The ``cycle.csv`` contract (feeder.study.columns): the columns a study fills are COLUMNS, in
file order; the kinematic ones are KINEMATIC_COLUMNS."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder.motion.laws import CycleSpec
from feeder.study.columns import COLUMNS, KINEMATIC_COLUMNS, cycle_columns, kinematic_columns
from feeder.study.cycle_study import run_cycle_study

NAMES = [column.name for column in COLUMNS]
FORWARD_PREFIX = "forward_"
CONTROLLED_PREFIX = "controlled_"
LAGRANGE_COLUMNS = (
    "lagrange_piston_force",
    "lagrange_forearm_torque",
    "lagrange_lambda1",
    "lagrange_lambda2",
)
"""The hand-derived equations' columns that docs/REFERENCE.md documents."""
STUDY_SPEC = CycleSpec(rate=500.0)
"""The forward run needs ≥ 500 Hz for the default stages (feeder.dynamics.cycle)."""


@pytest.fixture(scope="module", params=[True, False], ids=["forward", "no-forward"])
def study(request, feeder):
    return run_cycle_study(feeder, math.radians(30.0), STUDY_SPEC, forward=request.param)


def test_names_are_unique_and_documented():
    assert len(set(NAMES)) == len(NAMES)
    for column in COLUMNS:
        assert column.name.strip() and column.meaning.strip()
    assert set(LAGRANGE_COLUMNS) <= set(NAMES)


def test_study_fills_every_column_in_file_order(study):
    """With the forward run every column of COLUMNS, in order; without it the same but the
    forward_* columns (and without the controlled run, which this study lacks, its
    controlled_* columns)."""
    columns = study.columns()
    forward = study.dynamics.forward is not None
    assert study.dynamics.controlled is None
    expected = [
        n
        for n in NAMES
        if (forward or not n.startswith(FORWARD_PREFIX)) and not n.startswith(CONTROLLED_PREFIX)
    ]
    assert list(columns) == expected
    assert forward or not any(name.startswith(FORWARD_PREFIX) for name in columns)
    samples = study.dynamics.kinematics.t.size
    for name, values in columns.items():
        assert np.shape(values) == (samples,), name
        assert np.all(np.isfinite(values)), name


def test_columns_are_cycle_columns_of_both_computations(study):
    columns = cycle_columns(study.dynamics, study.lagrange)
    assert list(columns) == list(study.columns())
    np.testing.assert_array_equal(columns["lagrange_piston_force"], study.lagrange.piston_force)
    np.testing.assert_array_equal(
        columns["lagrange_forearm_torque"], study.lagrange.forearm_torque
    )
    np.testing.assert_array_equal(columns["lagrange_lambda1"], study.lagrange.lambdas[:, 0])
    np.testing.assert_array_equal(columns["lagrange_lambda2"], study.lagrange.lambdas[:, 1])
    np.testing.assert_array_equal(columns["piston_force"], study.dynamics.loads.piston_force)


def test_kinematic_columns_are_the_leading_columns(cycle):
    """KINEMATIC_COLUMNS = the keys of kinematic_columns, and the first columns of the file."""
    columns = kinematic_columns(cycle)
    assert tuple(columns) == KINEMATIC_COLUMNS
    assert NAMES[: len(KINEMATIC_COLUMNS)] == list(KINEMATIC_COLUMNS)
    np.testing.assert_array_equal(columns["t"], cycle.t)
    np.testing.assert_array_equal(columns["payload"], cycle.gripped)
    np.testing.assert_array_equal(columns["q_phi3"], cycle.q[:, 2])
    np.testing.assert_array_equal(
        columns["projectile_speed"], np.linalg.norm(cycle.payload_velocity, axis=1)
    )
