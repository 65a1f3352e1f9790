"""The device on a vehicle, end to end: ``feeder cycle --slope/--base-motion`` (its table, its
manifest, the comparison figure and the summary), vehicle cases in a sweep grid, and the
refusals. The dynamics themselves are checked in tests/chain/dynamics/test_base_motion.py and
test_base_mujoco.py; here, what reaches the user."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from feeder import load_feeder, run_cycle_study
from feeder.chain.model.base import BaseMotion
from feeder.chain.model.profiles import Recoil, Slope, Terrain
from feeder.cli import main
from feeder.device.parameters import VEHICLE_FORWARD
from feeder.motion.laws import CycleSpec
from feeder.study.csv import read_csv
from feeder.study.grid_file import read_grid
from feeder.study.sweep_table import read_sweep_table

SPEC = CycleSpec(rate=100.0)


def test_side_slope_loads_the_pivots_sideways():
    """At rest (the cycle's first sample) a roll turns part of the weight W into the device's z
    (the vehicle's left): standing, the arm pivot carries no lateral force; on a 15° roll (right
    side down) gravity has a component −g sin 15° along the left, so the mount pushes with
    F_z = +W sin 15°, carries the same |F| = W, and in the level axes its force is W straight
    up."""
    feeder = load_feeder("projectile")
    roll = math.radians(15.0)
    base = BaseMotion((Slope(roll=roll),), forward=VEHICLE_FORWARD)
    study = run_cycle_study(feeder, math.radians(30.0), SPEC, forward=False, base=base)
    standing = study.level
    assert standing.reactions.joints["arm_frame"].force[0, 2] == 0.0
    assert abs(study.dynamics.reactions.joints["arm_frame"].force[0, 2]) > 10.0
    still, tilted = standing.reactions.mount, study.dynamics.reactions.mount
    weight = np.linalg.norm(still.force[0])
    # round-off of sums of ~1e3 N terms: ~1e-13 N
    np.testing.assert_allclose(np.linalg.norm(tilted.force[0]), weight, rtol=1e-12)
    np.testing.assert_allclose(tilted.force[0, 2], weight * math.sin(roll), rtol=1e-12)
    np.testing.assert_allclose(tilted.level_force[0], [0.0, weight, 0.0], atol=1e-12 * weight)


def test_cycle_command_on_a_vehicle(tmp_path, capsys):
    out = tmp_path / "run"
    code = main(
        [
            "cycle",
            "--elevation",
            "30",
            "--rate",
            "100",
            "--no-forward",
            "--slope",
            "0",
            "15",
            "--base-motion",
            "terrain:heave=0.02",
            "--out",
            str(out),
        ]
    )
    assert code == 0
    text = capsys.readouterr().out
    assert "base: slope: pitch 0°, roll 15°; terrain: heave ±20 mm" in text
    assert "against the cycle standing level" in text
    assert (out / "base_peaks.png").stat().st_size > 10_000
    manifest = json.loads((out / "feeder-run.json").read_text())
    assert manifest["base"].startswith("slope")
    table = read_csv(out / "cycle.csv")
    for name in ("mount_force", "mount_moment_vehicle_z", "mount_force_x"):
        assert name in table


def test_forward_run_skipped_on_a_moving_base_kept_on_a_slope():
    feeder = load_feeder("projectile")
    moving = BaseMotion((Recoil(start=0.5),), forward=VEHICLE_FORWARD)
    sloped = BaseMotion((Slope(pitch=math.radians(5.0)),), forward=VEHICLE_FORWARD)
    spec = CycleSpec(rate=500.0)
    rocking = run_cycle_study(feeder, 0.5, spec, base=moving)
    assert rocking.dynamics.forward is None
    assert "skipped (the base moves)" in rocking.summary()
    run = run_cycle_study(feeder, 0.5, spec, base=sloped).dynamics
    assert max(run.tracking_error()) < 1e-4  # the force-rule check, on tilted gravity


def test_cycle_command_reads_a_base_file(tmp_path, capsys):
    """A [base] table without forward (the device's is fixed); with one, refused."""
    path = tmp_path / "base.toml"
    path.write_text('[base]\nroll_deg = 5.0\n[[base.profile]]\ntype = "bump"\nstart = 0.5\n')
    args = ["cycle", "--elevation", "30", "--rate", "100", "--no-figures", "--no-forward"]
    assert main([*args, "--base-motion", str(path), "--out", str(tmp_path / "a")]) == 0
    assert "slope: pitch 0°, roll 5°; bump: half-sine 2 g" in capsys.readouterr().out
    path.write_text("[base]\nforward = [1.0, 0.0, 0.0]\n")
    assert main([*args, "--base-motion", str(path), "--out", str(tmp_path / "b")]) != 0
    assert "leave forward out" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (
            ["--slope", "0", "95"],
            "roll reaches ±1.658 rad (95°), beyond the plausible ±0.7854 rad (45°)",
        ),
        (["--slope", "60", "0"], "pitch reaches ±1.047 rad (60°)"),
        (["--base-motion", "terrain:frequency=1e6"], "terrain frequency is 1e+06 Hz"),
        (["--base-motion", "bump:peak=1e12"], "z acceleration reaches ±1e+12 m/s²"),
        (["--slope", "nan", "0"], "slope"),
        (["--base-motion", "earthquake"], "unknown base profile"),
        (["--base-motion", "terrain:heave=big"], "number"),
        (["--base-motion", "no_such_file.csv"], "not found"),
        (["--base-motion", "."], "--base-motion . is a folder"),
        (["--base-motion", __file__], "neither a hull table (.csv) nor a .toml file"),
        (["--params", "."], "parameter file . is a folder, not a file"),
    ],
)
def test_cycle_command_refusals(tmp_path, capsys, args, match):
    code = main(
        ["cycle", "--elevation", "30", "--rate", "100", "--out", str(tmp_path / "o"), *args]
    )
    assert code != 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and match in err[0]


def test_a_file_named_as_a_profile_is_the_profile(tmp_path, monkeypatch):
    """``--base-motion terrain`` beside a folder ``terrain`` (e.g. the last run's output), or
    ``terrain:heave=0.05`` beside a file of that name, is the profile, not the file."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "terrain").mkdir()
    (tmp_path / "terrain:heave=0.05").write_text("")
    args = ["cycle", "--elevation", "30", "--rate", "100", "--no-forward", "--no-figures"]
    assert main([*args, "--base-motion", "terrain", "--out", "terrain"]) == 0
    assert main([*args, "--base-motion", "terrain:heave=0.05", "--out", "terrain"]) == 0


def test_cycle_command_refuses_motions_past_the_limits_together(tmp_path, capsys):
    """A slope and a file's [base] pitch each plausible, 50° together; a hull table's roll of
    30 (degrees in a radian column): one line each, before anything is computed."""
    path = tmp_path / "base.toml"
    path.write_text("[base]\npitch_deg = 30.0\n")
    hull = tmp_path / "hull.csv"
    hull.write_text("t,roll\n0,30\n5,30\n10,30\n")
    args = ["cycle", "--elevation", "30", "--rate", "100", "--out", str(tmp_path / "o")]
    for extra, match in [
        (["--slope", "20", "0", "--base-motion", str(path)], "together (slope: pitch 20°, roll "
         "0°; slope: pitch 30°, roll 0°): their pitch reaches ±0.8727 rad (50°)"),
        (["--base-motion", str(hull)], "roll = 30 rad (1719°) at t = 0 s is beyond the plausible "
         "±0.7854 rad (45°) (steeper than a vehicle stands on); if it holds degrees, name the "
         "column roll_deg"),
    ]:  # fmt: skip
        assert main([*args, *extra]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and match in err[0]
    assert not (tmp_path / "o").exists()


def test_vehicle_cases_in_a_sweep_grid(tmp_path):
    grid = tmp_path / "grid.toml"
    grid.write_text(
        "elevations = [0, 30]\nrate = 100.0\n"
        '[[variants]]\nname = "reference"\n'
        '[[variants]]\nname = "side_slope"\nbase = {roll_deg = 15.0}\n'
        '[[variants]]\nname = "cross_country"\n[[variants.base.profile]]\ntype = "terrain"\n'
    )
    cases = read_grid(grid).cases()
    assert {case.variant for case in cases} == {"reference", "side_slope", "cross_country"}
    assert len({case.sha256 for case in cases}) == len(cases)
    slope = next(case for case in cases if case.variant == "side_slope")
    assert slope.base.profiles == (Slope(0.0, math.radians(15.0)),)
    assert slope.base.forward == VEHICLE_FORWARD
    assert (
        main(
            [
                "sweep",
                "--grid",
                str(grid),
                "--out",
                str(tmp_path / "s"),
                "--workers",
                "1",
                "--no-figures",
            ]
        )
        == 0
    )
    rows, rejected = read_sweep_table(tmp_path / "s" / "sweep_peaks.csv")
    assert rejected == []
    by = {(row["variant"], row["elevation_deg"]): row for row in rows}
    assert (
        by[("side_slope", 30.0)]["arm_frame_force"] != by[("reference", 30.0)]["arm_frame_force"]
    )
    grid.write_text('[[variants]]\nname = "x"\nbase = {forward = [0, 0, 1]}\n')
    with pytest.raises(Exception, match="forward"):
        read_grid(grid)


def test_terrain_profile_moves_the_loads():
    feeder = load_feeder("projectile")
    base = BaseMotion((Terrain(),), forward=VEHICLE_FORWARD)
    study = run_cycle_study(feeder, math.radians(30.0), SPEC, forward=False, base=base)
    growth = (
        abs(study.dynamics.loads.piston_force).max() / abs(study.level.loads.piston_force).max()
    )
    assert growth > 1.01
