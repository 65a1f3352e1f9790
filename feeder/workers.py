"""Worker processes: one pool policy for the sweep's cases and the figures.

* **Count:** :func:`local_workers`, the cores this process may run on (its CPU affinity, which a
  batch system or ``taskset`` may restrict), checked by :func:`check_workers`.
* **Start:** ``fork`` (Linux) gives workers that have Pinocchio and the package loaded already;
  it is used only while this process runs a single thread (forking a threaded process can
  deadlock the child, e.g. in a Jupyter kernel or after tqdm started its monitor). Otherwise
  ``forkserver`` with the caller's modules preloaded once in the server, or ``spawn`` where
  neither exists (Windows); a caller that gains nothing from a fresh interpreter (the figures:
  drawing here is as quick as importing matplotlib there) asks for ``fork`` or nothing.
* **Signals:** every worker leaves Ctrl-C to the parent (a terminal sends SIGINT to the whole
  process group: the parent cancels what is queued, and a worker's own traceback would only add
  noise) and lets SIGTERM end it at once (a forked worker inherits the command line's SIGTERM
  handler, meant for the parent only). All workers are started when the pool is made, with
  SIGINT held back (blocked, not lost) in the parent meanwhile: a Ctrl-C inside a child before
  its handler is set would raise there (``Exception ignored in: <function _releaseLock>``).
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import signal
import threading
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor

from .exceptions import InputError


def local_workers() -> int:
    """The cores this process may run on."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


def check_workers(what: str, workers: object) -> int:
    """``workers`` as a count of processes ≥ 1, else :class:`InputError` naming ``what``."""
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise InputError(f"{what} must be a whole number ≥ 1, got {workers!r}")
    return workers


def worker_signals() -> None:
    """In a worker: SIGINT ignored, SIGTERM at its default, then the signals that
    :func:`interrupts_held` kept back during the fork taken (module docstring)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})


@contextlib.contextmanager
def interrupts_held() -> Iterator[None]:
    """SIGINT held back (blocked, not lost) in this thread while the block runs; the parent
    takes it when the block ends, the workers ignore it."""
    if not hasattr(signal, "pthread_sigmask"):  # Windows: no fork, nothing to hold
        yield
        return
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def fork_safe() -> bool:
    """Whether this process may fork: the platform has ``fork`` and no other thread runs (a
    thread holding a lock when the process forks leaves the child's copy of it held)."""
    return "fork" in multiprocessing.get_all_start_methods() and threading.active_count() == 1


def _nothing() -> None:
    """A first task that only makes the pool start its worker."""


def process_pool(
    workers: int,
    *,
    fork_only: bool = False,
    preload: Sequence[str] = (),
    warm_up: Callable[[], None] = _nothing,
) -> ProcessPoolExecutor | None:
    """A pool of ``workers`` processes, started now (module docstring): every one at once when
    forked, else as the warm-up tasks need them.

    Args:
        workers: Processes, ≥ 1.
        fork_only: Return None rather than start interpreters where ``fork`` is not safe.
        preload: Modules a ``forkserver`` imports once for all its workers.
        warm_up: Run once in each worker as it starts (e.g. the imports it will need).

    Returns:
        The pool, or None (``fork_only`` where forking is not safe here).
    """
    if fork_safe():
        context = multiprocessing.get_context("fork")
    elif fork_only:
        return None
    elif "forkserver" in multiprocessing.get_all_start_methods():
        context = multiprocessing.get_context("forkserver")
        context.set_forkserver_preload(list(preload))
    else:
        context = multiprocessing.get_context("spawn")
    pool = ProcessPoolExecutor(workers, mp_context=context, initializer=worker_signals)
    with interrupts_held():  # a fork pool starts every worker at the first submit
        for _ in range(workers):
            pool.submit(warm_up)
    return pool
