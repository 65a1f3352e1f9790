"""One writer at a time: an exclusive lock on a file, held for a block.

A folder that a run fills is locked for that run (:func:`exclusive_lock`, the kernel's
``flock``: released by the kernel when the process ends, however it ends, so a killed run leaves
no stale lock).
"""

from __future__ import annotations

import contextlib
import fcntl
import os
from collections.abc import Iterator
from pathlib import Path

from ..exceptions import InputError, OutputBusyError

LOCK_ATTEMPTS = 3
"""Tries to take a lock whose file the previous holder removed between our open and our lock
(each such race needs another run to finish in that instant: three tries are plenty)."""


@contextlib.contextmanager
def exclusive_lock(path: str | Path, what: str) -> Iterator[Path]:
    """Hold an exclusive lock on the file ``path`` (created) for the block; removed after it.

    Args:
        path: The lock file.
        what: What the lock guards, for the message (e.g. "the output folder results").

    Raises:
        OutputBusyError: Another process holds the lock.
        InputError: The lock file cannot be created.
    """
    path = Path(path)
    try:
        handle = _acquire(path, what)
    except (InputError, OutputBusyError):
        raise
    except BaseException:  # e.g. Ctrl-C while locking: leave no lock file of ours behind
        _remove_if_free(path)
        raise
    try:
        yield path
    finally:
        path.unlink(missing_ok=True)  # before unlocking: a waiting opener then sees a new file
        os.close(handle)


def _acquire(path: Path, what: str) -> int:
    """An open handle of the lock file ``path`` (created), exclusively locked."""
    for _ in range(LOCK_ATTEMPTS):
        try:
            handle = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as exc:
            raise InputError(f"cannot lock {what}: {exc.strerror or exc}") from exc
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
            locked = _same_file(handle, path)
        except BaseException as exc:
            os.close(handle)  # releases the lock if this run took it
            if isinstance(exc, BlockingIOError):
                raise OutputBusyError(
                    f"another feeder run is writing into {what} (it holds {path}); wait for "
                    "it to finish or choose another folder"
                ) from None
            raise
        if locked:
            return handle
        os.close(handle)  # the previous holder removed this file as we opened it: again
    raise OutputBusyError(f"cannot lock {what}: other runs keep replacing {path}")


def _same_file(handle: int, path: Path) -> bool:
    """Whether the open ``handle`` is the file now at ``path``."""
    try:
        current = os.stat(path)
    except FileNotFoundError:
        return False
    opened = os.fstat(handle)
    return (current.st_ino, current.st_dev) == (opened.st_ino, opened.st_dev)


def _remove_if_free(path: Path) -> None:
    """Remove the lock file ``path`` if no process holds it (after an interrupted locking)."""
    try:
        handle = os.open(path, os.O_RDWR)
    except OSError:
        return
    try:
        fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        if _same_file(handle, path):
            path.unlink()
    except OSError:
        pass  # another run holds it, or it is gone: not this run's to remove
    finally:
        os.close(handle)
