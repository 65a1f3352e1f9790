"""Sweeps: the peak loads and reactions of many cycles (elevations × parameter variants ×
devices), on every core of this machine or on a Dask cluster.

A case (:class:`~feeder.study.grid.SweepCase`) is one cycle's dynamics without the forward run
(:func:`~feeder.dynamics.cycle.cycle_dynamics` with ``forward=False``: loads, every joint
reaction, drives; the peaks need no forward run, hence no minimum sample rate) reduced to its
peaks (:func:`~feeder.study.peaks.cycle_peaks`). Cases run in batches on a
:class:`concurrent.futures.Executor`: a process pool here (all cores by default), or a Dask
cluster's (``scheduler="tcp://HOST:PORT"``, through ``Client.get_executor()``, the optional
``cluster`` extra); both take the same batches through the same code.

:func:`run_sweep` writes the table (:mod:`feeder.study.sweep_table`) into an output folder
(:class:`~feeder.files.OutputFolder`: new, empty, or one an earlier feeder run wrote; its
manifest records the sweep) and resumes: cases already in the table of an earlier sweep of that
folder, with the same parameters, are not computed again, and the table is rewritten
(atomically, its hash in the manifest) every :data:`CHECKPOINT_SECONDS` while the sweep runs, so
an interrupted sweep loses at most that much work. :func:`elevation_sweep` is the same in
memory, for one device.
"""

from __future__ import annotations

import contextlib
import functools
import math
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from concurrent.futures import Executor, Future, as_completed
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import urlsplit

import numpy as np
from tqdm import tqdm

from ..device.feeder import Feeder, load_feeder
from ..device.parameters import FeederParameters
from ..dynamics.cycle import cycle_dynamics
from ..exceptions import InputError
from ..files import OutputFolder, Writer
from ..motion.laws import CycleSpec
from ..validation import check_elevation, check_finite
from ..workers import check_workers, local_workers, process_pool
from .columns import COLUMNS
from .grid import SweepCase, SweepGrid, make_grid, read_grid
from .peaks import cycle_peaks
from .sweep_table import (
    PARQUET,
    TABLE,
    Row,
    check_parquet,
    read_table,
    row_key,
    write_parquet,
    write_table,
)

CHECKPOINT_SECONDS = 2.0
"""Longest time [s] between two writes of the table while a sweep runs: what an interruption
can lose. Rewriting costs ~1 ms per 100 rows, so 10 000 cases spend < 5 % of the time on it."""

BATCHES_PER_WORKER = 8
"""Batches per worker: small enough that the last ones finish together (the load balances),
large enough that the per-batch overhead (~1 ms to pickle and ship) stays negligible."""

MAX_BATCH = 16
"""Most cases in one batch (~0.7 s of work at 42 ms a case, measured at 1 kHz): the progress bar
moves, and after Ctrl-C a worker finishes its batch and the one queued for it within ~1.5 s."""

SCHEDULER_TIMEOUT = 10.0
"""Seconds to wait for a Dask scheduler to answer before giving up with a clear error."""

UNITS = {column.name: column.unit for column in COLUMNS}


@dataclass(frozen=True)
class ElevationSweep:
    """Peak loads of a cycle at each elevation of a sweep.

    Attributes:
        elevations: ε [rad], (K,).
        peaks: Quantity name → peak value at each elevation (signed where the quantity is
            signed, else the magnitude) [SI unit], (K,).
        times: Quantity name → time of that peak in its cycle [s], (K,).
        units: Quantity name → SI unit.
    """

    elevations: np.ndarray
    peaks: dict[str, np.ndarray]
    times: dict[str, np.ndarray]
    units: dict[str, str]

    def worst(self, name: str) -> tuple[float, float]:
        """Elevation [rad] and value of the largest |peak| of ``name`` over the sweep."""
        k = int(np.argmax(np.abs(self.peaks[name])))
        return float(self.elevations[k]), float(self.peaks[name][k])


@functools.lru_cache(maxsize=16)
def cached_feeder(params: FeederParameters) -> Feeder:
    """The device of a parameter set, built once per process (~10 ms: URDF, model): a worker
    reuses it for every case of the same parameters."""
    return load_feeder(params)


def case_peaks(case: SweepCase) -> Row:
    """One case's row of the sweep table: its key, its hash, and every peak with its time."""
    dynamics = cycle_dynamics(
        cached_feeder(case.params), case.elevation, case.spec, base=case.base, forward=False
    )
    row: Row = {
        "device": case.device,
        "variant": case.variant,
        "elevation_deg": case.elevation_deg,
        "case_sha256": case.sha256,
    }
    for peak in cycle_peaks(dynamics):
        row[peak.name] = peak.value
        row[f"{peak.name}_time"] = peak.time
    return row


def _run_batch(cases: list[SweepCase]) -> list[Row]:
    return [case_peaks(case) for case in cases]


def check_scheduler(address: str) -> str:
    """A Dask scheduler address ``tcp://HOST:PORT`` (or ``tls://``), else :class:`InputError`."""
    parts = urlsplit(address) if isinstance(address, str) else None
    try:
        port = parts.port if parts is not None else None
    except ValueError:
        port = None
    if parts is None or parts.scheme not in ("tcp", "tls") or not parts.hostname or port is None:
        raise InputError(f"the scheduler address must be tcp://HOST:PORT, got {address!r}")
    return address


@contextlib.contextmanager
def sweep_executor(
    workers: int | None = None, scheduler: str | None = None
) -> Iterator[tuple[Executor | None, int]]:
    """The executor of a sweep and how many cases it runs at once.

    Args:
        workers: Local worker processes (default: every core); 1 runs the cases in this
            process. Ignored with a scheduler.
        scheduler: Address of a running Dask scheduler, ``tcp://HOST:PORT``.

    Yields:
        (executor, slots): None and 1 to run here; a process pool; or the Dask client's
        executor and the cluster's thread count.

    Raises:
        InputError: ``workers`` not a positive whole number; a bad scheduler address; dask not
            installed; no scheduler answering at the address.
    """
    if scheduler is not None:
        address = check_scheduler(scheduler)
        try:
            from distributed import Client
        except ImportError as exc:
            raise InputError(
                "a Dask scheduler needs dask.distributed: pip install 'feeder[cluster]'"
            ) from exc
        try:
            client = Client(address, timeout=SCHEDULER_TIMEOUT, set_as_default=False)
        except (OSError, TimeoutError) as exc:
            raise InputError(f"no Dask scheduler answers at {address}: {exc}") from exc
        try:
            threads = sum(w["nthreads"] for w in client.scheduler_info()["workers"].values())
            yield client.get_executor(pure=False), max(threads, 1)
        finally:
            client.close()
        return
    count = local_workers() if workers is None else check_workers("workers", workers)
    if count == 1:
        yield None, 1
        return
    pool = process_pool(count, preload=[__name__])
    stopped = True
    try:
        yield pool, count
        stopped = False
    finally:  # after an error or Ctrl-C, the queued batches are dropped, not run
        pool.shutdown(wait=True, cancel_futures=stopped)


def run_cases(
    cases: Sequence[SweepCase],
    executor: Executor | None,
    slots: int = 1,
    progress: bool = True,
) -> Iterator[Row]:
    """Compute the cases' rows, yielded as they complete (not in order).

    Args:
        cases: The cases.
        executor: Where to run them (:func:`sweep_executor`); None: in this process.
        slots: Cases the executor runs at once (sets the batch size).
        progress: Show a progress bar on a terminal (none when stderr is not one).
    """
    quiet = None if progress else True  # None: tqdm shows the bar only on a terminal
    if executor is None:
        with tqdm(total=len(cases), desc="sweep", unit="case", disable=quiet) as bar:
            for case in cases:
                yield case_peaks(case)
                bar.update()
        return
    size = max(1, min(MAX_BATCH, math.ceil(len(cases) / (slots * BATCHES_PER_WORKER))))
    futures: list[Future] = []
    try:
        # Each future is kept as it is made, so that a Ctrl-C meanwhile cancels them.
        for k in range(0, len(cases), size):
            futures.append(executor.submit(_run_batch, list(cases[k : k + size])))
        with tqdm(total=len(cases), desc="sweep", unit="case", disable=quiet) as bar:
            for future in as_completed(futures):
                rows = future.result()
                bar.update(len(rows))
                yield from rows
    finally:
        for future in futures:
            future.cancel()


def elevation_sweep(
    feeder: Feeder,
    elevations: np.ndarray,
    spec: CycleSpec | None = None,
    progress: bool = True,
    workers: int | None = None,
) -> ElevationSweep:
    """Peak loads and reactions of the cycle at each of ``elevations`` [rad], in memory.

    The forward (force-rule) run of each cycle is skipped: the peaks do not need it.

    Args:
        feeder: The device.
        elevations: ε [rad], shape (K,), K ≥ 1.
        spec: Stage durations and sample rate (default :class:`~feeder.motion.laws.CycleSpec`).
        progress: Show a progress bar over the cycles on a terminal (none when stderr is not
            one, e.g. in CI logs).
        workers: Processes (default: every core; 1 computes here).

    Raises:
        InputError: ``elevations`` empty, not one-dimensional, or not finite; bad ``workers``.
        ElevationError: An elevation outside the device's range (checked before any work).
    """
    array = check_finite("elevations", elevations)
    if array.ndim != 1 or array.size == 0:
        raise InputError(f"elevations must be a non-empty 1-D array [rad], got {elevations!r}")
    elevations = np.array([check_elevation(e, feeder.params.elevation_limits) for e in array])
    spec = spec or CycleSpec()
    params = feeder.params
    cases = [
        SweepCase(params.name, "reference", math.degrees(e), float(e), params, spec)
        for e in elevations
    ]
    with sweep_executor(workers) as (executor, slots):
        rows = {row["elevation_deg"]: row for row in run_cases(cases, executor, slots, progress)}
    ordered = [rows[case.elevation_deg] for case in cases]
    names = row_quantities(ordered[0])
    return ElevationSweep(
        elevations=elevations,
        peaks={n: np.array([row[n] for row in ordered], dtype=float) for n in names},
        times={n: np.array([row[f"{n}_time"] for row in ordered], dtype=float) for n in names},
        units={n: UNITS[n] for n in names},
    )


def row_quantities(row: Row) -> list[str]:
    """The quantities of a table row, in column order."""
    return [name for name in row if f"{name}_time" in row]


def sweeps_of(rows: Sequence[Row]) -> dict[tuple[str, str], ElevationSweep]:
    """A table's rows as one :class:`ElevationSweep` per (device, variant), each by increasing
    elevation."""
    groups: dict[tuple[str, str], list[Row]] = {}
    for row in rows:
        groups.setdefault((str(row["device"]), str(row["variant"])), []).append(row)
    sweeps = {}
    for key, group in groups.items():
        group.sort(key=lambda row: float(row["elevation_deg"]))
        names = row_quantities(group[0])
        sweeps[key] = ElevationSweep(
            elevations=np.radians([float(row["elevation_deg"]) for row in group]),
            peaks={n: np.array([row[n] for row in group], dtype=float) for n in names},
            times={n: np.array([row[f"{n}_time"] for row in group], dtype=float) for n in names},
            units={n: UNITS[n] for n in names},
        )
    return sweeps


def _grid(
    grid: str | Path | SweepGrid | None,
    devices: Sequence[str] | None,
    elevations: Sequence[float] | None,
) -> SweepGrid:
    if grid is None:
        base = make_grid()
    elif isinstance(grid, SweepGrid):
        base = grid
    elif isinstance(grid, str | Path):
        base = read_grid(grid)
    else:
        raise InputError(f"grid must be a TOML file's path or a SweepGrid, got {grid!r}")
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
            computed again), by reason (:func:`~feeder.study.sweep_table.read_table`).
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
    rows, rejected = read_table(path)
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
        grid: A grid file (TOML, :mod:`feeder.study.grid`), a :class:`SweepGrid`, or None for
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
