"""``feeder design sensitivities``: the files, the manifest, the summary, and bad input refused
in one line before any folder is made."""

from __future__ import annotations

import argparse
import csv
import hashlib
import json

import pytest

from feeder.cli import main, parser
from feeder.design.tables import DETAIL_COLUMNS

COMMON = ["design", "sensitivities", "--rate", "100", "--workers", "1"]
"""100 Hz: each cycle ~15 ms, no sampling warning (tests/design/test_sensitivities.py)."""


def test_the_command_writes_the_tables_the_figure_the_summary_and_the_manifest(tmp_path, capsys):
    out = tmp_path / "sensitivities"
    arguments = ["--elevations", "-4", "70", "74", "--elevation", "30"]
    arguments += ["--parameter", "d3", "--parameter", "payload.mass", "--out", str(out)]
    assert main([*COMMON, *arguments]) == 0
    printed = capsys.readouterr().out
    assert "2 parameters (1 length, 1 mass): 27 cycles at 100 Hz" in printed  # 3 × (1 + 8)
    assert "envelope over ε = −4° … 70° (every 74°)" in printed
    assert printed.endswith(
        f"wrote sensitivities.csv, sensitivity_details.csv, summary.txt, sensitivities.png "
        f"in {out}\n"
    )
    manifest = json.loads((out / "feeder-run.json").read_text(encoding="utf-8"))
    assert manifest["complete"] and manifest["command"].startswith("feeder design sensitivities")
    assert manifest["parameters"] == ["d3", "payload.mass"]
    assert manifest["envelope_elevations_deg"] == [-4.0, 70.0]
    assert manifest["elevation_deg"] == 30.0 and manifest["cycles"] == 27
    assert sorted(manifest["files"]) == sorted(
        ["sensitivities.csv", "sensitivity_details.csv", "summary.txt", "sensitivities.png"]
    )
    for name, digest in manifest["files"].items():
        assert hashlib.sha256((out / name).read_bytes()).hexdigest() == digest
    assert (out / "summary.txt").read_text(encoding="utf-8") in printed
    assert (out / "sensitivities.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"

    with (out / "sensitivities.csv").open(encoding="utf-8") as handle:
        table = list(csv.DictReader(handle))
    assert [row["scope"] for row in table] == ["elevation"] * 17 + ["envelope"] * 17
    assert set(table[0]) >= {"d_d3", "d_payload.mass", "elasticity_d3", "time_s"}
    cap = next(r for r in table if r["scope"] == "envelope" and r["peak"] == "piston_force")
    assert cap["unit"] == "N" and cap["elevation_deg"] == "-4.0"
    # The elasticity is the derivative times p over the peak (p: d3 = 0.19 m).
    elasticity = float(cap["d_d3"]) * 0.19 / float(cap["value"])
    assert float(cap["elasticity_d3"]) == pytest.approx(elasticity, rel=1e-15)
    with (out / "sensitivity_details.csv").open(encoding="utf-8") as handle:
        details = list(csv.reader(handle))
    assert tuple(details[0]) == DETAIL_COLUMNS
    assert len(details) == 1 + 2 * 17 * 2
    assert {row[DETAIL_COLUMNS.index("status")] for row in details[1:]} == {"ok"}


@pytest.mark.parametrize(
    "arguments, message",
    [
        (["--elevation", "30", "--parameter", "L7"], "parameter 'L7' is not differentiable"),
        (["--elevations", "-10", "70", "2"], "-10"),
        (["--elevations", "-4", "80", "21"], "elevation 80°"),
        (["--elevations", "-4", "70", "0"], "step 0"),
        (["--elevations", "-4", "70", "-2"], "step -2"),
        (["--elevation", "30", "--step", "0"], "the relative step must be positive"),
        (["--elevation", "30", "--step=-1e-6"], "the relative step must be positive"),
        (["--out-of-place"], None),
        ([], "give an elevation range (--elevations), an elevation, or both"),
    ],
)
def test_bad_input_is_one_line_and_makes_no_folder(tmp_path, capsys, arguments, message):
    out = tmp_path / "out"
    if message is None:  # argparse's own refusal
        with pytest.raises(SystemExit):
            main([*COMMON, *arguments, "--out", str(out)])
        return
    assert main([*COMMON, *arguments, "--out", str(out)]) == 2
    error = capsys.readouterr().err
    assert error.count("\n") == 1 and error.startswith("feeder: error: ")
    assert message in error
    assert not out.exists()


def test_every_design_option_states_its_default_or_that_it_is_required(capsys):
    (commands,) = [a for a in parser()._actions if isinstance(a, argparse._SubParsersAction)]
    design = commands.choices["design"]
    (tasks,) = [a for a in design._actions if isinstance(a, argparse._SubParsersAction)]
    for name, task in tasks.choices.items():
        for action in task._actions:
            if action.option_strings and action.dest != "help":
                text = action.help % {"default": action.default}
                assert "default" in text or (action.required and "required" in text), name
    with pytest.raises(SystemExit) as info:
        main(["design", "sensitivities", "--help"])
    assert info.value.code == 0 and "--elevations START STOP STEP" in capsys.readouterr().out
