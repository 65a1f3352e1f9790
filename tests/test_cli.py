"""Command line: outputs exist and follow the contract; bad input exits non-zero with a message."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder.__main__ import main
from feeder.results import read_csv

from .conftest import REPO


def test_kinematics_command(tmp_path, capsys):
    assert main(["kinematics", "--elevation", "30", "--out", str(tmp_path), "--rate", "200"]) == 0
    table = read_csv(tmp_path / "cycle.csv")
    assert len(table["t"]) == 801
    assert table["closure_residual"].max() <= 1e-10
    assert table["q_phi3"][-1] == pytest.approx(math.radians(60.0), abs=1e-12)
    for name in ("fig04_workspace.png", "fig10_projectile_position.png"):
        assert (tmp_path / name).stat().st_size > 10_000
    out = capsys.readouterr().out
    assert "stroke" in out and "peak payload speed" in out
    speed = float(out.split("peak payload speed: ")[1].split()[0])
    assert speed == pytest.approx(table["projectile_speed"].max(), abs=1e-3)


def test_charge_device(tmp_path):
    assert main(["kinematics", "--elevation", "-4", "--out", str(tmp_path), "--device", "charge",
                 "--rate", "100"]) == 0
    from feeder import CHARGE_FEEDER, PROJECTILE_FEEDER

    z = read_csv(tmp_path / "cycle.csv")["projectile_z"]
    # Mirrored through the barrel plane: the payload sits at −z where the projectile is at +z.
    assert z[-1] == pytest.approx(-(PROJECTILE_FEEDER.c + PROJECTILE_FEEDER.z5), abs=1e-15)
    assert z[-1] == pytest.approx(CHARGE_FEEDER.c + CHARGE_FEEDER.z5, abs=1e-15) and z[-1] < 0


@pytest.mark.parametrize("elevation, message", [("75", "outside"), ("nan", "finite")])
def test_bad_elevation_exits_with_message(tmp_path, capsys, elevation, message):
    assert main(["kinematics", "--elevation", elevation, "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


def test_unknown_device_is_an_argparse_error(tmp_path):
    with pytest.raises(SystemExit) as info:
        main(["kinematics", "--elevation", "0", "--out", str(tmp_path), "--device", "mortar"])
    assert info.value.code == 2


def test_urdf_command_regenerates_the_shipped_files(tmp_path):
    assert main(["urdf", "--out", str(tmp_path)]) == 0
    for name in ("projectile_feeder.urdf", "charge_feeder.urdf"):
        assert (tmp_path / name).read_text() == (REPO / "urdf" / name).read_text()
