"""``feeder analyze`` on the shipped examples: the mobility report, the loads table and its
consistency with the generic layer."""

from __future__ import annotations

import numpy as np
import pytest

from feeder.study.analyze import analyze, check_mechanism

from ..conftest import REPO

EXAMPLES = ("four_bar", "slider_crank")

PASSIVE = 1e-12
"""[N·m, N] Load along a passive joint's axis: zero to round-off."""


@pytest.fixture(scope="module", params=EXAMPLES)
def analysis(request):
    folder = REPO / "examples" / request.param
    return analyze(folder / "closures.toml", folder / "motion.csv")


def test_check_reports_one_degree_of_freedom(analysis):
    text = check_mechanism(REPO / "examples" / analysis.spec.model.stem / "closures.toml")
    assert "actual mobility 3 − 2 = 1" in text and "redundant closure rows (3" in text


def test_table_has_every_joint_and_the_drive(analysis):
    columns = analysis.columns()
    n = analysis.motion.t.size
    assert all(values.shape == (n,) for values in columns.values())
    assert "tau_crank_joint" in columns and "velocity_gain" in columns
    for name in analysis.loads.joints:
        for what in ("force", "moment"):
            assert f"{name}_{what}" in columns
            np.testing.assert_allclose(
                columns[f"{name}_{what}"],
                np.linalg.norm(
                    np.column_stack([columns[f"{name}_{what}_{axis}"] for axis in "xyz"]), axis=1
                ),
            )
    # The prescribed crank follows the table; the passive joints carry no drive load.
    np.testing.assert_array_equal(columns["q_crank_joint"], analysis.motion.x[:, 0])
    for name, wrench in analysis.loads.joints.items():
        if name != "crank_joint":
            assert np.abs(wrench.drive).max() <= PASSIVE


def test_summary_names_peaks_and_the_convention(analysis):
    text = analysis.summary()
    assert "peak actuator load crank_joint: max |τ|" in text
    assert "statically indeterminate closure rows" in text and "minimum" in text
