"""Writing results: the cycle table (``cycle.csv``) in the column contract of REFERENCE.md."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .exceptions import InputError


def write_csv(path: str | Path, columns: dict[str, np.ndarray]) -> Path:
    """Write equal-length columns as CSV with a header row.

    SI units; 17 significant digits, so that reading the file back gives the same floats.

    Args:
        path: File to write (its folder is created).
        columns: Column name → array of shape (N,).

    Raises:
        InputError: Columns of different lengths, or the file cannot be written.
    """
    path = Path(path)
    lengths = {name: np.shape(values) for name, values in columns.items()}
    if len({shape for shape in lengths.values()}) != 1 or len(next(iter(lengths.values()))) != 1:
        raise InputError(f"columns must be 1-D arrays of one length, got shapes {lengths}")
    table = np.column_stack([np.asarray(values, dtype=float) for values in columns.values()])
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        np.savetxt(path, table, delimiter=",", header=",".join(columns), comments="", fmt="%.17g")
    except OSError as exc:
        raise InputError(f"cannot write {path}: {exc}") from exc
    return path


def read_csv(path: str | Path) -> dict[str, np.ndarray]:
    """Read a table written by :func:`write_csv` back into named columns."""
    table = np.genfromtxt(path, delimiter=",", names=True)
    return {name: np.asarray(table[name]) for name in table.dtype.names}
