"""Benchmark of the whole job: ``feeder cycle`` cold, each of its steps, and sweeps.

Prints each figure against its goal (issue 12) with PASS or MISS, and writes every figure to a
JSON file so that two runs can be compared (``--compare old.json`` prints the ratios). Times
are the best of several runs (the least disturbed by other processes); the per-sample costs are
also given as multiples of one bare ``pinocchio.constraintDynamics`` call measured in the same
run, which survive a busy or slower machine better than seconds do.

Figures:

* ``cycle_cold_cli``: ``feeder cycle --elevation -4`` as a user runs it (a fresh interpreter,
  every figure), wall time [s], median of ``--cold-runs`` runs; goal ≤ 0.8 s.
* ``cycle_cold_job``: the same job as a short script, without the command line's checks,
  output folder, manifest and summary (figures drawn by :class:`feeder.viz.report.
  FigureWorkers` started before the study, as the command line does), [s].
* ``cycle_cold_no_figures``: the job without figures (``--no-figures``), [s].
* The steps in one process: imports (numpy + Pinocchio, feeder, matplotlib), model,
  kinematics, inverse dynamics, reactions, forward run, Lagrange equations, CSV, figures.
* ``kinematics_calls``: the cycle's kinematics per sample, in bare calls; goal ≤ 1.
* ``inverse_calls`` (loads + every reaction) goal ≤ 3; ``forward_calls`` per step goal ≤ 6;
  ``lagrange_ratio`` (closed form / Pinocchio loads) goal < 0.1.
* ``sweep75_wall``: the 75-elevation sweep (−4° … 70°, loads and reactions, no forward run)
  on every local core, wall [s]; goal ≤ 1.0 s on 2 cores.
* ``sweep_cases_per_core_second``: throughput of a ``--sweep-cases`` sweep (10 000 by
  default: elevations × payload-mass variants × both devices), cases per second per core.

Run: ``python benchmarks/bench_cycle.py`` (a few minutes; ``--quick`` for a short run);
``--help`` lists the options.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from datetime import UTC, datetime
from pathlib import Path

GOALS = {
    "cycle_cold_cli": ("≤", 0.8, "s"),
    "cycle_cold_job": ("≤", 0.8, "s"),
    "kinematics_calls": ("≤", 1.0, "calls/sample"),
    "inverse_calls": ("≤", 3.0, "calls/sample"),
    "forward_calls": ("≤", 6.0, "calls/step"),
    "lagrange_ratio": ("<", 0.1, ""),
    "sweep75_wall": ("≤", 1.0, "s"),
}
"""Figure → (comparison, goal, unit): issue 12's goals and the earlier benchmark's targets."""

ELEVATION_DEG = -4.0
"""The main study's elevation: the longest arm travel."""

JOB = """
import math, sys
from pathlib import Path
from feeder.viz.report import FigureData, FigureWorkers, study_figure_names
with FigureWorkers(None if {draw} else 1) as figures:
    from feeder.device.feeder import load_feeder
    from feeder.study.csv import write_csv
    from feeder.study.cycle_study import run_cycle_study
    out = Path(sys.argv[1])
    out.mkdir(parents=True)
    study = run_cycle_study(load_feeder("projectile"), math.radians({elevation}))
    write_csv(out / "cycle.csv", study.columns())
    if {draw}:
        writers = figures.writers(FigureData.of_study(study), study_figure_names())
        for name, write in writers.items():
            write(out / name)
    print(study.summary())
"""
"""The cycle job as a script, as the command line runs it: figure workers started before the
study (they import matplotlib meanwhile), the table written while they draw."""


def best_time(function: Callable[[], object], repeats: int, calls: int = 1) -> float:
    """Smallest wall time [s] of one call, over ``repeats`` timings of ``calls`` calls each."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(calls):
            function()
        times.append((time.perf_counter() - start) / calls)
    return min(times)


def fresh_environment() -> dict[str, str]:
    """This environment, but with Python's bytecode cache on, as on a user's machine (pip
    compiles an installed package; a sandbox's PYTHONDONTWRITEBYTECODE would recompile every
    module at every start, ~0.1 s)."""
    return {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}


def cold_runs(command: list[str], runs: int, folder: Path) -> float:
    """Median wall time [s] of ``runs`` fresh processes of ``command`` + an output folder,
    after one run that fills the bytecode cache."""
    times = []
    for k in range(runs + 1):
        out = Path(tempfile.mkdtemp(dir=folder)) / "out"
        start = time.perf_counter()
        subprocess.run(
            [*command, str(out)], check=True, capture_output=True, env=fresh_environment()
        )
        if k:
            times.append(time.perf_counter() - start)
    return statistics.median(times)


def import_time(modules: str, runs: int) -> float:
    """Best wall time [s] of a fresh interpreter importing ``modules``, less a bare one's."""

    def fresh(code: str) -> float:
        start = time.perf_counter()
        subprocess.run([sys.executable, "-c", code], check=True, env=fresh_environment())
        return time.perf_counter() - start

    bare = min(fresh("pass") for _ in range(runs))
    return min(fresh(f"import {modules}") for _ in range(runs)) - bare


def measure_cold(figures: dict, runs: int, folder: Path) -> None:
    script = Path(sys.executable).with_name("feeder")
    cli = [str(script)] if script.exists() else [sys.executable, "-m", "feeder"]
    cycle = [*cli, "cycle", "--elevation", str(ELEVATION_DEG), "--out"]
    figures["cycle_cold_cli"] = cold_runs(cycle, runs, folder)
    for name, draw in (("cycle_cold_job", True), ("cycle_cold_no_figures", False)):
        code = JOB.format(elevation=ELEVATION_DEG, draw=draw)
        figures[name] = cold_runs([sys.executable, "-c", code], runs, folder)
    figures["import_numpy_pinocchio"] = import_time("numpy, pinocchio", runs)
    figures["import_feeder_study"] = import_time("feeder.study.cycle_study", runs)
    figures["import_matplotlib"] = import_time(
        "matplotlib.figure, matplotlib.backends.backend_agg", runs
    )


def measure_steps(figures: dict, repeats: int, folder: Path) -> None:
    """Each step of the job in this process, and the bare call that scales them."""
    import numpy as np
    import pinocchio as pin

    from feeder.device.feeder import load_feeder
    from feeder.dynamics import (
        FeederDynamics,
        ForceRule,
        actuator_loads,
        check_cycle_motion,
        pin_reactions,
        simulate_feeder,
    )
    from feeder.motion.cycle import feeding_cycle
    from feeder.paper import lagrange_loads
    from feeder.study.csv import write_csv
    from feeder.study.cycle_study import run_cycle_study
    from feeder.viz.png import png_bytes
    from feeder.viz.report import FigureData, draw, study_figure_names

    elevation = math.radians(ELEVATION_DEG)
    figures["model"] = best_time(lambda: load_feeder("projectile"), repeats)
    feeder = load_feeder("projectile")
    kin = feeding_cycle(feeder, elevation)
    n = kin.t.size
    dyn = FeederDynamics(feeder)
    motion = check_cycle_motion(dyn, kin.q, kin.v, kin.a, kin.gripped)
    loads = actuator_loads(dyn, motion)
    case = dyn.cases[1]
    q, v, tau = (dyn.to_pinocchio(x) for x in (kin.q, kin.v, loads.generalized_forces()))

    def bare_calls() -> None:
        for k in range(n):
            pin.constraintDynamics(
                case.model,
                case.data,
                q[k],
                v[k],
                tau[k],
                case.constraint_models,
                case.constraint_datas,
                case.prox,
            )

    call = best_time(bare_calls, repeats) / n
    rule = ForceRule(kin.t, kin.stage, kin.gripped, loads.piston_force, loads.forearm_torque)
    hand = (feeder.params, kin.q, kin.v, kin.a, kin.gripped)
    figures["samples"] = n
    figures["bare_call_us"] = call * 1e6
    # the payload's path is computed when first read: cycle.csv reads it
    figures["kinematics"] = best_time(
        lambda: feeding_cycle(feeder, elevation).payload_position, repeats
    )
    figures["inverse_dynamics"] = best_time(lambda: actuator_loads(dyn, motion), repeats)
    figures["reactions"] = best_time(lambda: pin_reactions(dyn, loads), repeats)
    figures["forward"] = best_time(lambda: simulate_feeder(dyn, rule, kin.q[0], kin.v[0]), repeats)
    figures["lagrange"] = best_time(lambda: lagrange_loads(*hand), repeats, calls=20)
    figures["kinematics_calls"] = figures["kinematics"] / n / call
    figures["inverse_calls"] = (figures["inverse_dynamics"] + figures["reactions"]) / n / call
    figures["forward_calls"] = figures["forward"] / (n - 1) / call
    figures["lagrange_ratio"] = figures["lagrange"] / figures["inverse_dynamics"]
    study = run_cycle_study(feeder, elevation)
    columns = study.columns()
    figures["csv"] = best_time(lambda: write_csv(folder / "cycle.csv", columns), repeats)
    data = FigureData.of_study(study)
    names = study_figure_names()
    for name in names:  # the first drawing loads fonts and caches: not the steady cost
        png_bytes(draw(name, data))
    figures["figures_serial"] = best_time(
        lambda: [png_bytes(draw(name, data)) for name in names], max(1, repeats // 3)
    )
    figures["figure_count"] = len(names)
    largest = np.abs(study.lagrange.piston_force - loads.piston_force).max()
    figures["lagrange_piston_force_difference_N"] = float(largest)


def measure_sweeps(figures: dict, cases: int, repeats: int, folder: Path) -> None:
    from feeder.study.grid import Variant, elevation_range, make_grid
    from feeder.study.sweep_folder import run_sweep
    from feeder.workers import local_workers

    workers = local_workers()
    figures["workers"] = workers
    grid = make_grid()
    run_sweep(grid, folder / "warm", progress=False)  # the page cache, the first imports
    times = []
    for k in range(repeats):
        start = time.perf_counter()
        run_sweep(grid, folder / f"sweep75-{k}", progress=False)
        times.append(time.perf_counter() - start)
    figures["sweep75_wall"] = min(times)
    figures["sweep75_case_ms"] = min(times) * workers / 75 * 1e3
    elevations = elevation_range(-4.0, 70.0, 1.0)
    count = max(1, math.ceil(cases / (2 * elevations.size)))
    factors = [0.8 + 0.5 * k / max(count - 1, 1) for k in range(count)]
    variants = [Variant(f"mass{f:.4f}", {"mass_factor": f}) for f in factors]
    big = make_grid(("projectile", "charge"), elevations, variants)
    total = 2 * elevations.size * count
    start = time.perf_counter()
    run_sweep(big, folder / "big", progress=True)
    wall = time.perf_counter() - start
    figures["sweep_cases"] = total
    figures["sweep_wall"] = wall
    figures["sweep_cases_per_core_second"] = total / wall / workers


def report(figures: dict, previous: dict | None) -> None:
    rows = [
        ("feeder cycle, cold (CLI as wired)", "cycle_cold_cli", "s"),
        ("feeder cycle job, cold, as a script", "cycle_cold_job", "s"),
        ("feeder cycle job, cold, no figures", "cycle_cold_no_figures", "s"),
        ("import numpy + pinocchio", "import_numpy_pinocchio", "s"),
        ("import feeder (study)", "import_feeder_study", "s"),
        ("import matplotlib (figure, agg)", "import_matplotlib", "s"),
        ("bare constraintDynamics call", "bare_call_us", "µs"),
        ("model (URDF, Pinocchio, closure)", "model", "s"),
        ("kinematics, whole cycle", "kinematics", "s"),
        ("  per sample", "kinematics_calls", "calls"),
        ("inverse dynamics (loads + pin)", "inverse_dynamics", "s"),
        ("joint reactions", "reactions", "s"),
        ("  loads + reactions per sample", "inverse_calls", "calls"),
        ("forward run (force rule)", "forward", "s"),
        ("  per step", "forward_calls", "calls"),
        ("Lagrange closed form", "lagrange", "s"),
        ("  / Pinocchio loads", "lagrange_ratio", ""),
        ("CSV (cycle.csv)", "csv", "s"),
        ("figures, one process", "figures_serial", "s"),
        ("sweep, 75 elevations, all cores", "sweep75_wall", "s"),
        ("  per case and core", "sweep75_case_ms", "ms"),
        ("sweep, large: cases", "sweep_cases", ""),
        ("  wall", "sweep_wall", "s"),
        ("  throughput per core", "sweep_cases_per_core_second", "cases/s"),
    ]
    print(
        f"machine: {platform.platform()}, {figures.get('workers', os.cpu_count())} cores, "
        f"Python {platform.python_version()}"
    )
    for label, key, unit in rows:
        if key not in figures:
            continue
        value = figures[key]
        line = f"{label:40s} {value:10.4g} {unit:8s}"
        if key in GOALS:
            sign, goal, _ = GOALS[key]
            met = value <= goal if sign == "≤" else value < goal
            line += f" goal {sign} {goal:g}  {'PASS' if met else 'MISS'}"
        if previous and isinstance(previous.get(key), int | float) and previous[key]:
            line += f"  ({value / previous[key]:.2f}× the compared run)"
        print(line)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        description="Time feeder's whole job and its sweeps against issue 12's goals.",
    )
    parser.add_argument("--quick", action="store_true", help="fewer runs, a 1 000-case sweep")
    parser.add_argument(
        "--sweep-cases", type=int, help="cases of the large sweep (default 10 000; 1 000 quick)"
    )
    parser.add_argument(
        "--json", default="bench_cycle.json", help="file to write the figures to (JSON)"
    )
    parser.add_argument("--compare", help="a JSON of an earlier run: print the ratios to it")
    parser.add_argument(
        "--skip",
        action="append",
        default=[],
        choices=["cold", "steps", "sweeps"],
        help="leave a part out (repeatable)",
    )
    args = parser.parse_args(argv)
    repeats, runs = (3, 3) if args.quick else (7, 5)
    cases = args.sweep_cases or (1_000 if args.quick else 10_000)
    previous = json.loads(Path(args.compare).read_text()) if args.compare else None
    figures: dict = {"date": datetime.now(UTC).isoformat(timespec="seconds")}
    with tempfile.TemporaryDirectory(prefix="feeder-bench-") as tmp:
        folder = Path(tmp)
        if "cold" not in args.skip:
            measure_cold(figures, runs, folder)
        if "steps" not in args.skip:
            measure_steps(figures, repeats, folder)
        if "sweeps" not in args.skip:
            measure_sweeps(figures, cases, max(1, repeats // 2), folder)
    report(figures, previous)
    Path(args.json).write_text(json.dumps(figures, indent=2) + "\n", encoding="utf-8")
    print(f"wrote {args.json}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
