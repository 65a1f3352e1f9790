"""Writing one file so that nothing half-written ever looks complete, and an output of one file.

Every output is written to a temporary name in its own folder and renamed into place only when
it is complete (a rename within one folder is atomic on POSIX): a run that fails or is
interrupted leaves the previous file, or none, never a truncated one.

An output of one file (``--out FILE``, ``--html FILE``) follows the same rule
(:func:`check_replaceable`): a new file, or one that the same command wrote, recognised by the
marker it writes at the file's beginning; any other file is refused, never replaced.
"""

from __future__ import annotations

import contextlib
import os
import secrets
from collections.abc import Callable, Iterator
from pathlib import Path

from ..exceptions import InputError
from ..validation import check_path


def path_in(folder: str | Path, name: str, what: str) -> Path:
    """``folder / name``, if ``name`` is a plain file name: not empty, ``.`` or ``..``, and no
    folder in it (so the path cannot lie outside ``folder``).

    Raises:
        InputError: Any other name (the message names ``what``).
    """
    if not is_plain_name(name):
        raise InputError(f"{what} {name!r} is not a file name in {folder}: rename it")
    return Path(folder) / name


def is_plain_name(name: object) -> bool:
    """Whether ``name`` is a file name without a folder (nor ``.``, ``..``, empty)."""
    return (
        isinstance(name, str)
        and name not in ("", ".", "..")
        and Path(name).name == name
        and "\\" not in name
    )


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


HEAD = 4096
"""Characters at a file's beginning in which :func:`check_replaceable` looks for a marker."""


def check_replaceable(path: str | Path, what: str, ours: str | Callable[[Path], bool]) -> Path:
    """``path`` if a command may write its one output file there: no file yet, or a file that
    the same command wrote, which it then replaces (an output folder's rule for one file).

    Args:
        path: The output file.
        what: The command's own file, for the message (e.g. "a URDF file that feeder urdf
            wrote").
        ours: The marker that the command writes in the first :data:`HEAD` characters of its
            files, or a test of the existing file.

    Raises:
        InputError: An empty path, a folder, or a file that is not the command's own: the
            message names the remedy (another name, or delete the file).
    """
    path = check_path("the output file", path)
    if not (path.exists() or path.is_symlink()):
        return path
    if path.is_file() and (ours(path) if callable(ours) else ours in _head(path)):
        return path
    raise InputError(
        f"{path} exists and is not {what}: choose another name, or delete the file first"
    )


def _head(path: Path) -> str:
    """The first :data:`HEAD` characters of the file ``path`` as text ('' if unreadable)."""
    try:
        with path.open(encoding="utf-8", errors="replace") as handle:
            return handle.read(HEAD)
    except OSError:
        return ""
