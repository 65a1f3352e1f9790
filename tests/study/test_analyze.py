"""``feeder analyze`` on the shipped examples: the mobility report, the loads table and its
consistency with the generic layer."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder.exceptions import InputError, SingularPoseError
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


ROCKER_DRIVEN = """[mechanism]
urdf = "four_bar.urdf"
actuated = ["rocker_joint"]
independent = ["rocker_joint"]
gravity = [0.0, -9.81, 0.0]
pose = {crank_joint = 0.7, rocker_joint = 1.5}

[[closure]]
frames = ["coupler_tip", "rocker_tip"]
type = "revolute"
"""
"""The example four-bar (crank 40 mm, coupler 120 mm, rocker 80 mm, ground 100 mm) driven from
its rocker: a crank-rocker whose rocker swings between the dead centres where crank and coupler
are aligned, the folded one at cos φ = (0.08² − 0.1² − 0.08²)/(2 · 0.1 · 0.08) = −0.625."""

DEAD_CENTRE = math.acos(-0.625)
"""The rocker's largest angle [rad] (the folded dead centre above)."""


def _rocker_swing(tmp_path, top: float, samples: int):
    """The mechanism file and a motion of the rocker from 1.5 rad up to ``top`` and back."""
    (tmp_path / "rocker.toml").write_text(ROCKER_DRIVEN)
    t = np.linspace(0.0, 1.0, samples)
    x = 1.5 + (top - 1.5) * np.sin(np.pi * t)
    rows = "\n".join(f"{float(a)!r},{float(b)!r}" for a, b in zip(t, x, strict=True))
    (tmp_path / "motion.csv").write_text(f"t,q_rocker_joint\n{rows}\n")
    return tmp_path / "rocker.toml", tmp_path / "motion.csv"


@pytest.mark.parametrize(
    "top, samples",
    [(DEAD_CENTRE, 11), (DEAD_CENTRE, 101), (DEAD_CENTRE, 1001), (DEAD_CENTRE + 0.05, 101)],
    ids=["dead-centre-11", "dead-centre-101", "dead-centre-1001", "beyond-101"],
)
def test_a_motion_through_a_dead_centre_is_a_singular_pose_at_any_sampling(tmp_path, top, samples):
    spec, motion = _rocker_swing(tmp_path, top, samples)
    with pytest.raises(SingularPoseError, match=r"^sample \d+ \(t = 0\.[345]\d* s\): ") as caught:
        analyze(spec, motion, model=REPO / "examples" / "four_bar" / "four_bar.urdf")
    assert "singular pose" in str(caught.value) and "q = [" in str(caught.value)


def test_a_coarse_motion_short_of_the_dead_centre_is_followed(tmp_path):
    """1e-4 rad short of the dead centre the velocity gain is ~150 (below MAX_GAIN): 11 samples
    are followed in adaptive parts, however sharply the crank turns there."""
    spec, motion = _rocker_swing(tmp_path, DEAD_CENTRE - 1e-4, 11)
    analysis = analyze(spec, motion, model=REPO / "examples" / "four_bar" / "four_bar.urdf")
    assert 100.0 < analysis.gain.max() < 200.0
    assert analysis.chain.residual(analysis.q[5]).__abs__().max() < 1e-9
