"""``feeder design optimize``: the device's free geometry that minimises a peak load over every
elevation and vehicle case, within the design's bounds and constraints, written into an output
folder (:class:`~feeder.files.OutputFolder`, resumable).

Files: ``optimum.toml`` (the optimum as a parameter file, which ``--params`` reads),
``optimum.csv`` and ``summary.txt`` (:mod:`~feeder.design.report`), ``history.csv``
(:mod:`~feeder.design.history`, rewritten after every iterate), ``optimum.png``
(:mod:`~feeder.design.optimum_figure`), ``sensitivities.csv`` and ``sensitivity_details.csv``
(:mod:`~feeder.design.sensitivities` at the optimum, for the variables that loads depend on),
and the manifest, which records the status and a hash of the problem.

The optimum's peaks are those of its parameter file as written, run as ``feeder sweep`` runs a
case. Ctrl-C writes the best feasible point so far, status :data:`~.report.INTERRUPTED`, and
raises again; a run on the same folder with the same problem resumes from the last iterate of
``history.csv`` (another problem's history there is refused).
"""

from __future__ import annotations

import hashlib
import json
import tempfile
import time
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..device.parameter_file import parameters_sha256, parameters_toml, read_parameters
from ..device.parameters import FeederParameters
from ..exceptions import InputError
from ..files import MANIFEST, OutputFolder, Writer, write_text
from ..motion.laws import CycleSpec
from ..study.grid import SweepGrid, Variant, base_fingerprint, elevation_range
from ..study.grid_file import as_grid
from ..study.sweep import sweep_executor
from ..validation import check_elevations_deg
from ..viz.catalog import elevations_text
from ..workers import check_workers
from .design_space import DesignSpace, read_design
from .differentiable import design_parameters
from .feasibility import check_feasible
from .history import HISTORY, History, read_history
from .objectives import Objective, parse_objective
from .outputs import figure_writer, sensitivity_writers
from .problem import DEFAULT_ELEVATIONS, DEFAULT_RATE, Evaluation, Problem, Scope
from .report import INTERRUPTED, Optimum, optimum_rows, summary
from .search import Found, Search
from .sensitivities import Sensitivities, design_sensitivities
from .tables import write_rows

SAMPLES_PER_VARIABLE = 8
"""Global-start points per variable that loads depend on, without ``samples``."""

PARAMETER_FILE, TABLE, SUMMARY, FIGURE = (
    "optimum.toml",
    "optimum.csv",
    "summary.txt",
    "optimum.png",
)

SAME_POINT = 1e-9
"""[-] SLSQP's last point is the optimum when no scaled variable differs by more."""


@dataclass(frozen=True)
class Setup:
    """The checked inputs of a run and the hash that tells its history from another's."""

    space: DesignSpace
    objective: Objective
    scope: Scope
    samples: int
    starts: int
    fingerprint: str


def _scope(space, grid, elevations_deg, spec) -> Scope:
    grid = None if grid is None else as_grid(grid)
    variants = grid.variants if grid is not None else (Variant("reference"),)
    if elevations_deg is None:
        elevations_deg = grid.elevations_deg if grid else elevation_range(*DEFAULT_ELEVATIONS)
    spec = spec or (grid.spec if grid is not None else CycleSpec(rate=DEFAULT_RATE))
    names = {v.name for v in space.variables}
    for variant in variants:
        keys = {key for key, _ in variant.changes}
        retrofit = {"mass_factor", "length_factor"} & keys and "payload.mass" in names
        if keys & names or retrofit:
            raise InputError(
                f"grid variant {variant.name!r} changes a variable ({sorted(keys & names) or ''}"
                f"{'payload.mass' if retrofit else ''}): keep the grid to vehicle cases"
            )
    elevations = check_elevations_deg(elevations_deg, space.device.elevation_limits)
    return Scope(tuple(dict.fromkeys(elevations)), tuple(variants), spec)


def check_inputs(
    params: FeederParameters, objective, design, elevations_deg, grid, spec, samples, starts
) -> Setup:
    """Every input checked before any cycle runs or folder is made (:func:`run_optimization`)."""
    space = read_design(design, params)
    goal = parse_objective(objective)
    scope = _scope(space, grid, elevations_deg, spec)
    loads = sum(v.loads for v in space.variables)
    samples = SAMPLES_PER_VARIABLE * loads if samples is None else samples
    if isinstance(samples, bool) or not isinstance(samples, int) or samples < 0:
        raise InputError(f"samples must be a whole number ≥ 0, got {samples!r}")
    starts = check_workers("starts", starts)
    check_feasible(space)
    variants = [(v.name, list(v.changes), base_fingerprint(v.base)) for v in scope.variants]
    text = json.dumps([parameters_sha256(space.device), space.text, goal.text,
                       list(scope.elevations_deg), variants, list(scope.spec.durations),
                       scope.spec.rate])  # fmt: skip
    fingerprint = hashlib.sha256(text.encode("utf-8")).hexdigest()
    return Setup(space, goal, scope, samples, starts, fingerprint)


def earlier_history(folder: OutputFolder, setup: Setup) -> list:
    """The history of an earlier run of this problem in ``folder`` (resumed), or none; the
    problem is told by ``setup.fingerprint`` (also a mechanism's setup,
    :mod:`feeder.design.mechanism.optimize`)."""
    if HISTORY not in folder.previous:
        return []
    record = json.loads((folder.path / MANIFEST).read_text(encoding="utf-8"))
    path = folder.path / HISTORY
    if record.get("problem_sha256") != setup.fingerprint:
        raise InputError(
            f"{folder.path} holds the history of another optimisation (another device or model, "
            "design, objective, elevations, motion tables, cases or timing): write to another "
            f"folder, or delete {HISTORY} to start afresh"
        )
    if hashlib.sha256(path.read_bytes()).hexdigest() != folder.previous[HISTORY]:
        raise InputError(f"{path} changed since the run that wrote it: delete it to start afresh")
    return read_history(path, [v.name for v in setup.space.variables])


def _record(setup: Setup, command: str | None, status: str, cycles: int) -> dict:
    scope = setup.scope
    return {
        "command": command or "Python API (feeder.design.run_optimization)",
        "status": status,
        "device": setup.space.device.name,
        "parameters_sha256": parameters_sha256(setup.space.device),
        "problem_sha256": setup.fingerprint,
        "objective": setup.objective.text,
        "variables": [v.name for v in setup.space.variables],
        "elevations_deg": list(scope.elevations_deg),
        "variants": [v.name for v in scope.variants],
        "stage_durations_s": list(scope.spec.durations),
        "sample_rate_hz": scope.spec.rate,
        "cycles": cycles,
    }


def _written(problem: Problem, candidates: Sequence[Evaluation]) -> tuple[Evaluation | None, str]:
    """The first candidate whose parameter file reads back (every check of ``--params``) and
    runs: (its evaluation as written, the file's text); (None, "") when none does."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / PARAMETER_FILE
        for e in candidates:
            text = parameters_toml(_named(e.params))
            write_text(path, text)
            try:
                final = problem.evaluate_written(read_parameters(path))
            except InputError:
                continue
            if not final.failure:
                return final, text
    return None, ""


def run_optimization(
    params: FeederParameters,
    out_dir: str | Path,
    *,
    objective: str = "peak_pressure",
    design: str | Path | None = None,
    elevations_deg: Sequence[float] | None = None,
    grid: str | Path | SweepGrid | None = None,
    spec: CycleSpec | None = None,
    samples: int | None = None,
    starts: int = 1,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = True,
    figure: bool = True,
    sensitivities: bool = True,
    command: str | None = None,
) -> tuple[Optimum, list[Path]]:
    """Optimise the geometry of ``params`` and write the outputs (module docstring) into the
    output folder ``out_dir``; returns the optimum and the paths written.

    Args:
        params: The device.
        objective: :func:`~feeder.design.objectives.parse_objective`'s text.
        design: A design file (:mod:`~feeder.design.design_space`); None: the built-in one.
        elevations_deg: ε [deg] (default: the grid's, else −4° … 70° every 2°).
        grid: A sweep grid (file or :class:`~feeder.study.grid.SweepGrid`) whose variants are
            the vehicle cases; its elevations and timing apply unless given here; its devices
            do not (the device is ``params``).
        spec: The cycles' timing (default: the grid's, else :data:`~.problem.DEFAULT_RATE`).
        samples: Global-start points (default :data:`SAMPLES_PER_VARIABLE` per variable that
            loads depend on; 0: none).
        starts: Local searches, from the best feasible points of the global start.
        workers, scheduler: Where the cycles run (:func:`~feeder.study.sweep.sweep_executor`).
        progress: Progress bars on a terminal.
        figure, sensitivities: Also write ``optimum.png``, the sensitivities at the optimum.
        command: The command line, for the manifest.

    Raises:
        InputError: A bad design, objective, elevation, grid, count or folder; bounds that
            admit no geometry meeting the constraints; another problem's history in the folder.
        KeyboardInterrupt: After writing the best feasible point so far.
    """
    setup = check_inputs(params, objective, design, elevations_deg, grid, spec, samples, starts)
    folder = OutputFolder(out_dir, resumable=True)
    began = time.monotonic()
    with folder:
        history = History([v.name for v in setup.space.variables], earlier_history(folder, setup),
                          save=lambda h: folder.put(HISTORY, h.write))  # fmt: skip
        folder.begin(_record(setup, command, "running", 0))
        search = None
        try:
            with sweep_executor(workers, scheduler) as (executor, slots):
                problem = Problem(setup.space, setup.objective, setup.scope, executor, slots)
                search = Search(problem, history, progress)
                found = search.run(setup.samples, setup.starts)
                best, text = _written(problem, search.feasible())
            optimum = found_optimum(found, best, time.monotonic() - began)
            result = None
            if sensitivities and best is not None:
                result = _sensitivities(optimum, workers, scheduler, progress)
        except KeyboardInterrupt:
            if search is None or search.reference_point is None:
                raise  # nothing evaluated yet: nothing to write
            best = search.best()
            text = "" if best is None else parameters_toml(_named(best.params))
            optimum = Optimum(INTERRUPTED, (), search.problem, search.reference_point, best, {},
                              time.monotonic() - began)  # fmt: skip
            _write(folder, setup, optimum, history, text, None, figure, command)
            raise
        paths = _write(folder, setup, optimum, history, text, result, figure, command)
    return optimum, paths


def _named(params: FeederParameters) -> FeederParameters:
    """The optimum's parameter set, named ``<device>_optimum``."""
    return replace(params, name=f"{params.name}_optimum")


def found_optimum(found: Found, best: Evaluation | None, seconds: float) -> Optimum:
    """The :class:`~.report.Optimum` of a finished search; SLSQP's multipliers only when its
    last point is the optimum."""
    problem, result, point = found.problem, found.result, found.result_point
    multipliers = {}
    if result is not None and best is not None and point is not None:
        if np.abs(problem.scaled(point.x) - problem.scaled(best.x)).max() < SAME_POINT:
            multipliers = dict(zip(problem.constraint_names(), result.multipliers, strict=True))
    if best is None:
        status = "no feasible point"
    else:
        status = "converged" if result is not None and result.success else "not converged"
    return Optimum(status, found.messages, problem, found.reference, best, multipliers, seconds)


def _sensitivities(optimum: Optimum, workers, scheduler, progress) -> Sensitivities:
    """The sensitivities of every peak at the optimum to the variables that loads depend on,
    over the run's elevations, standing level (:func:`~.sensitivities.design_sensitivities`)."""
    p = optimum.problem
    known = {parameter.name for parameter in design_parameters()}
    names = [v.name for v in p.space.variables if v.loads and v.name in known]
    return design_sensitivities(
        optimum.best.params,
        elevations_deg=list(p.scope.elevations_deg),
        parameters=names,
        spec=p.scope.spec,
        workers=workers,
        scheduler=scheduler,
        progress=progress,
    )


def _write(
    folder: OutputFolder,
    setup: Setup,
    optimum: Optimum,
    history: History,
    text: str,
    result: Sensitivities | None,
    figure: bool,
    command: str | None,
) -> list[Path]:
    """Every output and the manifest (marked with the status); returns the paths, the history
    first."""
    report = summary(optimum, elevations_text(setup.scope.elevations_deg)) + "\n"
    outputs: dict[str, Writer] = {HISTORY: history.write}  # first: what a resumed run reads
    if text:
        outputs[PARAMETER_FILE] = lambda path: write_text(path, text)
    outputs[TABLE] = lambda path: write_rows(path, optimum_rows(optimum))
    outputs[SUMMARY] = lambda path: write_text(path, report)
    if figure:
        outputs[FIGURE] = figure_writer(".optimum_figure", "optimum_figure", optimum)
    if result is not None:
        outputs |= sensitivity_writers(result)
    record = _record(setup, command, optimum.status, optimum.problem.cycles)
    return folder.write(outputs, record)
