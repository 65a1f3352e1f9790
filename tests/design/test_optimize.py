"""``feeder design optimize`` on the projectile feeder with two free variables (L1 and d3, the
end stops fixed): the optimum against a brute-force grid computed here, the written parameter
file through an ordinary sweep, a limit on another peak, Ctrl-C and the resumed run."""

from __future__ import annotations

import csv
import json
import math
from dataclasses import replace

import numpy as np
import pytest

from feeder.cli import main
from feeder.design.differences import STEP_FACTOR
from feeder.design.optimize import run_optimization
from feeder.design.problem import DEFAULT_ELEVATIONS, DEFAULT_RATE, Problem
from feeder.device.builtin import PROJECTILE_FEEDER
from feeder.device.feeder import load_feeder
from feeder.device.loop import loop_state, transmission_angle
from feeder.device.parameter_file import read_parameters
from feeder.dynamics.cycle import cycle_dynamics
from feeder.exceptions import InputError
from feeder.motion.laws import CycleSpec
from feeder.study.grid import make_grid
from feeder.study.peaks import cycle_peaks
from feeder.study.sweep_folder import run_sweep
from feeder.study.sweep_table import read_sweep_table

SPEC = CycleSpec(rate=100.0)
"""100 Hz: 101 samples a 1 s stage (a peak missed by < 0.05 %, no warning), ~9 ms a cycle."""

ELEVATIONS = (-4.0, 30.0, 70.0)

R2_STOPS = (0.21, 0.505)
"""[m] The end stops, fixed: with the 10 mm clearance the travel's r2 must lie in
[0.22, 0.495] m, which binds L1 and d3 (the built-in design's constraints otherwise)."""

DESIGN = f"""
[variables]
L1 = {{lower = -0.56, upper = -0.40}}
d3 = {{lower = 0.15, upper = 0.23}}

[fixed]
r2_min = {R2_STOPS[0]}
r2_max = {R2_STOPS[1]}
"""

GRID = 21
"""Brute-force points per variable: 8 mm in L1, 4 mm in d3. The optimum lies where the two
end-stop constraints meet, at the tip of a thin feasible wedge, so a grid approaches it slowly
from above (measured: 21 × 21 is 3.8 % above it, 41 × 41 1.6 %): the optimiser, searching the
same feasible set continuously, must be no worse than any grid point."""

TRAVEL = np.linspace(0.0, math.radians(94.0), 2001)
"""[rad] The arm's travel from loading to ramming at −4°, where the constraints are checked."""

ROUND_OFF = 1e-12
"""Relative difference allowed between the optimiser's peaks and the sweep's of the written
file: the same parameters (read back from the same file) through the same cycle code, so equal
but for round-off."""


def pressure_peak(params) -> float:
    """max |cap or rod pressure| over ELEVATIONS [Pa], from direct cycle runs."""
    feeder = load_feeder(params)
    peaks = []
    for e in ELEVATIONS:
        found = {
            p.name: p.value
            for p in cycle_peaks(cycle_dynamics(feeder, math.radians(e), SPEC, forward=False))
        }
        peaks += [abs(found["cylinder_cap_pressure"]), abs(found["cylinder_rod_pressure"])]
    return max(peaks)


def meets_constraints(params, slack: float = 0.0) -> bool:
    """The built-in design's constraints, checked here from the loop's closed form: r2 10 mm
    inside the end stops, the transmission angle in [40°, 140°], φ1 within its swing."""
    q = loop_state(replace(params, r2_min=1e-3, r2_max=2.0), TRAVEL).q
    mu, phi1 = np.degrees(transmission_angle(q)), q[:, 0]
    return bool(
        q[:, 1].min() >= params.r2_min + 0.01 - slack
        and q[:, 1].max() <= params.r2_max - 0.01 + slack
        and mu.min() >= 40.0 - slack
        and mu.max() <= 140.0 + slack
        and params.phi1_min <= phi1.min()
        and phi1.max() <= params.phi1_max
    )


@pytest.fixture(scope="module")
def design_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("design") / "two.toml"
    path.write_text(DESIGN, encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def optimum(tmp_path_factory, design_file):
    out = tmp_path_factory.mktemp("optimum") / "out"
    result, paths = run_optimization(
        PROJECTILE_FEEDER, out, design=design_file, elevations_deg=ELEVATIONS, spec=SPEC,
        workers=1, progress=False, figure=False,
    )  # fmt: skip
    return result, out


def table(path) -> dict[tuple[str, str], dict[str, str]]:
    with path.open(encoding="utf-8") as handle:
        return {(row["kind"], row["name"]): row for row in csv.DictReader(handle)}


def test_the_optimum_is_no_worse_than_a_brute_force_grid(optimum):
    result, out = optimum
    assert result.status == "converged"
    written = read_parameters(out / "optimum.toml")
    assert meets_constraints(written, slack=1e-9)  # SLSQP meets active constraints to ~1e-13
    best = math.inf
    base = replace(PROJECTILE_FEEDER, r2_min=R2_STOPS[0], r2_max=R2_STOPS[1])
    for L1 in np.linspace(-0.56, -0.40, GRID):
        for d3 in np.linspace(0.15, 0.23, GRID):
            params = replace(base, L1=float(L1), d3=float(d3))
            if meets_constraints(params):
                best = min(best, pressure_peak(params))
    assert math.isfinite(best)
    assert pressure_peak(written) <= best
    assert float(table(out / "optimum.csv")[("objective", "peak_pressure")]["after"]) <= best


def test_the_written_file_through_a_sweep_gives_the_optimiser_s_peaks(optimum, tmp_path):
    result, out = optimum
    params = read_parameters(out / "optimum.toml")
    assert params.name == "projectile_optimum"
    grid = make_grid({params.name: params}, elevations_deg=ELEVATIONS, spec=SPEC)
    swept = run_sweep(grid, tmp_path / "sweep", workers=1, progress=False)
    rows, rejected = read_sweep_table(swept.table)
    assert not rejected and len(rows) == len(ELEVATIONS)
    reported = table(out / "optimum.csv")
    for (kind, name), row in reported.items():
        if kind != "peak":
            continue
        values = [float(r[name]) for r in rows]
        largest = max(values, key=abs)
        assert largest == pytest.approx(float(row["after"]), rel=ROUND_OFF, abs=0.0), name
    pressure = max(
        max(abs(float(r[q])) for r in rows)
        for q in ("cylinder_cap_pressure", "cylinder_rod_pressure")
    )
    assert pressure == pytest.approx(result.value(result.best), rel=ROUND_OFF)
    objective = reported[("objective", "peak_pressure")]
    assert float(objective["after"]) < float(objective["before"])  # the device as given: 1.73 MPa


def test_the_outputs_and_the_manifest(optimum):
    result, out = optimum
    manifest = json.loads((out / "feeder-run.json").read_text(encoding="utf-8"))
    assert manifest["complete"] and manifest["status"] == "converged"
    assert manifest["variables"] == ["L1", "d3"] and manifest["sample_rate_hz"] == 100.0
    assert set(manifest["files"]) == {
        "optimum.toml", "optimum.csv", "history.csv", "summary.txt", "sensitivities.csv",
        "sensitivity_details.csv",
    }  # fmt: skip
    summary = (out / "summary.txt").read_text(encoding="utf-8")
    assert summary.startswith("status: converged\n")
    rows = table(out / "optimum.csv")
    active = {
        name for (kind, name), row in rows.items() if kind == "constraint" and row["active"] == "1"
    }
    assert active  # the optimum lies on constraints: the peak falls as d3 grows
    for name in active:
        assert abs(float(rows[("constraint", name)]["after"])) < 1e-9  # met to ~1e-13 m
        assert float(rows[("constraint", name)]["multiplier"]) >= 0.0
    with (out / "history.csv").open(encoding="utf-8") as handle:
        history = list(csv.DictReader(handle))
    assert history[0]["stage"] == "reference" and history[-1]["stage"] == "local"
    assert [int(r["iteration"]) for r in history] == list(range(len(history)))
    with (out / "sensitivities.csv").open(encoding="utf-8") as handle:
        assert {"d_L1", "d_d3"} <= set(next(csv.reader(handle)))


def test_a_limit_on_another_peak_holds_at_the_optimum(optimum, design_file, tmp_path):
    unlimited, out = optimum
    free = float(table(out / "optimum.csv")[("peak", "mount_moment")]["after"])
    limit = round(0.99 * free, 1)  # [N·m] binds: the unlimited optimum exceeds it by 1 %
    design = tmp_path / "limited.toml"
    design.write_text(DESIGN + f"\n[limits]\nmount_moment = {limit}\n", encoding="utf-8")
    result, _ = run_optimization(
        PROJECTILE_FEEDER, tmp_path / "out", design=design, elevations_deg=ELEVATIONS, spec=SPEC,
        workers=1, progress=False, figure=False, sensitivities=False,
    )  # fmt: skip
    rows = table(tmp_path / "out" / "optimum.csv")
    # A constraint counts as met to 1e-8 of its scale (feeder.design.constraints.FEASIBLE).
    assert float(rows[("peak", "mount_moment")]["after"]) <= limit * (1.0 + 1e-8)
    assert rows[("constraint", "limit:mount_moment")]["active"] == "1"
    assert result.value(result.best) > unlimited.value(unlimited.best)  # the limit binds


def test_ctrl_c_leaves_the_best_so_far_and_the_next_run_resumes(
    design_file, tmp_path, monkeypatch
):
    out = tmp_path / "out"
    original = Problem.constraints_jacobian
    calls = []

    def interrupted(self, z):
        calls.append(1)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return original(self, z)

    monkeypatch.setattr(Problem, "constraints_jacobian", interrupted)
    arguments = dict(design=design_file, elevations_deg=ELEVATIONS, spec=SPEC, workers=1,
                     progress=False, figure=False, sensitivities=False)  # fmt: skip
    with pytest.raises(KeyboardInterrupt):
        run_optimization(PROJECTILE_FEEDER, out, **arguments)
    manifest = json.loads((out / "feeder-run.json").read_text(encoding="utf-8"))
    assert manifest["complete"] and manifest["status"] == "interrupted: best so far"
    assert (
        (out / "summary.txt")
        .read_text(encoding="utf-8")
        .startswith("status: interrupted: best so far\n")
    )
    with (out / "history.csv").open(encoding="utf-8") as handle:
        before = list(csv.DictReader(handle))
    best = min(float(r["objective"]) for r in before if r["feasible"] == "1")
    written = float(table(out / "optimum.csv")[("objective", "peak_pressure")]["after"])
    assert written == best
    assert pressure_peak(read_parameters(out / "optimum.toml")) == pytest.approx(
        best, rel=ROUND_OFF
    )

    monkeypatch.setattr(Problem, "constraints_jacobian", original)
    result, _ = run_optimization(PROJECTILE_FEEDER, out, **arguments)
    with (out / "history.csv").open(encoding="utf-8") as handle:
        after = list(csv.DictReader(handle))
    assert after[: len(before)] == before
    resumed = next(r for r in after[len(before) :] if r["stage"] == "resumed")
    last = next(r for r in reversed(before) if r["stage"] == "local")
    assert [resumed[v] for v in ("L1", "d3")] == [last[v] for v in ("L1", "d3")]
    assert not any(r["stage"] == "sample" for r in after[len(before) :])  # no global start again
    assert result.status == "converged"

    with pytest.raises(InputError, match="holds the history of another optimisation"):
        run_optimization(PROJECTILE_FEEDER, out, **arguments, objective="piston_force")


def test_a_grid_variant_may_not_change_a_variable(design_file, tmp_path):
    grid = tmp_path / "grid.toml"
    grid.write_text('[[variants]]\nname = "moved"\nL1 = -0.5\n', encoding="utf-8")
    with pytest.raises(InputError, match="grid variant 'moved' changes a variable"):
        run_optimization(PROJECTILE_FEEDER, tmp_path / "out", design=design_file, grid=grid)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(
    "elevations, message",
    [
        (["x"], r"elevation \[deg\] must be numeric, got the text 'x'"),
        ([], "at least one elevation"),
        ([-4.0, 75.0], "elevation 75° is outside the device's range"),
    ],
)
def test_bad_elevations_are_refused_before_any_folder(design_file, tmp_path, elevations, message):
    with pytest.raises(InputError, match=message):
        run_optimization(PROJECTILE_FEEDER, tmp_path / "out", design=design_file,
                         elevations_deg=elevations)  # fmt: skip
    assert not (tmp_path / "out").exists()


def test_defaults_are_documented(capsys):
    """``--help`` states the defaults that a run without a grid uses."""
    with pytest.raises(SystemExit) as info:
        main(["design", "optimize", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert info.value.code == 0
    start, stop, step = DEFAULT_ELEVATIONS
    assert f"(default: the grid's, else {start:g} {stop:g} {step:g})" in text
    assert f"[Hz] (default: the grid's, else {DEFAULT_RATE:g})" in text
    with pytest.raises(SystemExit):
        main(["design", "sensitivities", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    mantissa, exponent = f"{STEP_FACTOR:.2e}".split("e")
    assert f"(default: ε^(1/3) = {mantissa}e{int(exponent)} of max(|p|, 0.1 m or 1 kg)" in text


def test_the_multipliers_are_the_objective_s_rate_of_change(optimum, tmp_path):
    """Relaxing the end-stop clearance by δ relaxes both active end-stop constraints by δ: the
    objective falls by the integral of the sum of their multipliers over δ. Over δ = 0.1 mm the
    sum changes by ~0.1 %, so the secant equals the mean of the two runs' sums to the trapezoid
    rule's error (third order in δ) and the runs' convergence (1e-9 of 1.7 MPa over
    δ · 1.6e7 Pa/m: 1e-6); 1e-4 leaves a margin."""
    result, out = optimum
    step = 1e-4  # [m]
    design = tmp_path / "relaxed.toml"
    relaxed = f"\n[constraints]\nend_stop_clearance = {0.01 - step}\n"
    design.write_text(DESIGN + relaxed, encoding="utf-8")
    moved, _ = run_optimization(
        PROJECTILE_FEEDER, tmp_path / "out", design=design, elevations_deg=ELEVATIONS, spec=SPEC,
        workers=1, progress=False, figure=False, sensitivities=False,
    )  # fmt: skip
    names = ("end_stop_retracted", "end_stop_extended")
    sums = []
    for folder in (out, tmp_path / "out"):
        rows = table(folder / "optimum.csv")
        assert all(rows[("constraint", n)]["active"] == "1" for n in names)
        assert {rows[("constraint", n)]["multiplier_unit"] for n in names} == {"Pa per m"}
        sums.append(sum(float(rows[("constraint", n)]["multiplier"]) for n in names))
    secant = (result.value(result.best) - moved.value(moved.best)) / step
    assert secant == pytest.approx(sum(sums) / 2.0, rel=1e-4)


def test_a_weighted_objective_is_relative_to_the_device_as_given(design_file, tmp_path):
    goal = "weighted:peak_pressure=1,mount_moment=0.5"
    result, _ = run_optimization(
        PROJECTILE_FEEDER, tmp_path / "out", design=design_file, objective=goal,
        elevations_deg=ELEVATIONS, spec=SPEC, samples=4, workers=1, progress=False, figure=False,
        sensitivities=False,
    )  # fmt: skip
    rows = table(tmp_path / "out" / "optimum.csv")
    objective = rows[("objective", goal)]
    assert objective["unit"] == "" and float(objective["before"]) == pytest.approx(1.5, rel=1e-15)

    def peak(names, when):
        return max(abs(float(rows[("peak", name)][when])) for name in names)

    pressures = ("cylinder_cap_pressure", "cylinder_rod_pressure")
    pressure = peak(pressures, "after") / peak(pressures, "before")
    moment = peak(["mount_moment"], "after") / peak(["mount_moment"], "before")
    expected = pressure + 0.5 * moment
    assert float(objective["after"]) == pytest.approx(expected, rel=1e-14)  # sums of ratios
    assert float(objective["after"]) < 1.5
