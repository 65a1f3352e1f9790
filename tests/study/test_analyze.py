"""``feeder analyze`` on the shipped examples: the mobility report, the loads table and its
consistency with the generic layer."""

from __future__ import annotations

import numpy as np
import pytest

from feeder.exceptions import InputError
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


@pytest.mark.parametrize("limits", [(-100.0, 100.0), (0.0, 0.0), (-20.0, 20.0)])
def test_the_branch_does_not_follow_the_joint_limits(tmp_path, limits):
    """The four-bar is written the natural way, links collinear and the loop open at zero: the
    branch is the closed pose nearest to that reference, whatever the limits say (±100 rad once
    gave a coupler at −95 rad and a 19 % lower peak crank torque)."""
    folder = REPO / "examples" / "four_bar"
    text = (folder / "four_bar.urdf").read_text()
    lower, upper = (f"{x!r}" for x in limits)
    text = text.replace('lower="-12.566370614359172"', f'lower="{lower}"')
    text = text.replace('upper="12.566370614359172"', f'upper="{upper}"')
    (tmp_path / "four_bar.urdf").write_text(text)
    (tmp_path / "closures.toml").write_text((folder / "closures.toml").read_text())
    reference = analyze(folder / "closures.toml", folder / "motion.csv")
    changed = analyze(tmp_path / "closures.toml", folder / "motion.csv")
    np.testing.assert_allclose(changed.q, reference.q, atol=1e-12)
    np.testing.assert_allclose(
        changed.loads.actuators["crank_joint"], reference.loads.actuators["crank_joint"], atol=1e-9
    )
    assert np.abs(changed.q[:, 1:]).max() <= np.pi  # dependent angles wrapped, never wound


def test_a_pose_file_picks_the_other_branch(tmp_path):
    """The mirror image of the default branch (coupler and rocker angles negated at the first
    sample) is the nearest closed pose to a reference drawn there."""
    folder = REPO / "examples" / "four_bar"
    default = analyze(folder / "closures.toml", folder / "motion.csv")
    names = ("crank_joint", "coupler_joint", "rocker_joint")
    mirrored = {name: -default.assembled[i] for i, name in enumerate(names)}
    (tmp_path / "pose.csv").write_text(
        "joint,value\n" + "".join(f"{name},{float(value)!r}\n" for name, value in mirrored.items())
    )
    other = analyze(folder / "closures.toml", folder / "motion.csv", pose=tmp_path / "pose.csv")
    np.testing.assert_allclose(other.assembled, -default.assembled, atol=1e-9)
    assert not np.allclose(other.q[:, 1], default.q[:, 1], atol=1e-3)


@pytest.mark.parametrize("key", ["actuated", "independent"])
def test_check_refuses_a_joint_the_model_does_not_have(tmp_path, key):
    folder = REPO / "examples" / "four_bar"
    text = (folder / "closures.toml").read_text()
    old = f'{key} = ["crank_joint"]'
    assert old in text
    (tmp_path / "closures.toml").write_text(text.replace(old, f'{key} = ["no_such_joint"]'))
    with pytest.raises(InputError, match=rf"{key} joints: no joint 'no_such_joint'.*correct them"):
        check_mechanism(tmp_path / "closures.toml", folder / "four_bar.urdf")
