"""The worker pool of the sweep and the figures: one count, one start policy, one signal policy."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time

import pytest

from feeder.exceptions import InputError
from feeder.workers import check_workers, interrupts_held, process_pool

from .conftest import REPO


def signal_policy() -> tuple[int, int, bool]:
    """In a worker: its SIGINT and SIGTERM handlers, and whether SIGINT is blocked."""
    blocked = signal.SIGINT in signal.pthread_sigmask(signal.SIG_BLOCK, set())
    return signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM), blocked


def test_workers_leave_ctrl_c_to_the_parent_and_end_on_sigterm():
    pool = process_pool(2)
    try:
        for policy in [pool.submit(signal_policy).result() for _ in range(4)]:
            assert policy == (signal.SIG_IGN, signal.SIG_DFL, False)
    finally:
        pool.shutdown()


def test_every_forked_worker_is_started_with_the_pool():
    """All forks happen while the pool is made (with SIGINT held), none at a later submit."""
    pool = process_pool(2)
    try:
        assert len(pool._processes) == 2  # the executor's own record of its children
        pids = {pool.submit(os.getpid).result() for _ in range(8)}
        assert pids <= set(pool._processes)
    finally:
        pool.shutdown()


def test_a_threaded_process_gets_no_forked_pool_when_only_fork_will_do():
    """Forking a process that runs another thread can deadlock the child (e.g. in Jupyter)."""
    release = threading.Event()
    thread = threading.Thread(target=release.wait)
    thread.start()
    try:
        assert process_pool(2, fork_only=True) is None
    finally:
        release.set()
        thread.join()


def test_interrupts_are_held_back_not_lost():
    """A Ctrl-C while the block runs does not interrupt it, and is raised once it ends."""

    def blocked() -> bool:
        return signal.SIGINT in signal.pthread_sigmask(signal.SIG_BLOCK, set())

    assert not blocked()
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)  # as in an interpreter
    finished = False
    try:
        with pytest.raises(KeyboardInterrupt):
            with interrupts_held():
                assert blocked()
                signal.pthread_kill(threading.get_ident(), signal.SIGINT)
                time.sleep(0.05)  # a SIGINT let through would be raised by now
                finished = True
    finally:
        signal.signal(signal.SIGINT, previous)
    assert finished  # held back: the block ran to its end
    assert not blocked()


@pytest.mark.parametrize("workers", [0, -1, 1.5, True, "2", None])
def test_a_worker_count_that_is_not_a_whole_number_above_zero_is_refused(workers):
    with pytest.raises(InputError, match=r"workers must be a whole number ≥ 1, got"):
        check_workers("workers", workers)


@pytest.mark.skipif(not hasattr(os, "sched_setaffinity"), reason="no CPU affinity here")
def test_local_workers_are_the_cores_this_process_may_use():
    """In a process bound to one core (as a batch scheduler or ``taskset`` binds it), one
    worker, whatever the machine has."""
    script = (
        "import os\n"
        "os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})\n"
        "from feeder.workers import local_workers\n"
        "print(local_workers())\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", script], cwd=REPO, capture_output=True, text=True, check=True
    )
    assert done.stdout == "1\n"
