"""Sweep cases run: one case's peaks, and many cases in batches on every core of this machine
or on a Dask cluster.

A case (:class:`~feeder.study.grid.SweepCase`) is one cycle's dynamics without the force-rule
run (:func:`~feeder.dynamics.cycle.cycle_dynamics` with ``forward=False``: loads, every joint
reaction, drives; the peaks need no forward run, hence no minimum sample rate) reduced to its
peaks (:func:`~feeder.study.peaks.cycle_peaks`), with the controlled forward run's loading pose
when its variant asks for it (``servo``): :func:`case_peaks`. Cases run in batches
(:func:`run_cases`) on a :class:`concurrent.futures.Executor` (:func:`sweep_executor`): a
process pool here (all cores by default), or a Dask cluster's (``scheduler="tcp://HOST:PORT"``,
through ``Client.get_executor()``, the optional ``cluster`` extra); both take the same batches
through the same code.

The sweeps built on them: :func:`~feeder.study.sweep_folder.run_sweep` (a grid into a resumable
output folder) and :func:`~feeder.study.elevation_sweeps.elevation_sweep` (one device, in
memory).
"""

from __future__ import annotations

import contextlib
import functools
import math
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import Executor, Future, as_completed
from typing import TypeVar
from urllib.parse import urlsplit

from tqdm import tqdm

from ..device.feeder import Feeder, load_feeder
from ..device.parameters import FeederParameters
from ..dynamics.cycle import cycle_dynamics
from ..exceptions import InputError
from ..workers import check_workers, local_workers, process_pool
from .grid import SweepCase
from .peaks import cycle_peaks
from .sweep_table import LOADING_COLUMNS, Row

GUIDED_SHARE = 2
"""Each batch takes 1/(this × slots) of the cases not yet batched (guided scheduling, as
OpenMP's ``schedule(guided)``): batches shrink towards the end, so that the last ones are single
cases and the slots finish within about one case of each other (equal batches of five left one
of two cores idle for up to five cases, ~0.14 s of a 75-elevation sweep), while the early ones
are large enough that the per-batch overhead (~1 ms to pickle and ship) stays negligible."""

MAX_BATCH = 16
"""Most cases in one batch (~0.7 s of work at 42 ms a case, measured at 1 kHz): the progress bar
moves, and after Ctrl-C a worker finishes its batch and the one queued for it within ~1.5 s."""

SCHEDULER_TIMEOUT = 10.0
"""Seconds to wait for a Dask scheduler to answer before giving up with a clear error."""


Result = TypeVar("Result")
"""What :func:`run_cases` computes of each case."""


@functools.lru_cache(maxsize=16)
def cached_feeder(params: FeederParameters) -> Feeder:
    """The device of a parameter set, built once per process (~10 ms: URDF, model): a worker
    reuses it for every case of the same parameters."""
    return load_feeder(params)


def case_peaks(case: SweepCase) -> Row:
    """One case's row of the sweep table: its key, its hash, every peak with its time, and the
    controlled run's loading pose, settling, peaks and saturation (``nan`` without that run:
    :data:`~feeder.study.sweep_table.LOADING_COLUMNS`)."""
    dynamics = cycle_dynamics(
        cached_feeder(case.params),
        case.elevation,
        case.spec,
        base=case.base,
        forward=False,
        controlled=case.servo,
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
    row |= dict.fromkeys(LOADING_COLUMNS, math.nan)
    run = dynamics.controlled
    if run is not None:
        pose, n = run.loading_pose(), run.cycle_samples
        step = 1.0 / case.spec.rate
        row |= {
            "loading_off_line": pose.off_line,
            "loading_along_line": pose.along_line,
            "loading_angle": pose.angle,
            "loading_settling": math.nan if pose.settle_time is None else pose.settle_time,
            "controlled_peak_pressure": float(run.pressures.peak()[:n].max()),
            "controlled_peak_rack_force": float(abs(run.rack_force[:n]).max()),
            "controlled_saturated_duration": float(run.saturated[:n].any(axis=1).sum() * step),
        }
    return row


def batch_sizes(count: int, slots: int) -> list[int]:
    """The sizes of the batches of ``count`` cases for ``slots`` cases at once, in the order
    they are submitted: each 1/(:data:`GUIDED_SHARE` × slots) of the cases left (at least one,
    at most :data:`MAX_BATCH`), so non-increasing, ending in single cases; they sum to
    ``count``."""
    sizes, left = [], count
    while left:
        size = max(1, min(MAX_BATCH, math.ceil(left / (GUIDED_SHARE * slots))))
        sizes.append(size)
        left -= size
    return sizes


def _run_batch(work: Callable[[SweepCase], Result], cases: list[SweepCase]) -> list[Result]:
    return [work(case) for case in cases]


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
    work: Callable[[SweepCase], Result] | None = None,
    unit: str = "case",
    desc: str = "sweep",
) -> Iterator[Result]:
    """Compute ``work`` of each case (by default its row of peaks, :func:`case_peaks`), yielded
    as they complete (not in order).

    Args:
        cases: The cases.
        executor: Where to run them (:func:`sweep_executor`); None: in this process.
        slots: Cases the executor runs at once (sets the batch size).
        progress: Show a progress bar on a terminal (none when stderr is not one).
        work: What to compute of a case (default :func:`case_peaks`): a module-level function
            (workers receive it pickled).
        unit, desc: The progress bar's unit and label.
    """
    work = case_peaks if work is None else work
    quiet = None if progress else True  # None: tqdm shows the bar only on a terminal
    if executor is None:
        with tqdm(total=len(cases), desc=desc, unit=unit, disable=quiet) as bar:
            for case in cases:
                yield work(case)
                bar.update()
        return
    futures: list[Future] = []
    try:
        # Each future is kept as it is made, so that a Ctrl-C meanwhile cancels them.
        start = 0
        for size in batch_sizes(len(cases), slots):
            batch = list(cases[start : start + size])
            futures.append(executor.submit(_run_batch, work, batch))
            start += size
        with tqdm(total=len(cases), desc=desc, unit=unit, disable=quiet) as bar:
            for future in as_completed(futures):
                results = future.result()
                bar.update(len(results))
                yield from results
    finally:
        for future in futures:
            future.cancel()
