"""``feeder design optimize MODEL --design FILE``: the minimax pivot of a cylinder lifting a
lever found to 1e-6, and the written optimum read back by ``feeder analyze``."""

from __future__ import annotations

import csv
import json
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from scipy.optimize import brentq

from feeder.cli import main
from feeder.design import run_mechanism_optimization
from feeder.design.report import INTERRUPTED
from feeder.design.search import Search
from feeder.files import MANIFEST

from .lever import Lever

DESIGN = """\
[variables]
cylinder_pivot.x = {lower = 0.9, upper = 1.6}   # [m] the ground pivot A along x

[objective]
peak = "tau_cylinder_slide"
"""


def hand_optimum(lever: Lever) -> float:
    """The pivot position a* [m] that minimises max_k F(θ_k, a) over the motion's samples, from
    the closed form (tests/design/mechanism/lever.py) alone: a scan finds where the maximum is
    least and the samples that are largest on either side; brentq finds where their forces are
    equal; the
    check below makes sure it is a crossing that is the minimax (the two forces' slopes of
    opposite signs, every other sample below them)."""
    _, theta, _, acceleration = lever.motion()
    grid = np.linspace(0.9, 1.6, 1401)
    largest = np.array([lever.force(a, theta, acceleration).max() for a in grid])
    k = int(np.argmin(largest))
    left, right = grid[k - 5], grid[k + 5]
    i = int(np.argmax(lever.force(left, theta, acceleration)))  # the peak's sample left of it
    j = int(np.argmax(lever.force(right, theta, acceleration)))  # and right of it

    def gap(a: float) -> float:
        f = lever.force(a, theta, acceleration)
        return f[i] - f[j]

    root = brentq(gap, left, right, xtol=1e-14, rtol=1e-15)
    f = lever.force(root, theta, acceleration)
    others = np.delete(f, [i, j])
    assert others.max() < f[i] * (1 - 1e-4)  # the two samples are the maximum there
    h = 1e-6
    slopes = [(lever.force(root + h, theta, acceleration)[s] - lever.force(root - h, theta,
              acceleration)[s]) for s in (i, j)]  # fmt: skip
    assert slopes[0] * slopes[1] < 0.0  # a crossing of a rising and a falling peak
    return float(root)


def test_the_optimiser_finds_the_minimax_pivot_of_a_lever(tmp_path):
    lever = Lever()
    model, closures, motion, design = lever.write(tmp_path, DESIGN)
    optimum, _ = run_mechanism_optimization(
        model, closures, design, [motion], tmp_path / "out", workers=1, progress=False,
        figure=False,
    )  # fmt: skip
    expected = hand_optimum(lever)
    assert optimum.status == "converged"
    # 1e-6 relative in the variable (the goal): at a crossing of two peaks SLSQP's
    # Newton step on the two active constraints converges quadratically, and the runs agree
    # with the closed form to ~1e-13 (test below), far below what moves a* by 1e-6.
    assert optimum.best.x[0] == pytest.approx(expected, rel=1e-6)
    _, theta, _, acceleration = lever.motion()
    peak = lever.force(expected, theta, acceleration).max()
    assert optimum.value(optimum.best) == pytest.approx(peak, rel=1e-9)


def test_the_runs_follow_the_closed_form(tmp_path):
    """The lever's cylinder force from the pipeline against the closed form at every sample:
    the cylinder is massless, so the two agree to the solvers' round-off (1e-10: the loads'
    equations hold to 1e-9 of their largest term, measured 1.2e-13 here)."""
    from feeder.study.analyze import analyze

    lever = Lever(a=1.3)
    _, closures, motion, _ = lever.write(tmp_path, DESIGN)
    analysis = analyze(closures, motion)
    _, theta, _, acceleration = lever.motion()
    expected = lever.force(lever.a, theta, acceleration)
    tau = analysis.loads.actuators["cylinder_slide"]
    np.testing.assert_allclose(tau, expected, rtol=1e-10)


def _peaks(path) -> dict[str, float]:
    with open(path, encoding="utf-8", newline="") as handle:
        rows = list(csv.DictReader(handle))
    return {name: max(abs(float(row[name])) for row in rows) for name in rows[0]}


def test_the_written_optimum_gives_the_optimisers_peaks_in_feeder_analyze(tmp_path):
    lever = Lever()
    model, closures, motion, design = lever.write(tmp_path, DESIGN)
    out = tmp_path / "out"
    optimum, _ = run_mechanism_optimization(
        model, closures, design, [motion], out, workers=1, progress=False, figure=False
    )
    assert {"optimum.urdf", "optimum_mechanism.toml", "report.html"} <= {
        p.name for p in out.iterdir()
    }
    assert main(["analyze", str(out / "optimum.urdf"), "--closures",
                 str(out / "optimum_mechanism.toml"), "--motion", str(motion), "--out",
                 str(tmp_path / "check")]) == 0  # fmt: skip
    loads = _peaks(tmp_path / "check" / "loads.csv")
    with open(out / "optimum.csv", encoding="utf-8", newline="") as handle:
        table = {(r["kind"], r["name"]): r for r in csv.DictReader(handle)}
    # The same pipeline on the same numbers (the URDF writes every float's repr): equal to
    # round-off, the CSV's repr of each float read back exactly.
    for (kind, name), row in table.items():
        if kind == "peak" and name in loads:
            assert abs(float(row["after"])) == pytest.approx(loads[name], rel=1e-12, abs=1e-9)
    (variable,) = optimum.problem.space.variables
    assert float(table[("variable", variable.name)]["after"]) == optimum.best.x[0]
    # and the optimiser's own evaluation of that point (history) has the same objective
    with open(out / "history.csv", encoding="utf-8", newline="") as handle:
        history = [r for r in csv.DictReader(handle) if r["feasible"] == "1"]
    least = min(float(r["objective"]) for r in history)
    assert loads["tau_cylinder_slide"] == pytest.approx(least, rel=1e-12)


def test_a_second_run_on_the_folder_resumes_from_the_last_iterate(tmp_path):
    model, closures, motion, design = Lever().write(tmp_path, DESIGN)
    out = tmp_path / "out"
    first, _ = run_mechanism_optimization(
        model, closures, design, [motion], out, workers=1, progress=False, figure=False
    )
    again, _ = run_mechanism_optimization(
        model, closures, design, [motion], out, workers=1, progress=False, figure=False
    )
    with open(out / "history.csv", encoding="utf-8", newline="") as handle:
        stages = [row["stage"] for row in csv.DictReader(handle)]
    assert stages.count("reference") == 2 and "resumed" in stages
    # from the last iterate SLSQP stays at the optimum (to its convergence, ftol 1e-9)
    assert again.best.x[0] == pytest.approx(first.best.x[0], rel=1e-6)


def test_ctrl_c_writes_the_best_point_so_far_marked_as_such(tmp_path, monkeypatch):
    def interrupted(self, start, stage="local"):
        raise KeyboardInterrupt

    monkeypatch.setattr(Search, "local", interrupted)  # Ctrl-C as SLSQP begins
    model, closures, motion, design = Lever().write(tmp_path, DESIGN)
    out = tmp_path / "out"
    with pytest.raises(KeyboardInterrupt):
        run_mechanism_optimization(
            model, closures, design, [motion], out, workers=1, progress=False, figure=False
        )
    manifest = json.loads((out / MANIFEST).read_text(encoding="utf-8"))
    assert manifest["status"] == INTERRUPTED
    summary = (out / "summary.txt").read_text(encoding="utf-8")
    assert summary.startswith(f"status: {INTERRUPTED}")
    # the best so far is the model as given (the only point run), written as a model
    written = ET.parse(out / "optimum.urdf").getroot()
    pivot = written.find("joint[@name='cylinder_pivot']/origin").get("xyz")
    assert [float(v) for v in pivot.split()] == [1.0, -0.3, 0.0]
