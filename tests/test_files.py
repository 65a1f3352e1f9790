"""Atomic writes and the output folder's lock: nothing half-written ever looks complete, one
writer at a time, and no stale lock after a run dies."""

from __future__ import annotations

import fcntl
import subprocess
import sys

import pytest

from feeder import files
from feeder.exceptions import InputError, OutputBusyError
from feeder.files import atomic_path, exclusive_lock, path_in, write_text

LOCK_WAIT = 30.0
"""[s] Longest wait for the killed child process to be reaped."""


@pytest.mark.parametrize("error", [RuntimeError, KeyboardInterrupt])
def test_interrupted_write_leaves_the_previous_file(tmp_path, error):
    path = write_text(tmp_path / "table.csv", "complete\n")
    with pytest.raises(error), atomic_path(path) as temporary:
        temporary.write_text("half", encoding="utf-8")
        raise error
    assert path.read_text(encoding="utf-8") == "complete\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["table.csv"]  # no temporary left


def test_interrupted_first_write_leaves_nothing(tmp_path):
    with pytest.raises(KeyboardInterrupt), atomic_path(tmp_path / "new.csv") as temporary:
        temporary.write_text("half", encoding="utf-8")
        raise KeyboardInterrupt
    assert list(tmp_path.iterdir()) == []


def test_unwritable_folder(tmp_path):
    with pytest.raises(InputError, match="cannot write"):
        write_text(tmp_path / "missing" / "x.txt", "x")


def test_second_lock_is_refused_and_the_file_removed_after(tmp_path):
    lock = tmp_path / "run.lock"
    with exclusive_lock(lock, "the folder"):
        assert lock.is_file()
        with pytest.raises(OutputBusyError, match="another feeder run is writing into the folder"):
            with exclusive_lock(lock, "the folder"):
                pass
    assert not lock.exists()
    with exclusive_lock(lock, "the folder"):  # free again
        pass


def test_lock_of_a_killed_process_is_released(tmp_path):
    """The kernel drops a dead process' flock: a killed run leaves no stale lock."""
    lock = tmp_path / "run.lock"
    holder = subprocess.Popen(
        [
            sys.executable,
            "-c",
            "import sys, time\nfrom feeder.files import exclusive_lock\n"
            f"with exclusive_lock({str(lock)!r}, 'x'):\n"
            "    print('locked', flush=True)\n    time.sleep(600)\n",
        ],
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert holder.stdout.readline().strip() == "locked"
        with pytest.raises(OutputBusyError):
            with exclusive_lock(lock, "x"):
                pass
    finally:
        holder.kill()
        holder.wait(timeout=LOCK_WAIT)
    assert lock.exists()  # the killed holder could not remove its file ...
    with exclusive_lock(lock, "x"):  # ... but its lock is gone
        pass


def test_lock_in_a_missing_folder(tmp_path):
    with pytest.raises(InputError, match="cannot lock"):
        with exclusive_lock(tmp_path / "missing" / "run.lock", "x"):
            pass


def test_interrupted_locking_leaves_no_lock_file(tmp_path, monkeypatch):
    """Ctrl-C after the lock file was created and locked, before the block starts: the lock is
    released and its file removed (else the run's new output folder could not be removed)."""
    path = tmp_path / "lock"

    calls, flock = [], fcntl.flock

    def flock_then_interrupted(handle, operation):
        calls.append(operation)
        flock(handle, operation)
        if len(calls) == 1:  # the locking, not the clean-up's test of the lock
            raise KeyboardInterrupt

    monkeypatch.setattr(files.fcntl, "flock", flock_then_interrupted)
    with pytest.raises(KeyboardInterrupt), exclusive_lock(path, "the folder"):
        pass
    assert not path.exists()


def test_a_lock_file_another_run_holds_is_not_removed(tmp_path):
    """The clean-up after an interrupted locking leaves a lock that another run holds."""
    path = tmp_path / "lock"
    with exclusive_lock(path, "the folder"):
        files._remove_if_free(path)
        assert path.exists()
    assert not path.exists()


@pytest.mark.parametrize("name", ["", ".", "..", "../x", "a/b", "/etc/x", "a\\b"])
def test_path_in_refuses_names_that_are_not_plain_file_names(tmp_path, name):
    with pytest.raises(InputError, match="is not a file name in"):
        path_in(tmp_path, name, "the file")


def test_path_in_gives_the_file_in_the_folder(tmp_path):
    assert path_in(tmp_path, "a.b-c_feeder.urdf", "the file") == tmp_path / "a.b-c_feeder.urdf"
