"""A sweep run into an output folder: the table of a grid's cases, resumed where an earlier run
of the same sweep stopped.

:func:`run_sweep` writes the table (:mod:`feeder.study.sweep_table`) into an output folder
(:class:`~feeder.files.OutputFolder`: new, empty, or one an earlier feeder run wrote; its
manifest records the sweep) and resumes: cases already in the table of an earlier sweep of that
folder, with the same parameters, are not computed again, and the table is rewritten
(atomically, its hash in the manifest) every :data:`CHECKPOINT_SECONDS` while the sweep runs, so
an interrupted sweep loses at most that much work. The cases run on the executors of
:mod:`feeder.study.sweep`.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from ..exceptions import InputError
from ..files import OutputFolder, Writer
from .grid import SweepCase, SweepGrid, make_grid
from .grid_file import as_grid
from .sweep import run_cases, sweep_executor
from .sweep_table import (
    PARQUET,
    TABLE,
    Row,
    check_parquet,
    read_sweep_table,
    row_key,
    write_parquet,
    write_table,
)

CHECKPOINT_SECONDS = 2.0
"""Longest time [s] between two writes of the table while a sweep runs: what an interruption
can lose. Rewriting costs ~1 ms per 100 rows, so 10 000 cases spend < 5 % of the time on it."""


def _grid(
    grid: str | Path | SweepGrid | None,
    devices: Sequence[str] | None,
    elevations: Sequence[float] | None,
) -> SweepGrid:
    base = make_grid() if grid is None else as_grid(grid)
    if devices is None and elevations is None:
        return base
    return make_grid(
        devices=list(devices) if devices is not None else base.devices,
        elevations_deg=base.elevations_deg if elevations is None else elevations,
        variants=base.variants,
        spec=base.spec,
    )


@dataclass(frozen=True)
class SweepOutputs:
    """What :func:`run_sweep` wrote.

    Attributes:
        table: The table ``sweep_peaks.csv``.
        files: Every output, the table first (then its Parquet copy, then the figures).
        kept: Cases kept from the table of an earlier sweep of the folder.
        computed: Cases computed by this run.
        dropped: Rows of the earlier table that failed their checks (and whose cases were
            computed again), by reason (:func:`~feeder.study.sweep_table.read_sweep_table`).
    """

    table: Path
    files: tuple[Path, ...]
    kept: int
    computed: int
    dropped: Mapping[str, int]

    def summary(self) -> str:
        """One line: the cases, how many were kept and computed, and the rows dropped and why."""
        cases = self.kept + self.computed
        line = (
            f"{cases} case{'' if cases == 1 else 's'}: {self.kept} kept from the earlier table, "
            f"{self.computed} computed"
        )
        if self.dropped:
            reasons = ", ".join(f"{count} {reason}" for reason, count in self.dropped.items())
            line += f" ({sum(self.dropped.values())} earlier rows recomputed: {reasons})"
        return line


def _reusable(path: Path, cases: Sequence[SweepCase]) -> tuple[dict, dict[str, int]]:
    """The rows of a previous run of this sweep in ``path`` that pass their checks, by case
    key, and how many rows were dropped, by reason (their cases are computed again).

    Raises:
        InputError: The table's columns are not this version's; it holds an intact row of a
            case that is not in this sweep, or of one computed with other parameters or timing
            (the folder belongs to another sweep).
    """
    if not path.exists():
        return {}, {}
    rows, rejected = read_sweep_table(path)
    wanted = {case.key: case for case in cases}
    done = {}
    for row in rows:
        key = row_key(row)
        if key not in wanted:
            raise InputError(
                f"{path} holds case {key} that is not in this sweep: write to another folder, "
                "or delete the table to start afresh"
            )
        if row["case_sha256"] != wanted[key].sha256:
            raise InputError(
                f"{path} holds case {key} computed with other parameters or timing: write to "
                "another folder, or delete the table to start afresh"
            )
        done[key] = row
    dropped: dict[str, int] = {}
    for _, reason in rejected:
        dropped[reason] = dropped.get(reason, 0) + 1
    return done, dropped


def run_sweep(
    grid: str | Path | SweepGrid | None,
    out_dir: str | Path,
    *,
    devices: Sequence[str] | None = None,
    elevations: Sequence[float] | None = None,
    scheduler: str | None = None,
    workers: int | None = None,
    progress: bool = True,
    parquet: bool = False,
    figures: Callable[[Path], Mapping[str, Writer]] | None = None,
    command: str | None = None,
) -> SweepOutputs:
    """Run a sweep and write its table ``sweep_peaks.csv`` (and ``sweep_peaks.parquet``, and
    figures) with a manifest into the output folder ``out_dir``, resuming an earlier sweep
    there.

    Args:
        grid: A grid file (TOML, :mod:`feeder.study.grid_file`), a :class:`SweepGrid`, or None for
            the default: the projectile feeder, every degree of −4° … 70°, unchanged.
        out_dir: Output folder: new, empty, or one an earlier feeder run wrote
            (:class:`~feeder.files.OutputFolder`; the outputs of a run other than a sweep are
            replaced; an interrupted sweep keeps its table there).
        devices: Built-in device names replacing the grid's.
        elevations: Elevations [deg] replacing the grid's
            (:func:`~feeder.study.grid.elevation_range` makes a range).
        scheduler: A Dask scheduler's address ``tcp://HOST:PORT`` to run the cases on; default
            this machine's cores.
        workers: Local worker processes (default: every core; 1: in this process).
        progress: Progress bar on a terminal.
        parquet: Also write the table as Parquet (needs pyarrow: the ``parquet`` extra).
        figures: Given the finished table's path, the figures to write (file name → writer);
            default none.
        command: The command line, for the manifest.

    Raises:
        InputError: A bad grid, device, elevation, worker count or scheduler; an output folder
            that cannot be written, that holds files no feeder run wrote, or that holds another
            sweep's table or a table of other columns (another version's); pyarrow missing.
        OutputBusyError: Another run is writing into the same folder (it holds the lock).
        FeederError: A variant whose device does not assemble (from the grid's check).
    """
    sweep = _grid(grid, devices, elevations)
    if parquet:
        check_parquet()  # before the work, not after it
    folder = OutputFolder(out_dir, resumable=True)
    with folder:
        return _run(sweep, folder, workers, scheduler, progress, parquet, figures, command)


def _record(
    sweep: SweepGrid, command: str | None, kept: int, todo: int, dropped: Mapping[str, int]
) -> dict[str, object]:
    """The manifest's description of a sweep: its grid, how many cases were kept, and how many
    rows of the earlier table were dropped, by reason."""
    return {
        "command": command or "Python API (feeder.run_sweep)",
        "sweep": {
            "devices": list(sweep.devices),
            "variants": [variant.name for variant in sweep.variants],
            "elevations_deg": [float(e) for e in sweep.elevations_deg],
            "stage_durations_s": list(sweep.spec.durations),
            "sample_rate_hz": sweep.spec.rate,
        },
        "cases": kept + todo,
        "cases_kept": kept,
        "cases_computed": todo,
        "earlier_rows_dropped": dict(dropped),
    }


def _run(
    sweep: SweepGrid,
    folder: OutputFolder,
    workers: int | None,
    scheduler: str | None,
    progress: bool,
    parquet: bool,
    figures: Callable[[Path], Mapping[str, Writer]] | None,
    command: str | None,
) -> SweepOutputs:
    path = folder.path / TABLE
    cases = sweep.cases()
    order = {case.key: k for k, case in enumerate(cases)}
    done, dropped = _reusable(path, cases) if TABLE in folder.previous else ({}, {})
    kept = len(done)
    todo = [case for case in cases if case.key not in done]
    folder.begin(_record(sweep, command, kept, len(todo), dropped))

    def rows() -> list[Row]:
        return sorted(done.values(), key=lambda row: order[row_key(row)])

    def save() -> None:
        if done:
            folder.put(TABLE, lambda table: write_table(table, rows()))

    saved = time.monotonic()
    try:
        with (
            sweep_executor(workers, scheduler) as (executor, slots),
            contextlib.closing(run_cases(todo, executor, slots, progress)) as computed,
        ):
            for row in computed:
                done[row_key(row)] = row
                if time.monotonic() - saved > CHECKPOINT_SECONDS:
                    save()
                    saved = time.monotonic()
    finally:
        save()  # also a resumed sweep with nothing left to compute: its table is this run's
    files = [path]
    if parquet:
        files.append(folder.put(PARQUET, lambda table: write_parquet(table, rows())))
    for name, writer in (figures(path) if figures else {}).items():
        files.append(folder.put(name, writer))
    folder.finish()
    return SweepOutputs(path, tuple(files), kept, len(todo), dropped)
