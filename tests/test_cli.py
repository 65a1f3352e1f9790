"""Command line: outputs exist and follow the contract; bad input exits non-zero with a message."""

from __future__ import annotations

import argparse
import contextlib
import hashlib
import json
import math

import numpy as np
import pytest

from feeder.chain import read_spec
from feeder.cli import main, parser
from feeder.device.parameter_file import DIGITS
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


def test_kinematics_without_figures_writes_the_same_table_and_no_figure(tmp_path):
    """--no-figures: the table (byte for byte the one written with the figures) and the
    manifest, no PNG."""
    argv = ["kinematics", "--elevation", "30", "--rate", "200", "--out"]
    assert main([*argv, str(tmp_path / "all")]) == 0
    assert main([*argv, str(tmp_path / "table"), "--no-figures"]) == 0
    written = sorted(path.name for path in (tmp_path / "table").iterdir())
    assert written == ["cycle.csv", "feeder-run.json"]
    table = (tmp_path / "table" / "cycle.csv").read_bytes()
    assert table == (tmp_path / "all" / "cycle.csv").read_bytes()


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


def test_a_name_the_file_system_refuses_is_one_line(tmp_path, capsys):
    """An output folder whose name is longer than the file system allows (255 bytes on Linux):
    one line naming the cause and the path, exit status 1, no traceback."""
    out = tmp_path / ("a" * 300)
    argv = ["cycle", "--elevation", "30", "--rate", "100", "--no-forward", "--no-figures"]
    assert main([*argv, "--out", str(out)]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "File name too long" in err and "a" * 300 in err


@pytest.mark.parametrize("rate", ["13.7", "0.3"])
def test_a_rate_that_misses_the_cycle_end_is_refused(tmp_path, capsys, rate):
    argv = ["cycle", "--elevation", "30", "--rate", rate, "--no-forward", "--no-figures"]
    assert main([*argv, "--out", str(tmp_path / "run")]) == 2
    assert "does not divide the 4 s cycle" in capsys.readouterr().err
    assert not (tmp_path / "run").exists()


def test_a_rerun_does_not_overwrite_an_edited_table(tmp_path, capsys):
    """README: earlier outputs are replaced only if unchanged. An edited cycle.csv refuses the
    next run into that folder before it computes, and keeps the edit."""
    argv = ["cycle", "--elevation", "30", "--rate", "100", "--no-forward", "--no-figures"]
    out = tmp_path / "run"
    assert main([*argv, "--out", str(out)]) == 0
    (out / "cycle.csv").write_text("my edited table\n", encoding="utf-8")
    capsys.readouterr()
    assert main([*argv, "--out", str(out)]) == 2
    assert "cycle.csv, changed since the run that wrote it" in capsys.readouterr().err
    assert (out / "cycle.csv").read_text(encoding="utf-8") == "my edited table\n"


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


FOREIGN = {"cycle.csv": "t,x\n0,1\n", "README.md": "# feeder\n\nmine\n"}
"""Files a user owns: a run's table, a copy of a document."""


def test_view_html_replaces_only_a_page_it_wrote(tmp_path, capsys):
    """``--html`` writes a new page or replaces one that feeder view wrote (its marker); a
    run's cycle.csv or a user's document is refused and left as it was."""
    for name, text in FOREIGN.items():
        (tmp_path / name).write_text(text, encoding="utf-8")
        assert main(["view", "--elevation", "30", "--html", str(tmp_path / name)]) == 2
        err = capsys.readouterr().err
        assert "is not an HTML page that feeder view wrote" in err and "another name" in err
        assert (tmp_path / name).read_text(encoding="utf-8") == text
    page = tmp_path / "cycle.html"
    for _ in range(2):
        assert main(["view", "--elevation", "30", "--html", str(page)]) == 0
    from feeder.viz.viewer import PAGE_MARKER

    assert PAGE_MARKER in page.read_text(encoding="utf-8")[:4096]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["README.md", "cycle.csv", "cycle.html"]


def test_errata_out_replaces_only_a_table_it_wrote(tmp_path, capsys):
    own = tmp_path / "own.md"
    own.write_text("mine\n", encoding="utf-8")
    assert main(["errata", "--out", str(own)]) == 2
    assert "is not an errata table that feeder errata wrote" in capsys.readouterr().err
    assert own.read_text(encoding="utf-8") == "mine\n"
    table = tmp_path / "ERRATA.md"
    for _ in range(2):
        assert main(["errata", "--out", str(table)]) == 0
    assert table.read_text(encoding="utf-8") == (REPO / "ERRATA.md").read_text(encoding="utf-8")


@pytest.mark.parametrize("device", [[], ["--device", "projectile"]])
def test_urdf_out_replaces_only_urdf_files_it_wrote(tmp_path, capsys, device):
    """A user's own projectile_feeder.urdf in the folder is refused, and nothing is written;
    the URDF files that feeder urdf wrote are replaced."""
    mine = tmp_path / "projectile_feeder.urdf"
    mine.write_text('<robot name="mine"/>\n', encoding="utf-8")
    assert main(["urdf", "--out", str(tmp_path), *device]) == 2
    assert "is not a URDF file that feeder urdf wrote" in capsys.readouterr().err
    assert [p.name for p in tmp_path.iterdir()] == ["projectile_feeder.urdf"]
    assert mine.read_text(encoding="utf-8") == '<robot name="mine"/>\n'
    mine.unlink()
    for _ in range(2):
        assert main(["urdf", "--out", str(tmp_path), *device]) == 0
    shipped = (REPO / "urdf" / "projectile_feeder.urdf").read_text(encoding="utf-8")
    assert mine.read_text(encoding="utf-8") == shipped


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


# -- issue 11: every option once, every command's defaults stated, nothing created on failure --


@pytest.mark.parametrize(
    "arguments",
    [
        ["cycle", "--elevation", "10", "--elevation", "20", "--out", "{out}"],
        ["cycle", "--elevation", "10", "--out", "{out}", "--rate", "500", "--rate", "1000"],
        ["cycle", "--elevation", "10", "--out", "{out}", "--no-forward", "--no-forward"],
        ["cycle", "--elevation", "10", "--out", "{out}", "--out", "{out}2"],
        [
            "kinematics",
            "--elevation",
            "10",
            "--out",
            "{out}",
            "--device",
            "charge",
            "--device",
            "charge",
        ],
        ["view", "--elevation", "10", "--port", "8000", "--port", "8001"],
        ["view", "--elevation", "10", "--html", "{out}.html", "--html", "{out}2.html"],
        ["parameters", "--format", "toml", "--format", "markdown"],
        ["urdf", "--out", "{out}", "--out", "{out}2"],
        ["errata", "--out", "{out}", "--out", "{out}2"],
    ],
    ids=lambda a: " ".join(x for x in a if x.startswith("--") or x.isalpha()),
)
def test_repeated_option_is_refused(tmp_path, capsys, arguments):
    """argparse would keep the last value (``--elevation 10 --elevation 20`` ran at 20°)."""
    out = str(tmp_path / "out")
    with pytest.raises(SystemExit) as info:
        main([a.replace("{out}", out) for a in arguments])
    assert info.value.code == 2
    assert "given twice" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "arguments",
    [
        ["cycle", "--elevation", "10", "--out", ""],
        ["kinematics", "--elevation", "10", "--out", " "],
        ["view", "--elevation", "10", "--html", ""],
        ["parameters", "--out", ""],
        ["errata", "--out", ""],
        ["urdf", "--out", ""],
        ["cycle", "--elevation", "10", "--out", "x", "--params", ""],
    ],
)
def test_empty_path_is_refused(tmp_path, monkeypatch, capsys, arguments):
    """``--out ""`` used to write into the current folder."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as info:
        main(arguments)
    assert info.value.code == 2
    assert "empty" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "arguments, message",
    [
        (["--elevation", "80"], "outside"),
        (["--elevation", "10", "--rate", "nan"], "finite"),
        (["--elevation", "10", "--rate", "-5"], "positive"),
        (["--elevation", "10", "--params", "missing.toml"], "not found"),
        (["--elevation", "10", "--rate", "100"], "--no-forward"),  # fails after computing
    ],
)
def test_failed_run_creates_no_output_folder(tmp_path, monkeypatch, capsys, arguments, message):
    monkeypatch.chdir(tmp_path)
    assert main(["cycle", "--out", "results", *arguments]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    assert list(tmp_path.iterdir()) == []


def test_folder_of_other_files_is_refused(tmp_path, capsys):
    (tmp_path / "thesis.tex").write_text("mine")
    assert main(["kinematics", "--elevation", "10", "--out", str(tmp_path), "--rate", "50"]) == 2
    assert "no feeder run wrote" in capsys.readouterr().err
    assert [p.name for p in tmp_path.iterdir()] == ["thesis.tex"]


def test_reused_folder_holds_only_the_last_runs_outputs(tmp_path):
    """A cycle run writes 13 figures, a kinematics run 2: after both, the folder holds the
    kinematics outputs and its manifest, nothing of the first run."""
    out = tmp_path / "results"
    common = ["--elevation", "10", "--out", str(out), "--rate", "100"]
    assert main(["cycle", *common, "--no-forward"]) == 0
    first = json.loads((out / "feeder-run.json").read_text(encoding="utf-8"))
    assert len(first["files"]) == 14
    assert main(["kinematics", *common]) == 0
    second = json.loads((out / "feeder-run.json").read_text(encoding="utf-8"))
    assert second["complete"] and second["command"].startswith("feeder kinematics")
    assert sorted(p.name for p in out.iterdir()) == sorted([*second["files"], "feeder-run.json"])
    assert len(second["files"]) == 3
    for name, digest in second["files"].items():
        assert hashlib.sha256((out / name).read_bytes()).hexdigest() == digest
    assert "forward_q_phi3" not in read_csv(out / "cycle.csv")  # the kinematic table


def parser_actions(parser):
    """(sub-command name, action) for every option of every sub-command."""
    (commands,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    for name, sub in commands.choices.items():
        for action in sub._actions:
            if action.option_strings and action.dest != "help":
                yield name, action


def test_every_option_states_its_default_or_that_it_is_required():
    for name, action in parser_actions(parser()):
        text = action.help % {"default": action.default}
        assert "default" in text or (action.required and "required" in text), (name, action)


@pytest.mark.parametrize(
    "command", ["cycle", "kinematics", "view", "parameters", "urdf", "errata"]
)
def test_help_prints_and_writes_nothing(tmp_path, monkeypatch, capsys, command):
    """``--help`` once wrote a file named ``--help`` (feeder.errata)."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as info:
        main([command, "--help"])
    assert info.value.code == 0
    assert "default" in capsys.readouterr().out
    assert list(tmp_path.iterdir()) == []


def test_cycle_help_states_the_default_and_minimum_rate(capsys):
    with pytest.raises(SystemExit):
        main(["cycle", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "(default: 1000)" in text and "≥ 500 Hz" in text and "--no-forward" in text


def test_unknown_device_in_view_is_an_argparse_error(capsys):
    with pytest.raises(SystemExit) as info:
        main(["view", "--elevation", "10", "--device", "mortar"])
    assert info.value.code == 2 and "mortar" in capsys.readouterr().err


def test_device_and_params_are_exclusive(tmp_path, capsys):
    with pytest.raises(SystemExit) as info:
        main(["parameters", "--device", "charge", "--params", str(tmp_path / "p.toml")])
    assert info.value.code == 2 and "not allowed with" in capsys.readouterr().err


# -- issue 11: the parameter file on every command --


@pytest.fixture
def heavier_file(tmp_path):
    """``feeder parameters --format toml`` output with the payload 8.7 kg heavier."""
    path = tmp_path / "edited.toml"
    assert main(["parameters", "--format", "toml", "--out", str(path)]) == 0
    text = path.read_text(encoding="utf-8")
    assert text.count("\nmass = 43.5  # [kg]\n") == 1
    path.write_text(text.replace("\nmass = 43.5  #", "\nmass = 52.2  #"), encoding="utf-8")
    return path


HEAVIER_KG = 52.2 - 43.5
STATIC_MOMENT_ROUND_OFF = 1e-9
"""[N·m] Moments of ~1e2–1e3 N·m from the inverse dynamics at a rest instant, differenced:
round-off of the solves (~1e-12 relative), far below a gram of payload (~1e-3 N·m)."""


def test_params_file_changes_the_cycle_results(tmp_path, heavier_file):
    """``feeder cycle --params edited.toml`` runs the edited device. Independent check: at the
    rest instant t = 2 s (v = a = 0, payload gripped) the arm is in static balance about its
    pivot A, so the extra payload weight's moment about A is carried by the pin force alone:
    Δ[(P − A) × F_pin]_z = Δm g (x_payload − x_A)."""
    from feeder.device import PROJECTILE_FEEDER as p

    runs = {}
    for name, extra in (("builtin", []), ("edited", ["--params", str(heavier_file)])):
        out = tmp_path / name
        assert (
            main(["cycle", "--elevation", "30", "--out", str(out), "--rate", "500", *extra]) == 0
        )
        runs[name] = read_csv(out / "cycle.csv")
        runs[name + "_manifest"] = json.loads((out / "feeder-run.json").read_text("utf-8"))
    base, heavy = runs["builtin"], runs["edited"]
    assert (
        runs["builtin_manifest"]["parameters_sha256"]
        != (runs["edited_manifest"]["parameters_sha256"])
    )
    # The same motion: the file gives the lengths back to DIGITS relative (≤ 1e-12 m on lengths
    # under 1 m; the angles through degrees to a few ulp), and the motion follows them to that
    # order (measured: 6e-17).
    for name in ("q_phi1", "q_r2", "q_phi3", "q_phi4", "projectile_x"):
        np.testing.assert_allclose(heavy[name], base[name], rtol=0, atol=DIGITS, err_msg=name)
    k = int(np.flatnonzero(base["t"] == 2.0)[0])

    def pin_moment(table):
        phi3 = table["q_phi3"][k]
        lever = p.d3 * np.array([math.cos(phi3), math.sin(phi3)])  # P − A
        force = np.array([table["piston_arm_force_x"][k], table["piston_arm_force_y"][k]])
        return lever[0] * force[1] - lever[1] * force[0]

    weight_moment = HEAVIER_KG * 9.81 * (base["projectile_x"][k] - p.L1)
    assert pin_moment(heavy) - pin_moment(base) == pytest.approx(
        weight_moment, abs=STATIC_MOMENT_ROUND_OFF
    )
    assert abs(weight_moment) > 10.0  # the check is not trivially zero


def test_params_file_on_every_other_command(tmp_path, capsys, heavier_file):
    from feeder.device.parameter_file import parameters_sha256, read_parameters

    params = ["--params", str(heavier_file)]
    out = tmp_path / "k"
    assert (
        main(["kinematics", "--elevation", "30", "--out", str(out), "--rate", "50", *params]) == 0
    )
    manifest = json.loads((out / "feeder-run.json").read_text(encoding="utf-8"))
    assert manifest["parameters_sha256"] == parameters_sha256(read_parameters(heavier_file))
    assert main(["parameters", *params]) == 0
    assert "| payload.mass | 52.2 | kg |" in capsys.readouterr().out
    assert main(["urdf", "--out", str(tmp_path), *params]) == 0
    assert '<mass value="52.2" />' in (tmp_path / "projectile_feeder.urdf").read_text()
    capsys.readouterr()
    assert main(["parameters", "--format", "toml", *params]) == 0
    assert capsys.readouterr().out == heavier_file.read_text(encoding="utf-8")
    page = tmp_path / "view.html"
    assert main(["view", "--elevation", "30", "--html", str(page), *params]) == 0
    assert page.stat().st_size > 500_000


def test_bad_params_file_names_the_field(tmp_path, capsys, heavier_file):
    text = heavier_file.read_text(encoding="utf-8").replace("d3 = 0.19", 'd3 = "0.19"')
    heavier_file.write_text(text, encoding="utf-8")
    out = tmp_path / "results"
    arguments = ["cycle", "--elevation", "10", "--out", str(out), "--params", str(heavier_file)]
    assert main(arguments) == 2
    err = capsys.readouterr().err
    assert "d3 must be a number [m]" in err and str(heavier_file) in err
    assert not out.exists()


def test_a_parameter_set_name_cannot_lead_outside_the_urdf_folder(tmp_path, capsys):
    """A name that is a path is refused where the file is read: nothing is written anywhere."""
    assert main(["parameters", "--format", "toml", "--out", str(tmp_path / "p.toml")]) == 0
    path = tmp_path / "p.toml"
    path.write_text(
        path.read_text(encoding="utf-8").replace('name = "projectile"', 'name = "../../x"'),
        encoding="utf-8",
    )
    inner = tmp_path / "w" / "a" / "inner"
    assert main(["urdf", "--out", str(inner), "--params", str(path)]) == 2
    err = capsys.readouterr().err
    assert "name must be letters, digits" in err and str(path) in err
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["p.toml"]


def test_urdf_writes_only_inside_its_folder(tmp_path, capsys, monkeypatch):
    """A parameter set whose name is a path (possible in Python, e.g. a retrofit's name, not in
    a file: the reader is replaced here) cannot make feeder urdf write outside --out."""
    import dataclasses

    from feeder.device import PROJECTILE_FEEDER, parameter_file

    escaped = dataclasses.replace(PROJECTILE_FEEDER, name="../x")
    monkeypatch.setattr(parameter_file, "read_parameters", lambda path: escaped)
    inner = tmp_path / "w" / "inner"
    assert main(["urdf", "--out", str(inner), "--params", str(tmp_path / "p.toml")]) == 2
    assert "is not a file name in" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_parameters_out_replaces_only_a_table_it_wrote(tmp_path, capsys, heavier_file):
    """A Markdown table that feeder parameters wrote is replaced (PARAMETERS.md is regenerated
    so); a user's file or an edited parameter file (TOML) is refused and left as it was."""
    table = tmp_path / "table.md"
    for arguments in (["--device", "charge"], ["--params", str(heavier_file)], []):
        assert main(["parameters", *arguments, "--out", str(table)]) == 0
    assert table.read_text(encoding="utf-8") == (REPO / "PARAMETERS.md").read_text("utf-8")
    notes = tmp_path / "notes.md"
    notes.write_text("# Parameters\n\nmine\n", encoding="utf-8")
    edited = heavier_file.read_text(encoding="utf-8")
    for target, format_ in (
        (notes, "markdown"),
        (heavier_file, "toml"),
        (heavier_file, "markdown"),
        (tmp_path, "toml"),
    ):
        capsys.readouterr()
        assert main(["parameters", "--format", format_, "--out", str(target)]) == 2
        err = capsys.readouterr().err
        assert "is not a file that feeder parameters wrote" in err, err
        assert "another name" in err, err
    assert notes.read_text(encoding="utf-8") == "# Parameters\n\nmine\n"
    assert heavier_file.read_text(encoding="utf-8") == edited


def test_parameters_out_replaces_an_unedited_parameter_file_it_wrote(
    tmp_path, capsys, heavier_file
):
    """``--format toml --out q.toml`` twice: the second run replaces the file the first wrote
    (another device's file too); a copy of an edited file, written again, also."""
    from feeder.device.builtin import CHARGE_FEEDER
    from feeder.device.parameter_file import parameters_toml

    path = tmp_path / "q.toml"
    for _ in range(2):
        assert main(["parameters", "--format", "toml", "--out", str(path)]) == 0
    assert main(["parameters", "--format", "toml", "--device", "charge", "--out", str(path)]) == 0
    assert path.read_text(encoding="utf-8") == parameters_toml(CHARGE_FEEDER)
    assert main(["parameters", "--out", str(path)]) == 0  # the same command, as a table
    assert path.read_text(encoding="utf-8") == (REPO / "PARAMETERS.md").read_text("utf-8")
    copy = tmp_path / "copy.toml"
    for _ in range(2):
        arguments = ["--format", "toml", "--params", str(heavier_file), "--out", str(copy)]
        assert main(["parameters", *arguments]) == 0
    assert copy.read_text(encoding="utf-8") == heavier_file.read_text(encoding="utf-8")


def test_urdf_of_one_device(tmp_path):
    assert main(["urdf", "--out", str(tmp_path / "new"), "--device", "charge"]) == 0
    assert [p.name for p in (tmp_path / "new").iterdir()] == ["charge_feeder.urdf"]
    shipped = (REPO / "urdf" / "charge_feeder.urdf").read_text()
    assert (tmp_path / "new" / "charge_feeder.urdf").read_text() == shipped


EXAMPLE = REPO / "examples" / "four_bar"


def test_analyze_check_prints_the_mobility_report(capsys):
    arguments = [str(EXAMPLE / "four_bar.urdf"), "--closures", str(EXAMPLE / "closures.toml")]
    assert main(["analyze", *arguments, "--check"]) == 0
    out = capsys.readouterr().out
    assert "actual mobility 3 − 2 = 1" in out and "admissible independent joints" in out


def test_analyze_check_refuses_what_it_would_ignore(tmp_path, capsys):
    """--check computes and writes nothing: an --out or --motion beside it is refused, not
    silently dropped."""
    arguments = [str(EXAMPLE / "four_bar.urdf"), "--closures", str(EXAMPLE / "closures.toml")]
    out = ["--out", str(tmp_path / "o")]
    assert main(["analyze", *arguments, "--check", *out]) == 2
    assert "leave out --out" in capsys.readouterr().err
    motion = ["--motion", str(EXAMPLE / "motion.csv")]
    assert main(["analyze", *arguments, "--check", *motion, *out]) == 2
    assert "leave out --motion, --out" in capsys.readouterr().err
    assert main(["analyze", *arguments, "--check", "--no-figures"]) == 2
    assert "leave out --no-figures" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


FOLDED_DEAD_CENTRE = {
    "crank_joint": 4.037257447447691,
    "coupler_joint": 3.141592653589793,
    "rocker_joint": 2.2459278597319257,
}
"""The example four-bar's folded dead centre (coupler folded back onto the crank), closed to
2e-15 m: Newton over the crank and rocker with the coupler at π."""


def test_analyze_check_is_a_gate_for_scripts(tmp_path, capsys):
    """The four-bar driven from its rocker, mounted at its folded dead centre: --check prints the
    report, says in one line that the independent joints cannot drive the mechanism, and exits
    with status 2, as ``analyze`` of any motion then does; the help says so."""
    folder = REPO / "examples" / "four_bar"
    pose = ", ".join(f"{name} = {value!r}" for name, value in FOLDED_DEAD_CENTRE.items())
    (tmp_path / "rocker.toml").write_text(
        f'[mechanism]\nurdf = "{folder / "four_bar.urdf"}"\nactuated = ["rocker_joint"]\n'
        f'independent = ["rocker_joint"]\ngravity = [0.0, -9.81, 0.0]\npose = {{{pose}}}\n\n'
        '[[closure]]\nframes = ["coupler_tip", "rocker_tip"]\ntype = "revolute"\n',
        encoding="utf-8",
    )
    arguments = [str(folder / "four_bar.urdf"), "--closures", str(tmp_path / "rocker.toml")]
    assert main(["analyze", *arguments, "--check"]) == 2
    captured = capsys.readouterr()
    assert "with independent ['rocker_joint']: the closure does not determine" in captured.out
    (error,) = [line for line in captured.err.splitlines() if "error" in line]
    assert error.startswith("feeder: error: the independent joints ['rocker_joint'] cannot drive")
    assert "mount from one nearer it with --pose FILE" in error  # what to do about it
    with pytest.raises(SystemExit):
        main(["analyze", "--help"])
    assert "exit status 0 when the independent joints drive" in " ".join(
        capsys.readouterr().out.split()
    )


def test_analyze_check_passes_a_mechanism_whose_free_freedom_moves_mass(tmp_path, capsys):
    """The 5-bar export with one motor of its two: the other arm is free and moves mass, so
    ``analyze --motion`` integrates it (a hybrid run); --check names it and exits with 0."""
    cad = REPO / "examples" / "cad" / "5bar_linkage"
    side = (cad / "robot.yaml").read_text(encoding="utf-8")
    assert "name_mot: ['mot1', 'mot2']" in side
    (tmp_path / "robot.yaml").write_text(side.replace("['mot1', 'mot2']", "['mot1']"))
    arguments = [str(cad / "robot.urdf"), "--closures", str(tmp_path / "robot.yaml"), "--check"]
    assert main(["analyze", *arguments]) == 0
    out = capsys.readouterr().out
    assert "with independent ['mot1']: the closure does not determine" in out
    assert "1 freedom(s) left free move mass (" in out and "a hybrid run" in out


def test_analyze_reads_a_cad_export_as_shipped(tmp_path, capsys):
    """The Cassie-like leg from its Extended-URDF side-file: mobility with its two idle rod spins
    and the assembled pose (--check), then its motion's loads and the pose written."""
    cad = REPO / "examples" / "cad"
    arguments = [str(cad / "cassie_like" / "robot.urdf")]
    arguments += ["--closures", str(cad / "cassie_like" / "robot.yaml")]
    assert main(["analyze", *arguments, "--check"]) == 0
    out = capsys.readouterr().out
    assert "determined up to 2 idle motion(s)" in out and "assembled pose" in out
    folder = tmp_path / "cassie"
    extra = ["--motion", str(cad / "cassie_like_motion.csv"), "--out", str(folder)]
    assert main(["analyze", *arguments, *extra]) == 0
    table = read_csv(folder / "loads.csv")
    assert "tau_motor_ankle" in table and "q_tarsus_half_hachil_rode_rev2" in table
    pose = (folder / "assembled_pose.csv").read_text(encoding="utf-8").splitlines()
    assert pose[0] == "joint,coordinate,value" and len(pose) == 1 + 19
    assert "2 idle motion(s)" in (folder / "summary.txt").read_text(encoding="utf-8")


def test_an_implausible_body_is_a_one_line_warning(capsys):
    """The 5-bar export's 654-tonne sphere: the run goes on, the terminal gets one line naming
    the link (not Python's warning with a source line)."""
    cad = REPO / "examples" / "cad" / "5bar_linkage"
    arguments = [str(cad / "robot.urdf"), "--closures", str(cad / "robot.yaml"), "--check"]
    assert main(["analyze", *arguments]) == 0
    err = capsys.readouterr().err
    assert "feeder: warning:" in err and "(links sphere) weighs 654498 kg" in err
    assert "build_model(" not in err


def test_analyze_writes_the_loads_table_and_figures(tmp_path, capsys):
    out = tmp_path / "four_bar"
    arguments = [str(EXAMPLE / "four_bar.urdf"), "--closures", str(EXAMPLE / "closures.toml")]
    arguments += ["--motion", str(EXAMPLE / "motion.csv"), "--out", str(out)]
    assert main(["analyze", *arguments]) == 0
    table = read_csv(out / "loads.csv")
    assert table["t"].size == 101 and "tau_crank_joint" in table
    assert "peak actuator load crank_joint" in (out / "summary.txt").read_text(encoding="utf-8")
    for name in ("actuator_loads.png", "joint_reactions.png", "closure_forces.png"):
        assert (out / name).stat().st_size > 10_000
    assert "wrote" in capsys.readouterr().out


@pytest.mark.parametrize(
    "extra, message",
    [
        ([], "give --motion FILE and --out DIR"),
        (["--motion", "missing.csv", "--out", "x"], "motion file not found"),
    ],
)
def test_analyze_bad_input_exits_with_message(tmp_path, capsys, extra, message):
    arguments = [str(EXAMPLE / "four_bar.urdf"), "--closures", str(EXAMPLE / "closures.toml")]
    extra = [str(tmp_path / x) if x.endswith((".csv", "x")) and x != "--out" else x for x in extra]
    assert main(["analyze", *arguments, *extra]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    assert not (tmp_path / "x").exists()  # a failed analysis creates no output folder


SQUEEZER = REPO / "examples" / "andrews_squeezer"


def test_simulate_runs_the_squeezer_from_its_two_files(tmp_path, capsys):
    """``feeder simulate`` on the shipped URDF and mechanism file is the whole run: the published
    state at t = 0.03 s (checked more tightly in tests/chain/test_andrews_squeezer.py), the
    table, the summary with the drift and energy balance, the figures and the manifest."""
    import json
    import tomllib

    out = tmp_path / "squeezer"
    arguments = [str(SQUEEZER / "andrews_squeezer.urdf"), "--closures"]
    arguments += [str(SQUEEZER / "squeezer.toml"), "--duration", "0.03", "--out", str(out)]
    assert main(["simulate", *arguments, "--samples", "31"]) == 0
    table = read_csv(out / "states.csv")
    reference = tomllib.loads((SQUEEZER / "reference.toml").read_text(encoding="utf-8"))
    beta = reference["final"]["q"][0]
    # the default tolerances (rtol 1e-8) give q(0.03) to ~1e-9 relative (measured 9e-10)
    assert table["t"].size == 31 and abs(table["q_beta"][-1] - beta) <= 1e-8 * abs(beta)
    for column in ("spring_D_body3_C_ground_force", "F_body2_F_body3_force_x", "energy_balance"):
        assert column in table
    summary = (out / "summary.txt").read_text(encoding="utf-8")
    assert "energy balance" in summary and "largest drift" in summary
    manifest = json.loads((out / "feeder-run.json").read_text(encoding="utf-8"))
    assert manifest["integrator"]["method"] == "DOP853"
    for name in ("motion.png", "energy_balance.png", "force_elements.png"):
        assert (out / name).stat().st_size > 10_000
    assert "wrote" in capsys.readouterr().out


def test_simulate_runs_a_mechanism_on_a_moving_base(tmp_path, capsys):
    """The four-bar with a ``[base]`` (a slope and a terrain ride): ``feeder simulate`` runs it
    on the moving base (issue 31; it used to refuse), the table has the mount's columns and the
    base's work, the summary names the base and closes the absolute motion's energy balance
    with the base's work to the integrator's tolerance (rtol 1e-8 on energies of ~0.1 J;
    measured 2e-10 J)."""
    text = (EXAMPLE / "closures.toml").read_text(encoding="utf-8")
    base = '\n[base]\nroll_deg = 5.0\n\n[[base.profile]]\ntype = "terrain"\nheave = 0.04\n'
    (tmp_path / "closures.toml").write_text(text + base, encoding="utf-8")
    out = tmp_path / "run"
    arguments = [str(EXAMPLE / "four_bar.urdf"), "--closures", str(tmp_path / "closures.toml")]
    extra = ["--duration", "0.5", "--samples", "26", "--no-figures", "--out", str(out)]
    assert main(["simulate", *arguments, *extra]) == 0
    table = read_csv(out / "states.csv")
    for axes in ("", "_vehicle"):
        for what in ("force", "moment"):
            assert all(f"mount_{what}{axes}_{k}" in table for k in "xyz")
    assert table["mount_force_y"].min() > 1.0  # the support carries the weight (up is +y)
    assert np.abs(table["base_work"]).max() > 1e-4  # the ride does work on the mechanism
    assert np.abs(table["energy_balance"]).max() <= 1e-6
    summary = (out / "summary.txt").read_text(encoding="utf-8")
    assert "base: slope: pitch 0°, roll 5°; terrain: heave ±40 mm" in summary
    assert "max |E − E(0) − W − W_B|" in summary
    assert "wrote" in capsys.readouterr().out


def test_a_cad_export_without_its_meshes_is_run_and_drawn(tmp_path, capsys):
    """Battobot's export ships no STL files: ``simulate`` and ``analyze`` write their tables,
    figures and report page (the bodies a stick figure), and the terminal gets one warning line
    naming the missing meshes — no error after the computation, no matplotlib warning."""
    cad = REPO / "examples" / "cad" / "battobot_6d"
    arguments = [str(cad / "robot.urdf"), "--closures", str(cad / "robot.yaml")]
    run = tmp_path / "run"
    extra = ["--duration", "0.02", "--samples", "5", "--out", str(run)]
    assert main(["simulate", *arguments, *extra]) == 0
    states = read_csv(run / "states.csv")
    assert states["t"].size == 5
    motion = ["t"] + [f"q_{name}" for name in read_spec(cad / "robot.yaml").independent]
    rows = np.column_stack([states[name] for name in motion])  # the run's motion, analysed
    lines = [",".join(motion), *(",".join(f"{x:.17g}" for x in row) for row in rows)]
    (tmp_path / "motion.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")
    loads = tmp_path / "loads"
    extra = ["--motion", str(tmp_path / "motion.csv"), "--out", str(loads)]
    assert main(["analyze", *arguments, *extra]) == 0
    err = capsys.readouterr().err
    ours = [line for line in err.splitlines() if line.startswith("feeder:")]
    assert len(ours) == 2, err  # one warning per command
    for line in ours:
        assert line.startswith("feeder: warning:") and "35 mesh file(s) not found" in line
        assert "package:///hip_z_axis_transmission.stl" in line
    assert "UserWarning" not in err  # matplotlib's "Tight layout not applied" among them
    for folder in (run, loads):
        page = (folder / "report.html").read_text(encoding="utf-8")
        assert "bodies as a stick figure (their mesh files are missing or unusable)" in page
        assert (folder / "joint_reactions.png").stat().st_size > 10_000


def test_simulate_into_a_dead_centre_names_the_time_to_stop_before(tmp_path, capsys):
    """The released delta reaches a dead centre at t ≈ 0.050 s: with ``--singular stop``,
    ``--duration 0.05`` stops where its loads can no longer be computed (t = 0.0429 s) and says
    to end the run before it — once an error without a time, after the whole run — and the
    duration it names runs."""
    cad = REPO / "examples" / "cad" / "robot_delta"
    arguments = [str(cad / "robot.urdf"), "--closures", str(cad / "robot.yaml"), "--singular",
                 "stop"]  # fmt: skip
    out = ["--out", str(tmp_path / "delta")]
    assert main(["simulate", *arguments, "--duration", "0.05", "--samples", "5", *out]) == 2
    err = capsys.readouterr().err
    assert "singular pose" in err and "at t = 0.0429" in err and "Traceback" not in err
    before = err.split("end the run before t = ")[1].split(" s")[0]
    assert not (tmp_path / "delta").exists()
    assert main(["simulate", *arguments, "--duration", before, "--samples", "5", *out]) == 0
    assert read_csv(tmp_path / "delta" / "states.csv")["t"][-1] == float(before)


def test_simulate_passes_a_dead_centre_by_default_flagging_its_loads(tmp_path, capsys):
    """By default the undriven delta passes its dead centre (the closure's rank drops from 9 to
    8 at t ≈ 0.050 s, where the two links of its third rod line up): the summary lists the
    instant with the ranks, and the samples whose loads are indeterminate there are flagged in
    states.csv (their loads 0), the others solved."""
    cad = REPO / "examples" / "cad" / "robot_delta"
    arguments = [str(cad / "robot.urdf"), "--closures", str(cad / "robot.yaml")]
    out = tmp_path / "delta"
    assert main(["simulate", *arguments, "--duration", "0.06", "--samples", "61",
                 "--out", str(out)]) == 0  # fmt: skip
    text = capsys.readouterr().out
    assert "singular positions passed: 1" in text and "closure rank 9 → 8 → 9" in text
    passed = float(text.split("singular positions passed: 1")[1].split("t = ")[1].split(" s")[0])
    table = read_csv(out / "states.csv")
    flagged = table["loads_indeterminate"] == 1.0
    # the samples flagged are those around the instant, the others are not
    assert flagged.any() and not flagged.all()
    assert table["t"][flagged].min() <= passed <= table["t"][flagged].max()
    assert np.all(np.isfinite(table["energy_balance"]))


def test_simulate_drives_the_boom_lift_by_its_cylinder_s_push(tmp_path, capsys):
    """``feeder simulate`` on examples/boom_lift: the boom's hinge is not actuated, the
    ``[[control]]`` table drives it by the cylinder element's push. Standing on its reference
    until the raise begins (t = 0.5 s), the push is the statics by hand: the boom's weight
    moment m g 1.5 m over the cylinder's lever g = n · (ẑ × p) at 0 rad (the bracket p =
    (1.2, −0.1) m, the base (0.5, −0.6) m), all of it in the cap chamber, p = push / (π D²/4)."""
    folder = REPO / "examples" / "boom_lift"
    arguments = [str(folder / "boom_lift.urdf"), "--closures", str(folder / "closures.toml")]
    out = tmp_path / "run"
    extra = ["--duration", "1.0", "--samples", "21", "--no-figures"]
    assert main(["simulate", *arguments, "--out", str(out), *extra]) == 0
    table = read_csv(out / "states.csv")
    gap, bracket = np.array([0.7, 0.5]), np.array([1.2, -0.1])
    lever = gap @ np.array([-bracket[1], bracket[0]]) / np.linalg.norm(gap)  # [m]
    push = 200.0 * 9.81 * 1.5 / lever  # [N]
    standing = table["t"] <= 0.5
    # the run stands on its reference to the default integrator's tolerance (1e-12 rad), whose
    # feedback K_p e I_O / g moves the push of ~3.8 kN by ~1e-11 of it (measured 1.5e-10 with
    # the rate's): 1e-8; the cap's pressure likewise, the rod side at zero gauge
    np.testing.assert_allclose(table["command_boom_hinge"][standing], push, rtol=1e-8)
    np.testing.assert_allclose(
        table["cap_pressure_boom_hinge"][standing], push / (math.pi * 0.05**2 / 4.0), rtol=1e-8
    )
    assert np.all(table["rod_pressure_boom_hinge"] == 0.0)  # it pushes all along
    # the run's loads carry the push applied: the cylinder's tension is −push standing (its
    # damper idle), and the hinge holds the boom against its weight and the push along the
    # cylinder, F = (0, m g) − push n with n the cylinder's axis (gravity along −y)
    np.testing.assert_allclose(table["lift_cylinder_force"][standing], -push, rtol=1e-8)
    hinge = np.array([0.0, 200.0 * 9.81]) - push * gap / np.linalg.norm(gap)
    np.testing.assert_allclose(
        table["boom_hinge_force"][standing], np.linalg.norm(hinge), rtol=1e-8
    )
    # the raise through a 10 Hz valve's lag: an error of 3e-4 rad (measured over 4 s)
    assert np.abs(table["error_boom_hinge"]).max() <= 1e-3
    summary = (out / "summary.txt").read_text(encoding="utf-8")
    assert "control of 'boom_hinge' by the push of 'lift_cylinder': peak error" in summary
    assert "peak cap pressure" in summary and "peak rod pressure 0 MPa" in summary


def test_simulate_drives_a_joint_under_control_from_a_control_file(tmp_path, capsys):
    """``feeder simulate --control FILE``: the four-bar's crank driven toward its motion table
    from rest (an initial rate error of 2π rad/s); states.csv has the controller's columns and
    summary.txt its peak and RMS error and the time saturated; a bad table is one line."""
    control = tmp_path / "control.toml"
    reference = (EXAMPLE / "motion.csv").as_posix()
    control.write_text(
        f'[[control]]\njoint = "crank_joint"\nreference = "{reference}"\nomega = 30\n'
        "force_limit = 0.1\n",
        encoding="utf-8",
    )
    arguments = [str(EXAMPLE / "four_bar.urdf"), "--closures", str(EXAMPLE / "closures.toml")]
    out = tmp_path / "run"
    extra = ["--control", str(control), "--duration", "0.5", "--samples", "51", "--no-figures"]
    assert main(["simulate", *arguments, "--out", str(out), *extra]) == 0
    table = read_csv(out / "states.csv")
    for name in ("q_ref", "v_ref", "error", "error_rate", "demand", "command", "saturated"):
        assert f"{name}_crank_joint" in table
    summary = (out / "summary.txt").read_text(encoding="utf-8")
    assert "control of 'crank_joint': peak error" in summary and "RMS error" in summary
    # at rest against a 2π rad/s reference the start asks more than 0.1 N·m (0.13 measured)
    saturated = table["saturated_crank_joint"] == 1.0
    assert saturated[0] and np.abs(table["tau_crank_joint"]).max() <= 0.1 * (1.0 + 1e-9)
    assert "saturated 0 s" not in summary and "% of the run), from t = 0 s" in summary
    # the error's closed loop (ω = 30 rad/s, ζ = 1) leaves e^(−15) of the start's by 0.5 s
    assert abs(table["error_crank_joint"][-1]) <= 1e-3 * np.abs(table["error_crank_joint"]).max()
    control.write_text('[[control]]\njoint = "crank"\nreference = "x.csv"\nomega = 1\n')
    (tmp_path / "x.csv").write_text("t,q_crank\n0,0\n0.5,0\n1,0\n", encoding="utf-8")
    assert main(["simulate", *arguments, "--out", str(tmp_path / "bad"), *extra]) == 2
    err = capsys.readouterr().err
    assert "is not actuated; did you mean 'crank_joint'?" in err and err.count("\n") == 1
    assert not (tmp_path / "bad").exists()


@pytest.mark.parametrize(
    "extra, message",
    [
        (["--duration", "-1"], "duration must be > 0"),
        (["--duration", "0.1", "--rtol", "0"], "rtol must be > 0"),
        (["--duration", "0.1", "--forces", "missing.toml"], "force file not found"),
        (["--duration", "0.1", "--samples", "1"], "samples must be"),
    ],
)
def test_simulate_bad_input_exits_with_message(tmp_path, capsys, extra, message):
    arguments = [str(EXAMPLE / "four_bar.urdf"), "--closures", str(EXAMPLE / "closures.toml")]
    extra = [str(tmp_path / x) if x.endswith(".toml") else x for x in extra]
    assert main(["simulate", *arguments, "--out", str(tmp_path / "x"), *extra]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    assert not (tmp_path / "x").exists()


@pytest.mark.parametrize("duration", ["1e9", "1e308"])
def test_simulate_of_a_long_duration_stops_at_the_step_cap(
    tmp_path, capsys, monkeypatch, duration
):
    """``--duration 1e9`` (or 1e308) once never answered: the run stops at the cap of steps
    (made small here, so that the stop comes from the cap, not from the test's patience) with
    one line naming the time reached, and writes nothing."""
    from feeder.chain.dynamics import budget

    monkeypatch.setattr(budget, "MAX_STEPS", 300)
    arguments = [str(EXAMPLE / "four_bar.urdf"), "--closures", str(EXAMPLE / "closures.toml")]
    out = ["--out", str(tmp_path / "x")]
    assert main(["simulate", *arguments, "--duration", duration, *out]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert f"of {float(duration):g} s: it reached the cap of 300 integration steps" in err
    assert "end it by t = " in err and not (tmp_path / "x").exists()


def test_simulate_of_more_samples_than_the_cap_is_refused(tmp_path, capsys):
    """``--samples 10000000`` once never answered (hours of post-processing, 40 GB): refused
    before the run, naming the count and the cap."""
    from feeder.chain.dynamics.budget import max_samples

    cap = max_samples(3)  # the four-bar's three coordinates
    assert cap < 10_000_000
    arguments = [str(EXAMPLE / "four_bar.urdf"), "--closures", str(EXAMPLE / "closures.toml")]
    extra = ["--duration", "1", "--samples", "10000000", "--out", str(tmp_path / "x")]
    assert main(["simulate", *arguments, *extra]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert f"10000000 output samples (samples) are more than the {cap}" in err
    assert f"ask for at most {cap}" in err and not (tmp_path / "x").exists()


def test_simulate_names_a_stiff_damper_and_radau_runs_it(tmp_path, capsys):
    """A damper of 1e6 N·s/m on the four-bar holds DOP853's steps at ~25 µs: one warning line
    names it and says ``--method Radau``, which runs the same motion without the warning."""
    text = (EXAMPLE / "closures.toml").read_text(encoding="utf-8")
    damper = '[[force]]\ntype = "spring"\nframes = ["ground", "rocker_tip"]\ndamping = 1e6\n'
    (tmp_path / "damped.toml").write_text(f"{text}\n{damper}", encoding="utf-8")
    arguments = [str(EXAMPLE / "four_bar.urdf"), "--closures", str(tmp_path / "damped.toml")]
    arguments += ["--duration", "0.02", "--samples", "5"]
    assert main(["simulate", *arguments, "--out", str(tmp_path / "dop")]) == 0
    warned = [line for line in capsys.readouterr().err.splitlines() if "stiff" in line]
    assert len(warned) == 1 and warned[0].startswith("feeder: warning: the run is stiff")
    assert "spring:ground-rocker_tip" in warned[0] and "--method Radau" in warned[0]
    radau = ["--method", "Radau", "--out", str(tmp_path / "radau")]
    assert main(["simulate", *arguments, *radau]) == 0
    assert "stiff" not in capsys.readouterr().err
    explicit = read_csv(tmp_path / "dop" / "states.csv")["q_crank_joint"]
    implicit = read_csv(tmp_path / "radau" / "states.csv")["q_crank_joint"]
    np.testing.assert_allclose(implicit, explicit, rtol=0.0, atol=1e-9)  # rtol 1e-8 of ~0.3 rad


def test_simulate_help_states_the_caps(capsys):
    from feeder.chain.dynamics.budget import MAX_STEPS, SAMPLE_BYTES, SAMPLE_MEMORY

    with pytest.raises(SystemExit):
        main(["simulate", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert f"a run stops after {MAX_STEPS} integration steps" in text
    assert f"at most {SAMPLE_MEMORY // SAMPLE_BYTES} divided by the mechanism's velocity" in text
    assert "progress line" in text and "stiff" in text


def test_sweep_command_follows_the_output_folder_rule(tmp_path, capsys):
    """A folder of other files is refused (docs/ with its tracked figure); a sweep's own folder
    is resumed (and says what it kept), and any feeder run takes it over."""
    docs = tmp_path / "docs"
    docs.mkdir()
    (docs / "sweep_projectile.png").write_text("tracked", encoding="utf-8")
    sweep = ["sweep", "--elevations", "60", "70", "10", "--workers", "1"]
    assert main([*sweep, "--out", str(docs)]) == 2
    assert "no feeder run wrote" in capsys.readouterr().err
    assert [p.name for p in docs.iterdir()] == ["sweep_projectile.png"]
    assert (docs / "sweep_projectile.png").read_text(encoding="utf-8") == "tracked"
    out = tmp_path / "sweep"
    assert main([*sweep, "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "2 cases: 0 kept from the earlier table, 2 computed" in printed
    assert f"wrote sweep_peaks.csv and 1 figure in {out}\n" in printed
    sweep[2] = "50"
    assert main([*sweep, "--out", str(out), "--no-figures"]) == 0
    printed = capsys.readouterr().out
    assert "3 cases: 2 kept from the earlier table, 1 computed" in printed
    table = (out / "sweep_peaks.csv").read_text(encoding="utf-8").splitlines()
    assert len(table) == 4  # a header and the three elevations
    assert sorted(p.name for p in out.iterdir()) == ["feeder-run.json", "sweep_peaks.csv"]
    cycle = ["cycle", "--elevation", "10", "--rate", "100", "--no-forward", "--no-figures"]
    assert main([*cycle, "--out", str(out)]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["cycle.csv", "feeder-run.json"]


def test_a_misspelt_command_gets_the_nearest_one(capsys):
    assert main(["simualte", "model.urdf"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "did you mean `feeder simulate`?" in err
    assert main(["xyzzy"]) == 2
    assert "did you mean" not in capsys.readouterr().err


def test_analyze_says_an_assumed_gravity_in_the_manifest_and_warns_it_does_no_work(
    tmp_path, capsys
):
    folder = REPO / "examples" / "four_bar"
    text = (folder / "closures.toml").read_text()
    lines = [line for line in text.splitlines() if not line.startswith("gravity")]
    (tmp_path / "closures.toml").write_text("\n".join(lines) + "\n")
    out = tmp_path / "out"
    code = main(
        ["analyze", str(folder / "four_bar.urdf"), "--closures", str(tmp_path / "closures.toml"),
         "--motion", str(folder / "motion.csv"), "--out", str(out)]
    )  # fmt: skip
    assert code == 0
    assert "feeder: warning: gravity [0.0, 0.0, -9.81] m/s² (assumed" in capsys.readouterr().err
    manifest = json.loads((out / "feeder-run.json").read_text(encoding="utf-8"))
    assert manifest["gravity"] == {"value": [0.0, 0.0, -9.81], "assumed": True}
    assert "(assumed: the mechanism file gives no gravity" in (out / "summary.txt").read_text()


@pytest.mark.parametrize("command", ["simulate", "analyze"])
def test_no_figures_writes_the_table_summary_and_manifest_only(tmp_path, capsys, command):
    """``--no-figures`` as on ``feeder cycle``: no PNG, no report.html; the table, the summary,
    the pose, the indeterminate columns and the manifest, which lists exactly those."""
    import json

    out = tmp_path / "out"
    arguments = [str(EXAMPLE / "four_bar.urdf"), "--closures", str(EXAMPLE / "closures.toml")]
    if command == "simulate":
        extra = ["--duration", "0.02", "--samples", "5", "--rate", "crank_joint=2"]
    else:
        extra = ["--motion", str(EXAMPLE / "motion.csv")]
    assert main([command, *arguments, *extra, "--out", str(out), "--no-figures"]) == 0
    table = "states.csv" if command == "simulate" else "loads.csv"
    names = {table, "summary.txt", "assembled_pose.csv", "indeterminate.txt", "feeder-run.json"}
    assert {path.name for path in out.iterdir()} == names
    manifest = json.loads((out / "feeder-run.json").read_text(encoding="utf-8"))
    assert set(manifest["files"]) == names - {"feeder-run.json"}
    assert "and 0 figures" in capsys.readouterr().out
    if command == "simulate":
        assert manifest["initial_rates"]["given"] == {"crank_joint": 2.0}
        assert read_csv(out / table)["v_crank_joint"][0] == pytest.approx(2.0, abs=1e-12)


@pytest.mark.parametrize(
    "rates, message",
    [
        (["--rate", "crank_joint"], "expected JOINT=VALUE"),
        (["--rate", "crank_joint=fast"], "must be a finite number"),
        (["--rate", "crank_joint=inf"], "must be a finite number"),
        (["--rate", "crank=1"], "did you mean 'crank_joint'"),
        (["--rate", "crank_joint=1", "--rate", "crank_joint=2"], "given twice"),
    ],
)
def test_simulate_bad_rates_exit_with_one_line(tmp_path, capsys, rates, message):
    """A malformed --rate is argparse's error (usage and one line), a joint the model lacks or
    one given twice the command's one line; either exits with status 2 and writes nothing."""
    arguments = [str(EXAMPLE / "four_bar.urdf"), "--closures", str(EXAMPLE / "closures.toml")]
    extra = ["--duration", "0.02", "--out", str(tmp_path / "x"), *rates]
    try:
        code = main(["simulate", *arguments, *extra])
    except SystemExit as exc:  # argparse's refusal
        code = exc.code
    assert code == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    assert not (tmp_path / "x").exists()


def test_analyze_of_a_passive_mechanism_asks_for_actuated_joints(tmp_path, capsys):
    text = (EXAMPLE / "closures.toml").read_text(encoding="utf-8")
    (tmp_path / "closures.toml").write_text(
        text.replace('actuated = ["crank_joint"]', "actuated = []"), encoding="utf-8"
    )
    arguments = [str(EXAMPLE / "four_bar.urdf"), "--closures", str(tmp_path / "closures.toml")]
    extra = ["--motion", str(EXAMPLE / "motion.csv"), "--out", str(tmp_path / "x")]
    assert main(["analyze", *arguments, *extra]) == 2
    err = capsys.readouterr().err
    assert "the motion's loads need actuated joints" in err and "feeder simulate" in err
    assert not (tmp_path / "x").exists()


@pytest.mark.parametrize(
    ("options", "message"),
    [
        (["--forward", "controlled", "--no-forward"], "contradict"),
        (["--bandwidth", "8"], "add --forward controlled"),
        (["--drive-bandwidth", "20"], "add --forward controlled"),
        (["--forward", "controlled", "--bandwidth", "0"], "bandwidth_hz must be a positive"),
        (["--forward", "controlled", "--drive-bandwidth", "-3"], "actuator_hz must be a positive"),
        (["--forward", "rule"], "invalid choice"),
    ],
)
def test_controlled_run_options_are_refused_in_one_line(tmp_path, capsys, options, message):
    """Each refused before the run, the output folder not created."""
    out = tmp_path / "run"
    with pytest.raises(SystemExit) if "invalid" in message else contextlib.nullcontext():
        assert main(["cycle", "--elevation", "30", "--out", str(out), *options]) == 2
    assert message in capsys.readouterr().err
    assert not out.exists()


def test_controlled_cycle_on_a_rocking_hull(tmp_path, capsys):
    """``--forward controlled`` on a moving base: the table gains the controlled_* columns (the
    force-rule's forward_* are not there: one forward run), the figure of the loading error is
    written, the summary gives the loading pose and the gains, the manifest the servo."""
    argv = ["cycle", "--elevation", "70", "--rate", "100", "--forward", "controlled"]
    argv += ["--base-motion", "recoil:start=3", "--bandwidth", "8", "--out", str(tmp_path)]
    assert main(argv) == 0
    table = read_csv(tmp_path / "cycle.csv")
    assert not any(name.startswith("forward_") for name in table)
    # the run follows the prescribed cycle closely but not exactly: the hull rocks
    error = np.abs(table["controlled_q_phi3"] - table["q_phi3"]).max()
    assert 0.0 < error < 1e-2
    assert table["controlled_cylinder_saturated"].max() == 0
    cap = table["controlled_piston_force"] / (math.pi * 0.05**2 / 4.0)  # the 50 mm bore
    np.testing.assert_allclose(
        table["controlled_cylinder_cap_pressure"], np.maximum(cap, 0.0), rtol=1e-12
    )
    assert (tmp_path / "loading_error.png").stat().st_size > 10_000
    out = capsys.readouterr().out
    assert "controlled run (position loops 8 Hz" in out and "rammer's line" in out
    manifest = json.loads((tmp_path / "feeder-run.json").read_text(encoding="utf-8"))
    assert "8 Hz" in json.dumps(manifest)
