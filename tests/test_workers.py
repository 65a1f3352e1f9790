"""The worker pool of the sweep and the figures: one count, one start policy, one signal policy."""

from __future__ import annotations

import os
import signal
import threading

import pytest

from feeder.exceptions import InputError
from feeder.workers import check_workers, interrupts_held, local_workers, process_pool


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
    def blocked() -> bool:
        return signal.SIGINT in signal.pthread_sigmask(signal.SIG_BLOCK, set())

    assert not blocked()
    with interrupts_held():
        assert blocked()
    assert not blocked()


@pytest.mark.parametrize("workers", [0, -1, 1.5, True, "2", None])
def test_a_worker_count_that_is_not_a_whole_number_above_zero_is_refused(workers):
    with pytest.raises(InputError, match=r"workers must be a whole number ≥ 1, got"):
        check_workers("workers", workers)


def test_local_workers_are_the_cores_this_process_may_use():
    assert local_workers() == len(os.sched_getaffinity(0))
