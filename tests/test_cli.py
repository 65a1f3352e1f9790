"""Command line: outputs exist and follow the contract; bad input exits non-zero with a message."""

from __future__ import annotations

import math

import pytest

from feeder.__main__ import main
from feeder.study.csv import read_csv

from .conftest import REPO

PIN_GAP = 1e-10
"""[m] The loop closes to round-off (~1e-16 m) in the file: 17 digits keep that far below this."""
ANGLE_ROUND_OFF = 1e-12
"""[rad] An angle written with 17 digits and read back, after a sum of ~1 rad terms."""
PRINTED_DIGITS = 1e-3
"""[m/s] The summary prints speeds with 3 decimals."""
POSITION_ROUND_OFF = 1e-15
"""[m] A ~0.1 m coordinate from a few additions, written with 17 digits."""


def test_kinematics_command(tmp_path, capsys):
    assert main(["kinematics", "--elevation", "30", "--out", str(tmp_path), "--rate", "200"]) == 0
    table = read_csv(tmp_path / "cycle.csv")
    assert len(table["t"]) == 801
    assert table["closure_residual"].max() <= PIN_GAP
    assert table["q_phi3"][-1] == pytest.approx(math.radians(60.0), abs=ANGLE_ROUND_OFF)
    for name in ("fig04_workspace.png", "fig10_projectile_position.png"):
        assert (tmp_path / name).stat().st_size > 10_000
    out = capsys.readouterr().out
    assert "stroke" in out and "peak payload speed" in out
    speed = float(out.split("peak payload speed: ")[1].split()[0])
    assert speed == pytest.approx(table["projectile_speed"].max(), abs=PRINTED_DIGITS)


def test_charge_device(tmp_path):
    assert (
        main(
            [
                "kinematics",
                "--elevation",
                "-4",
                "--out",
                str(tmp_path),
                "--device",
                "charge",
                "--rate",
                "100",
            ]
        )
        == 0
    )
    from feeder.device import CHARGE_FEEDER, PROJECTILE_FEEDER

    z = read_csv(tmp_path / "cycle.csv")["projectile_z"]
    # Mirrored through the barrel plane: the payload sits at −z where the projectile is at +z.
    assert z[-1] == pytest.approx(
        -(PROJECTILE_FEEDER.c + PROJECTILE_FEEDER.z5), abs=POSITION_ROUND_OFF
    )
    assert (
        z[-1] == pytest.approx(CHARGE_FEEDER.c + CHARGE_FEEDER.z5, abs=POSITION_ROUND_OFF)
        and z[-1] < 0
    )


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


CONTRACT_COLUMNS = (
    "t stage payload q_phi1 q_r2 q_phi3 q_phi4 v_phi1 v_r2 v_phi3 v_phi4 a_phi1 a_r2 a_phi3 "
    "a_phi4 projectile_x projectile_y projectile_z projectile_speed projectile_axis_x "
    "projectile_axis_y projectile_axis_z transmission_angle_deg closure_residual piston_force "
    "forearm_torque cylinder_frame_force piston_arm_force arm_frame_force forearm_joint_force "
    "forearm_joint_moment lagrange_piston_force lagrange_forearm_torque lagrange_lambda1 "
    "lagrange_lambda2 forward_q_phi3 forward_q_phi4 forward_closure_residual"
).split()
"""The cycle table's columns, typed from REFERENCE.md's contract."""


def test_cycle_command_writes_every_contract_column(tmp_path, capsys):
    assert main(["cycle", "--elevation", "30", "--out", str(tmp_path), "--rate", "500"]) == 0
    table = read_csv(tmp_path / "cycle.csv")
    for name in CONTRACT_COLUMNS:
        assert name in table, name
    figures = sorted(path.name for path in tmp_path.glob("*.png"))
    for number in ("04", "08", "10", "11", "12", "13", "14", "15"):
        assert any(name.startswith(f"fig{number}") for name in figures), number
    out = capsys.readouterr().out
    assert "peak piston_force" in out and "Lagrange equations vs Pinocchio" in out


def test_cycle_command_bad_elevation(tmp_path, capsys):
    assert main(["cycle", "--elevation", "-10", "--out", str(tmp_path)]) == 2
    assert "outside" in capsys.readouterr().err


@pytest.mark.parametrize(
    "arguments, message",
    [
        (["--elevation", "71"], "outside"),
        (["--elevation", "inf"], "finite"),
        (["--elevation", "10", "--html", "/nonexistent-folder/cycle.html"], "no directory"),
        (["--elevation", "10", "--port", "70000"], "port"),
    ],
)
def test_view_command_bad_input_exits_with_message(capsys, arguments, message):
    assert main(["view", *arguments]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


def test_view_command_busy_port(capsys):
    import socket

    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen()
        port = busy.getsockname()[1]
        assert main(["view", "--elevation", "10", "--port", str(port)]) == 2
    err = capsys.readouterr().err
    assert str(port) in err and "Traceback" not in err


def test_view_command_writes_html(tmp_path, capsys):
    page = tmp_path / "cycle.html"
    assert main(["view", "--elevation", "10", "--html", str(page)]) == 0
    assert page.stat().st_size > 500_000  # MeshCat's JavaScript is embedded: works offline
    assert "<script" in page.read_text(encoding="utf-8")[:2_000_000]


def test_published_parameter_table_is_current(capsys):
    assert main(["parameters"]) == 0
    printed = capsys.readouterr().out
    assert printed == (REPO / "PARAMETERS.md").read_text(encoding="utf-8"), (
        "run `feeder parameters --out PARAMETERS.md`"
    )
    for source in ("Table I", "assumed"):
        assert source in printed


def test_errata_command_writes_the_published_table(tmp_path, capsys):
    path = tmp_path / "ERRATA.md"
    assert main(["errata", "--out", str(path)]) == 0
    assert f"wrote {path}" in capsys.readouterr().out
    assert path.read_text(encoding="utf-8") == (REPO / "ERRATA.md").read_text(encoding="utf-8"), (
        "run `feeder errata --out ERRATA.md`"
    )


@pytest.mark.parametrize("command", ["cycle", "kinematics"])
def test_unwritable_output_folder_fails_before_computing(tmp_path, capsys, command):
    blocker = tmp_path / "a_file"
    blocker.write_text("")
    assert main([command, "--elevation", "0", "--out", str(blocker / "sub")]) == 2
    err = capsys.readouterr().err
    assert "cannot create the output folder" in err and "Traceback" not in err


@pytest.mark.parametrize(
    "command", [["urdf", "--out"], ["parameters", "--out"], ["errata", "--out"]]
)
def test_unwritable_urdf_and_parameter_outputs(tmp_path, capsys, command):
    blocker = tmp_path / "a_file"
    blocker.write_text("")
    assert main([*command, str(blocker / "sub" / "x")]) == 2
    assert "cannot write" in capsys.readouterr().err


def test_cycle_command_low_rate_forward_run_refused_or_skipped(tmp_path, capsys):
    """At 100 Hz the force-driven forward run cannot track the cycle: a clear error that names
    the remedy; with --no-forward the loads are written without the forward_* columns."""
    assert main(["cycle", "--elevation", "10", "--out", str(tmp_path), "--rate", "100"]) == 2
    err = capsys.readouterr().err
    assert "--no-forward" in err and "Traceback" not in err
    arguments = ["cycle", "--elevation", "10", "--out", str(tmp_path), "--rate", "100"]
    assert main([*arguments, "--no-forward"]) == 0
    table = read_csv(tmp_path / "cycle.csv")
    assert "piston_force" in table and "forward_q_phi3" not in table
    assert "forward run" in capsys.readouterr().out
