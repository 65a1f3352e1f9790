"""``feeder design optimize`` on the command line: the built-in design printed, a small run
with its files, and bad input refused in one line before any folder is made."""

from __future__ import annotations

import json

import pytest

from feeder.cli import main
from feeder.design.design_space import BUILT_IN, read_design
from feeder.device.builtin import PROJECTILE_FEEDER
from feeder.device.parameter_file import read_parameters

TWO = """[variables]
L1 = {lower = -0.56, upper = -0.40}
d3 = {lower = 0.15, upper = 0.23}

[fixed]
r2_min = 0.21
r2_max = 0.505
"""
"""Two free variables, the end stops fixed (tests/design/test_optimize.py)."""


def test_print_design_prints_the_built_in_design(capsys):
    assert main(["design", "optimize", "--print-design"]) == 0
    printed = capsys.readouterr().out
    assert printed == BUILT_IN
    space = read_design(None, PROJECTILE_FEEDER)
    assert [v.name for v in space.variables] == ["L1", "L2", "d3", "r2_min", "r2_max"]
    assert [v.loads for v in space.variables] == [True, True, True, False, False]
    assert space.band_deg == (40.0, 140.0) and space.max_stroke == 0.30 and not space.limits


def test_a_run_writes_its_files_on_two_workers(tmp_path, capsys):
    design = tmp_path / "two.toml"
    design.write_text(TWO, encoding="utf-8")
    out = tmp_path / "out"
    arguments = ["design", "optimize", "--design", str(design), "--elevations", "-4", "70", "74"]
    arguments += ["--rate", "100", "--workers", "2", "--samples", "4", "--out", str(out)]
    assert main(arguments) == 0
    printed = capsys.readouterr().out
    assert printed.startswith("status: converged\n")
    assert printed.splitlines()[1] == (
        "Minimise peak_pressure: peak_pressure (cylinder_cap_pressure or cylinder_rod_pressure), "
        "over ε = −4° … 70° (every 74°), 1 vehicle case, at 100 Hz."
    )
    names = "history.csv, optimum.toml, optimum.csv, summary.txt, optimum.png, sensitivities.csv"
    assert f"wrote {names}, sensitivity_details.csv in {out}\n" in printed
    assert (out / "optimum.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    manifest = json.loads((out / "feeder-run.json").read_text(encoding="utf-8"))
    assert manifest["command"].startswith("feeder design optimize --design")
    assert manifest["elevations_deg"] == [-4.0, 70.0]
    assert read_parameters(out / "optimum.toml").name == "projectile_optimum"


@pytest.mark.parametrize(
    "design, objective, message",
    [
        ("[variables]\nL1 = {lower = -0.40, upper = -0.56}\n", None, "lower -0.4 must be below"),
        (
            "[variables]\nd3 = {lower = 0.40, upper = 0.50}\n",
            None,
            "the bounds admit no geometry that meets the constraints",
        ),
        (
            "[variables]\nL1 = {lower = 0.30, upper = 0.40}\n",
            None,
            "misses swing_low (cylinder angle φ1 ≥ phi1_min)",
        ),
        ("[variables]\nd3 = {lower = -0.1, upper = 0.2}\n", None, "d3 must be positive"),
        (
            "[variables]\nL7 = {lower = 0.1, upper = 0.2}\n",
            None,
            "names 'L7', not a free parameter of the device: no such parameter",
        ),
        (
            "[variables]\nL1 = {lower = -0.6, upper = -0.4}\n"
            "[limits]\narm_frame_joint_force = 3500.0\n",
            None,
            "[limits] names 'arm_frame_joint_force', no peak of the sweep; did you mean "
            "'arm_frame_force'?",
        ),
        (None, "peak_nothing", "the objective 'peak_nothing' names no peak"),
        (None, "weighted:peak_pressure=-1", "weights must be positive"),
        (None, "weighted:peak_pressure", "each term of a weighted sum is NAME=WEIGHT"),
    ],
)
def test_bad_input_is_one_line_and_makes_no_folder(tmp_path, capsys, design, objective, message):
    out = tmp_path / "out"
    arguments = ["design", "optimize", "--rate", "100", "--out", str(out)]
    if design is not None:
        (tmp_path / "design.toml").write_text(design, encoding="utf-8")
        arguments += ["--design", str(tmp_path / "design.toml")]
    if objective is not None:
        arguments += ["--objective", objective]
    assert main(arguments) == 2
    error = capsys.readouterr().err
    assert error.count("\n") == 1 and error.startswith("feeder: error: ")
    assert message in error
    assert not out.exists()


def test_an_output_folder_is_required_unless_printing(capsys):
    assert main(["design", "optimize"]) == 2
    assert "give the output folder: --out DIR" in capsys.readouterr().err
