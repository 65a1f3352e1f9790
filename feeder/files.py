"""Writing files so that nothing half-written ever looks complete, and one writer at a time.

Every output is written to a temporary name in its own folder and renamed into place only when
it is complete (a rename within one folder is atomic on POSIX): a run that fails or is
interrupted leaves the previous file, or none, never a truncated one. A folder that a run fills
is locked for that run (:func:`exclusive_lock`, the kernel's ``flock``: released by the kernel
when the process ends, however it ends, so a killed run leaves no stale lock). This module
imports nothing from feeder but its exceptions, so every layer may use it.
"""

from __future__ import annotations

import contextlib
import fcntl
import os
import secrets
from collections.abc import Iterator
from pathlib import Path

from .exceptions import InputError, OutputBusyError

LOCK_ATTEMPTS = 3
"""Tries to take a lock whose file the previous holder removed between our open and our lock
(each such race needs another run to finish in that instant: three tries are plenty)."""


def path_in(folder: str | Path, name: str, what: str) -> Path:
    """``folder / name``, if ``name`` is a plain file name: not empty, ``.`` or ``..``, and no
    folder in it (so the path cannot lie outside ``folder``).

    Raises:
        InputError: Any other name (the message names ``what``).
    """
    if not name or name in (".", "..") or Path(name).name != name or "\\" in name:
        raise InputError(f"{what} {name!r} is not a file name in {folder}: rename it")
    return Path(folder) / name


@contextlib.contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """A temporary path beside ``path``; renamed onto ``path`` if the block completes, removed
    if it raises.

    Raises:
        InputError: The folder does not exist or cannot be written, or the rename fails.
    """
    path = Path(path)
    # Named before it exists, so that a Ctrl-C at any moment after its creation still finds it.
    temporary: Path | None = path.with_name(f".{path.name}.{secrets.token_hex(8)}.part")
    try:
        try:
            os.close(os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
        except OSError as exc:
            temporary = None  # not created here: nothing of ours to remove
            raise InputError(f"cannot write {path}: {exc.strerror or exc}") from exc
        yield temporary
        os.replace(temporary, path)
    except OSError as exc:
        raise InputError(f"cannot write {path}: {exc.strerror or exc}") from exc
    finally:
        if temporary is not None:
            temporary.unlink(missing_ok=True)


def write_text(path: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically and return the path."""
    path = Path(path)
    with atomic_path(path) as temporary:
        temporary.write_text(text, encoding="utf-8")
    return path


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
