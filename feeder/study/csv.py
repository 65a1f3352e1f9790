"""Reading and writing the tables feeder writes (``cycle.csv``, whose columns are in
:mod:`feeder.study.columns`; ``loads.csv``, ``states.csv``), by column name."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..exceptions import InputError
from ..files import atomic_path
from ..validation import check_file


def write_csv(path: str | Path, columns: dict[str, np.ndarray]) -> Path:
    """Write equal-length, finite columns as CSV with a header row, atomically.

    SI units; each number as Python's ``repr`` of the float: the shortest text that reads back
    as the same float (``0.3``, where 17 significant digits write ``0.29999999999999999``); a
    column of integers or truth values (a stage, a flag) as whole numbers (``2``, not ``2.0``).

    Args:
        path: File to write (its folder is created).
        columns: Column name → array of shape (N,).

    Raises:
        InputError: Columns of different lengths, a NaN or infinite value, or the file cannot
            be written.
    """
    path = Path(path)
    lengths = {name: np.shape(values) for name, values in columns.items()}
    if len({shape for shape in lengths.values()}) != 1 or len(next(iter(lengths.values()))) != 1:
        raise InputError(f"columns must be 1-D arrays of one length, got shapes {lengths}")
    table = np.column_stack([np.asarray(values, dtype=float) for values in columns.values()])
    if not np.all(np.isfinite(table)):
        bad = list(columns)[int(np.flatnonzero(~np.all(np.isfinite(table), axis=0))[0])]
        raise InputError(f"column {bad!r} has a NaN or infinite value: not written to {path}")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot write {path}: {exc.strerror or exc}") from exc
    whole = [np.asarray(values).dtype.kind in "biu" for values in columns.values()]
    rows = "\n".join(
        ",".join(
            str(int(x)) if integer else repr(x) for x, integer in zip(row, whole, strict=True)
        )
        for row in table.tolist()
    )
    with atomic_path(path) as temporary:
        temporary.write_text(f"{','.join(columns)}\n{rows}\n", encoding="utf-8")
    return path


def read_csv(path: str | Path) -> dict[str, np.ndarray]:
    """Read a table written by :func:`write_csv` back into named columns, each (N,).

    Raises:
        InputError: The file is missing or unreadable, or is not a table of numbers with a
            header row.
    """
    path = check_file("table", path)
    try:
        with path.open(encoding="utf-8") as handle:
            header = handle.readline().strip().split(",")
        table = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise InputError(f"{path} is not a table of numbers with a header row: {exc}") from exc
    if table.size == 0 or table.shape[1] != len(header) or len(set(header)) != len(header):
        raise InputError(f"{path} is not a table of numbers with a header row")
    if not np.all(np.isfinite(table)):
        raise InputError(f"{path} has a value that is not a finite number")
    return {name: table[:, k].copy() for k, name in enumerate(header)}
