"""``feeder analyze`` on the shipped examples: the mobility report, the loads table and its
consistency with the generic layer."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from feeder.chain import Partition
from feeder.exceptions import FeederWarning, InputError, SingularPoseError
from feeder.study.analyze import analyze, check_mechanism
from feeder.study.csv import write_csv

from ..conftest import REPO

EXAMPLES = ("four_bar", "slider_crank")

PASSIVE = 1e-12
"""[N·m, N] Load along a passive joint's axis: zero to round-off."""


@pytest.fixture(scope="module", params=EXAMPLES)
def analysis(request):
    folder = REPO / "examples" / request.param
    return analyze(folder / "closures.toml", folder / "motion.csv")


def test_check_reports_one_degree_of_freedom(analysis):
    check = check_mechanism(REPO / "examples" / analysis.spec.model.stem / "closures.toml")
    assert "actual mobility 3 − 2 = 1" in check.text
    assert (
        "self-stresses of the closures: 3; statically indeterminate closure rows (3" in check.text
    )
    assert check.drives


def test_check_and_analyze_report_the_same_pose_under_its_name(analysis):
    """Both measure the mobility at the assembled pose and say so, and what is indeterminate
    (the summary along the motion, its rows too); the analysis names the first sample where it
    gives that sample's gain (the crank-rocker's is not the assembled pose's)."""
    check = check_mechanism(REPO / "examples" / analysis.spec.model.stem / "closures.toml")
    summary = analysis.summary()
    lines = check.text.splitlines()
    block = lines.index(next(line for line in lines if line.startswith("  statically")))
    assert summary.startswith("\n".join(lines[:block]) + "\n")
    assert all(line in summary.splitlines() for line in lines[block:])
    assert check.text.startswith("mobility at the assembled pose (the closed pose nearest")
    gains = f"velocity gain at the first sample (t = 0 s) {analysis.gain[0]:.3g}, largest"
    assert gains in summary
    partition = Partition(analysis.chain, analysis.spec.independent)
    assert analysis.report.gain == partition.gain(analysis.assembled)
    assert analysis.gain[0] == pytest.approx(partition.gain(analysis.q[0]), rel=1e-12)


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
    message = str(caught.value)  # one line: the loop, the joints by name, values with units
    assert "singular pose" in message and "\n" not in message and "q = [" not in message
    assert "loop coupler_tip-rocker_tip (crank_joint = " in message
    assert re.search(r"at rocker_joint = 2\.2\d* rad[:,]", message)


def test_a_coarse_motion_short_of_the_dead_centre_is_followed(tmp_path):
    """1e-4 rad short of the dead centre the velocity gain is ~150 (below MAX_GAIN): 11 samples
    are followed in adaptive parts, however sharply the crank turns there."""
    spec, motion = _rocker_swing(tmp_path, DEAD_CENTRE - 1e-4, 11)
    analysis = analyze(spec, motion, model=REPO / "examples" / "four_bar" / "four_bar.urdf")
    assert 100.0 < analysis.gain.max() < 200.0
    assert analysis.chain.residual(analysis.q[5]).__abs__().max() < 1e-9


FLOATING_COUPLER = """[mechanism]
urdf = "four_bar.urdf"
actuated = ["crank-joint"]
independent = ["crank-joint"]
gravity = [0.0, -9.81, 0.0]
pose = { "crank-joint" = 0.7 }

[[closure]]
frames = ["crank_tip", "coupler"]
type = "revolute"

[[closure]]
frames = ["coupler_tip", "rocker_tip"]
type = "revolute"

[[force]]
type = "cylinder"
frames = ["ground", "rocker_tip"]
bore = 0.02
rod = 0.01
pressure = 1e5
"""
"""The example four-bar with its coupler a free body (a free-flyer on the ground) pinned to the
crank's tip and the rocker's by two revolute cuts, joint names with '-' and '.', and a cylinder
with its default label ``cylinder:ground-rocker_tip``."""

CRANK, COUPLER, ROCKER, GROUND = 0.04, 0.12, 0.08, 0.1
"""The example four-bar's lengths [m] (examples/four_bar/four_bar.urdf)."""


@pytest.fixture(scope="module")
def floating(tmp_path_factory):
    """The analysis of :data:`FLOATING_COUPLER` over one crank turn."""
    folder = tmp_path_factory.mktemp("floating")
    urdf = (REPO / "examples" / "four_bar" / "four_bar.urdf").read_text()
    pinned = urdf[
        urdf.index('  <joint name="coupler_joint"') : urdf.index('  <link name="coupler_tip"')
    ]
    free = """  <joint name="coupler_free" type="floating">
    <parent link="ground"/>
    <child link="coupler"/>
  </joint>
  <link name="crank_tip"/>
  <joint name="crank_tip_joint" type="fixed">
    <origin xyz="0.04 0 0" rpy="0 0 0"/>
    <parent link="crank"/>
    <child link="crank_tip"/>
  </joint>
"""
    urdf = urdf.replace(pinned, free).replace('"crank_joint"', '"crank-joint"')
    (folder / "four_bar.urdf").write_text(urdf.replace('"rocker_joint"', '"rocker.joint"'))
    (folder / "floating.toml").write_text(FLOATING_COUPLER)
    t = np.linspace(0.0, 1.0, 51)
    rows = "".join(f"{float(a)!r},{float(0.7 + 2 * np.pi * a)!r}\n" for a in t)
    (folder / "motion.csv").write_text("t,q_crank-joint\n" + rows)
    return analyze(folder / "floating.toml", folder / "motion.csv")


GEOMETRY = 1e-9
"""[m, rad] The loops close to ~1e-13 (Newton's tolerance) times the velocity gain (≤ 2)."""


def test_a_free_flyer_shows_its_coordinates_by_name(floating):
    """The coupler's origin is the crank's tip and its angle the direction from there to the
    rocker's tip: the free-flyer's columns x, y, rz read against the four-bar's geometry."""
    columns = floating.columns()
    crank, rocker = columns["q_crank_joint"], columns["q_rocker_joint"]
    tip = CRANK * np.column_stack([np.cos(crank), np.sin(crank)])
    rocker_tip = np.column_stack([GROUND + ROCKER * np.cos(rocker), ROCKER * np.sin(rocker)])
    np.testing.assert_allclose(columns["q_coupler_free_x"], tip[:, 0], atol=GEOMETRY)
    np.testing.assert_allclose(columns["q_coupler_free_y"], tip[:, 1], atol=GEOMETRY)
    direction = np.arctan2(*(rocker_tip - tip)[:, ::-1].T)
    np.testing.assert_allclose(columns["q_coupler_free_rz"], direction, atol=GEOMETRY)
    np.testing.assert_allclose(columns["q_coupler_free_qz"], np.sin(direction / 2), atol=GEOMETRY)
    named = [key for key in columns if key.startswith(("q_coupler_free", "v_coupler_free"))]
    assert named == [
        *(
            f"q_coupler_free_{c}"
            for c in ("x", "y", "z", "rx", "ry", "rz", "qx", "qy", "qz", "qw")
        ),
        *(f"v_coupler_free_{c}" for c in ("vx", "vy", "vz", "wx", "wy", "wz")),
    ]
    text = floating.summary()
    assert "  coupler_free x = " in text and " m\n" in text and "  coupler_free qw = " in text
    assert "coupler_free 1" not in text and "coupler_free q =" not in text


def test_a_free_flyer_has_no_reaction(floating):
    """A joint free in all six directions transmits nothing: no round-off "reaction" for it."""
    assert "coupler_free" not in floating.loads.joints
    assert not [key for key in floating.columns() if key.startswith("coupler_free_")]
    assert (
        "no reaction in coupler_free: free in all six directions (a free-flyer), it transmits no "
        "force and no moment" in floating.summary()
    )


def test_every_column_name_reads_back_as_written(floating, tmp_path):
    """numpy.genfromtxt(names=True) keeps every name (it deletes '-', ':' and '.'), and each is
    an identifier (pandas' attribute access, formulas): the closures', the element's and the
    joints' names with '-' and '.' written with '_'."""
    columns = floating.columns()
    path = write_csv(tmp_path / "loads.csv", columns)
    table = np.genfromtxt(path, delimiter=",", names=True)
    assert table.dtype.names == tuple(columns)
    assert all(name.isidentifier() for name in columns)
    for name in (
        "crank_tip_coupler_force_x",
        "coupler_tip_rocker_tip_moment_z",
        "cylinder_ground_rocker_tip_force",
        "tau_crank_joint",
        "rocker_joint_force",
    ):
        assert name in columns
    assert "peak force of cylinder:ground-rocker_tip: " in floating.summary()


def test_two_columns_of_one_name_are_refused(tmp_path):
    """A joint named ``mount`` would write ``mount_force_x`` as the mount's does: refused, named
    (a table silently missing one of them was written before)."""
    folder = REPO / "examples" / "four_bar"
    (tmp_path / "four_bar.urdf").write_text(
        (folder / "four_bar.urdf").read_text().replace('"rocker_joint"', '"mount"')
    )
    (tmp_path / "closures.toml").write_text((folder / "closures.toml").read_text())
    analysis = analyze(tmp_path / "closures.toml", folder / "motion.csv")
    with pytest.raises(InputError, match=r"two columns of the table would be named 'mount_force"):
        analysis.columns()


def test_a_load_at_round_off_is_printed_as_zero_without_a_time(tmp_path):
    """The four-bar at rest under gravity along its joints' axes (−z): gravity does no work, so
    the crank's drive load is zero in exact arithmetic (virtual work); the joints carry the
    weight (their reactions are not zero)."""
    folder = REPO / "examples" / "four_bar"
    text = (folder / "closures.toml").read_text()
    (tmp_path / "closures.toml").write_text(
        text.replace("gravity = [0.0, -9.81, 0.0]", "gravity = [0.0, 0.0, -9.81]")
    )
    (tmp_path / "four_bar.urdf").write_text((folder / "four_bar.urdf").read_text())
    (tmp_path / "rest.csv").write_text(
        "t,q_crank_joint,v_crank_joint,a_crank_joint\n0,0.7,0,0\n0.5,0.7,0,0\n1,0.7,0,0\n"
    )
    with pytest.warns(FeederWarning, match="does no work"):
        analysis = analyze(tmp_path / "closures.toml", tmp_path / "rest.csv")
    lines = analysis.summary().splitlines()
    (drive,) = [line for line in lines if "peak actuator load crank_joint" in line]
    assert "0 N·m to round-off" in drive and "at t =" not in drive
    reactions = [line for line in lines if "peak reaction force" in line]
    assert len(reactions) == 3 and all(" N at t = " in line for line in reactions)


def test_the_mechanism_file_s_points_are_columns_of_the_loads_table(tmp_path):
    """A ``[[point]]`` at the rocker's tip: its columns are the tip frame's position and velocity
    (feeder.chain.frame_motion, the named frame's own computation) along the analysed motion."""
    from feeder.chain import frame_motion

    folder = REPO / "examples" / "four_bar"
    text = (folder / "closures.toml").read_text(encoding="utf-8")
    path = tmp_path / "closures.toml"
    path.write_text(text + '\n[[point]]\nname = "P1"\nframe = "rocker_tip"\n', encoding="utf-8")
    analysis = analyze(path, folder / "motion.csv", model=folder / "four_bar.urdf")
    columns = analysis.columns()
    tip = frame_motion(analysis.chain, ["rocker_tip"], analysis.q, analysis.v)["rocker_tip"]
    for k, axis in enumerate("xyz"):
        np.testing.assert_allclose(columns[f"point_P1_{axis}"], tip.position[:, k], atol=1e-15)
        np.testing.assert_allclose(
            columns[f"point_P1_velocity_{axis}"], tip.velocity[:, k], atol=1e-15
        )
    assert "point_P1_acceleration_x" in columns
