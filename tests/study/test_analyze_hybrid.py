"""``feeder analyze --motion`` on mechanisms whose actuated joints leave a freedom free that moves
mass: the rod between two balls on a driven carriage (tests/data/hybrid), and the Cassie-like
CAD export with one rod's centre of gravity moved 2 mm off the line through its balls (the case
of the exports the issue names: refused before, at the first sample). The hybrid run's own
accuracy is checked against closed forms in tests/chain/dynamics/test_hybrid.py; here: the
summary names the free freedoms, how far they moved and their start, ``--check`` lets them pass,
and the mechanisms without such a freedom keep the minimum-norm path.
"""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from feeder.chain.dynamics.hybrid import HybridRun
from feeder.study.analyze import analyze, check_mechanism

from ..conftest import REPO

DATA = REPO / "tests" / "data" / "hybrid"
CAD = REPO / "examples" / "cad"

ROD_CENTRE = (
    '<origin xyz="6.3459955094325992158e-17 -6.0542399339965078733e-19 '
    '-0.12549999999999997269" rpy="0 0 0" />'
)
"""The centre of gravity of the Cassie-like leg's half_hachil_rode, on the line through its two
balls (the rod frame's z axis) as exported."""


def carriage_table(path, samples=101, span=1.0):
    """x = 0.1 sin(2π t) [m] of the carriage, with exact rates, written as a motion table."""
    t = np.linspace(0.0, span, samples)
    w = 2.0 * np.pi
    x = 0.1 * np.sin(w * t)
    columns = np.column_stack([t, x, 0.1 * w * np.cos(w * t), -w * w * x])
    rows = [",".join(repr(value) for value in row) for row in columns.tolist()]
    path.write_text("t,q_slider,v_slider,a_slider\n" + "\n".join(rows) + "\n", encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def offset_cassie(tmp_path_factory):
    """The Cassie-like export with its half_hachil_rode's centre of gravity 2 mm off its axis,
    and the first 0.2 s of its shipped motion table."""
    folder = tmp_path_factory.mktemp("cassie") / "cassie_like"
    shutil.copytree(CAD / "cassie_like", folder)
    urdf = folder / "robot.urdf"
    text = urdf.read_text(encoding="utf-8")
    assert text.count(ROD_CENTRE) == 1
    urdf.write_text(text.replace(ROD_CENTRE, '<origin xyz="0.002 0 -0.1255" rpy="0 0 0" />'))
    lines = (CAD / "cassie_like_motion.csv").read_text().splitlines()
    motion = folder / "motion.csv"
    motion.write_text("\n".join(lines[:42]) + "\n")  # t ≤ 0.2 s
    return folder


def test_the_rod_on_the_carriage_runs_hybrid_and_the_summary_names_its_spin(tmp_path):
    analysis = analyze(DATA / "ball_rod.toml", carriage_table(tmp_path / "motion.csv"))
    assert isinstance(analysis.hybrid, HybridRun)
    summary = analysis.summary()
    assert "1 freedom(s) free that move mass" in summary
    excursion = analysis.hybrid.excursion()[0]
    assert f"free freedom 1 moves ball_rz; max excursion {excursion:.4g} rad" in summary
    assert excursion > 0.5  # the carriage's 3.9 m/s² swing the 5 cm pendulum far
    assert "start: the free freedoms at rest" in summary and "ball_rz = -0.3 rad" in summary
    columns = analysis.columns()
    np.testing.assert_array_equal(columns["q_ball_rz"], analysis.hybrid.q[:, 3])
    np.testing.assert_array_equal(columns["a_ball_rz"], analysis.hybrid.a[:, 3])


def test_check_lets_a_mechanism_with_free_freedoms_pass(tmp_path):
    check = check_mechanism(DATA / "ball_rod.toml")
    assert check.report.determined is not None  # not determined by the slider alone …
    assert check.free == (("ball_rz",),) and check.drives  # … but analyze runs it
    assert "1 freedom(s) left free move mass (ball_rz)" in check.text


def test_the_rod_on_the_carriage_runs_hybrid_on_a_moving_hull(tmp_path):
    """The mechanism file's [base]: a 5° slope and the default terrain (its pitch −3° at t = 0,
    its roll 0). Refused before; now the run's start is at rest under the gravity of the hull's
    2° nose-down pitch at t = 0: the rod's centre of gravity hangs 2° towards +x from the
    model's −y, ball_rz = 2° − TILT (0.3 rad, ball_rod.urdf), to SciPy's root's 1e-8 rad. The
    run's accuracy on a moving base: tests/chain/dynamics/test_hybrid_base.py."""
    for name in ("ball_rod.urdf", "ball_rod.toml"):
        shutil.copy(DATA / name, tmp_path / name)
    with (tmp_path / "ball_rod.toml").open("a", encoding="utf-8") as file:
        file.write('\n[base]\npitch_deg = 5.0\n[[base.profile]]\ntype = "terrain"\n')
    analysis = analyze(tmp_path / "ball_rod.toml", carriage_table(tmp_path / "motion.csv"))
    run = analysis.hybrid
    assert isinstance(run, HybridRun)
    assert abs(run.start[3] - (np.radians(2.0) - 0.3)) <= 1e-8
    summary = analysis.summary()
    assert "base: slope: pitch 5°, roll 0°; terrain" in summary
    assert "under the gravity the moving base sees there" in summary
    assert run.excursion()[0] > 0.5 and np.all(np.isfinite(analysis.loads.actuators["slider"]))


def test_a_cad_rod_with_its_centre_off_its_axis_runs_hybrid(offset_cassie):
    """Refused before ("… can still move … not an idle motion"); now the rod's spin is
    integrated, the other rod (centre on its axis) stays an idle motion."""
    analysis = analyze(offset_cassie / "robot.yaml", offset_cassie / "motion.csv")
    run = analysis.hybrid
    assert run is not None and run.idle == 1
    assert set(run.free.joints[0]) == {
        "tarsus_half_hachil_rode_rev2",
        "tigh_half_hachil_rode_2_rev2",
    }
    assert run.excursion()[0] > 1e-3
    assert "free freedom 1 moves" in analysis.summary()
    assert np.all(np.isfinite(analysis.loads.actuators["motor_knee"]))


def test_the_same_rod_without_mass_stays_an_idle_motion(offset_cassie, tmp_path):
    """The same rod with no inertial: its spin moves no mass and no point (its frames lie on its
    axis), so it is an idle motion again, on the minimum-norm path: no hybrid run."""
    folder = tmp_path / "cassie_like"
    shutil.copytree(offset_cassie, folder)
    urdf = folder / "robot.urdf"
    text = urdf.read_text(encoding="utf-8")
    start = text.index('<link name="half_hachil_rode">')
    end = text.index("</link>", start)
    link = text[start:end]
    inertial = link[link.index("<inertial>") : link.index("</inertial>") + len("</inertial>")]
    urdf.write_text(text[:start] + link.replace(inertial, "") + text[end:])
    analysis = analyze(folder / "robot.yaml", folder / "motion.csv")
    assert analysis.hybrid is None and analysis.loads.idle_motions == 2


@pytest.mark.parametrize("example", ["four_bar", "slider_crank"])
def test_mechanisms_their_joints_determine_keep_the_minimum_norm_path(example):
    folder = REPO / "examples" / example
    assert analyze(folder / "closures.toml", folder / "motion.csv").hybrid is None
