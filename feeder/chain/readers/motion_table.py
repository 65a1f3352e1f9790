"""The motion table (CSV, header row): ``t`` [s] and, for every independent joint j, ``q_j`` and
optionally ``v_j``, ``a_j`` (SI units); rates that are missing are differentiated from the
positions (second-order central differences, ``numpy.gradient``)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...exceptions import InputError
from ...validation import check_finite, check_path


@dataclass(frozen=True)
class MotionTable:
    """A prescribed motion of the independent joints.

    Attributes:
        t: Times [s], (N,).
        x, dx, ddx: Positions, rates and accelerations of the independent joints (N, n).
        differentiated: Joints whose rates were differentiated from the positions.
    """

    t: np.ndarray
    x: np.ndarray
    dx: np.ndarray
    ddx: np.ndarray
    differentiated: tuple[str, ...]


def read_motion(path: str | Path, independent: tuple[str, ...]) -> MotionTable:
    """Read a motion table (module docstring) for the ``independent`` joints.

    Raises:
        InputError: Missing or malformed file, a missing column or one the table does not take
            (named), non-finite values, times that do not increase.
    """
    if (
        not isinstance(independent, tuple | list)
        or not independent
        or not all(isinstance(name, str) for name in independent)
    ):
        raise InputError(f"independent must be a list of joint names, got {independent!r}")
    path, header, columns = read_columns(path, "the motion file")
    t = columns["t"]
    for joint in independent:
        if f"q_{joint}" not in columns:
            raise InputError(f"{path}: no column 'q_{joint}' for independent joint {joint!r}")
    _refuse_other_columns(path, header, independent)
    x, dx, ddx, differentiated = [], [], [], []
    for joint in independent:
        position = columns[f"q_{joint}"]
        if (f"v_{joint}" not in columns or f"a_{joint}" not in columns) and t.size < 3:
            raise InputError(
                f"{path}: the rates of {joint!r} are differentiated from its positions, which "
                "needs at least 3 rows; give v_ and a_ columns or more samples"
            )
        rate = columns.get(f"v_{joint}")
        if rate is None:
            rate = np.gradient(position, t, edge_order=2)
            differentiated.append(joint)
        acceleration = columns.get(f"a_{joint}")
        if acceleration is None:
            acceleration = np.gradient(rate, t, edge_order=2)
            differentiated.append(joint)
        x.append(position)
        dx.append(rate)
        ddx.append(acceleration)
    return MotionTable(
        t=t,
        x=np.column_stack(x),
        dx=np.column_stack(dx),
        ddx=np.column_stack(ddx),
        differentiated=tuple(dict.fromkeys(differentiated)),
    )


def read_columns(path: str | Path, what: str) -> tuple[Path, list[str], dict[str, np.ndarray]]:
    """A CSV table of numbers with a header row and a column ``t`` [s] of increasing times:
    (the path, the header, column name → values (N,)).

    Raises:
        InputError: A missing or unreadable file, rows of other lengths than the header, text
            or non-finite values, fewer than two rows, no ``t``, times that do not increase.
    """
    path = check_path(what, path)
    if not path.is_file():
        raise InputError(f"{what} not found: {path}")
    try:
        lines = path.read_text(encoding="utf-8-sig").splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read {what} {path}: {exc}") from exc
    rows = [line.split(",") for line in lines if line.strip()]
    if len(rows) < 3:
        raise InputError(f"{path}: a header row and at least two rows of numbers are needed")
    header = [name.strip() for name in rows[0]]
    if any(len(row) != len(header) for row in rows[1:]):
        raise InputError(f"{path}: every row must have {len(header)} values, like the header")
    if len(set(header)) != len(header):
        raise InputError(f"{path}: a column name appears twice in the header {header}")
    try:
        table = np.array([[float(x) for x in row] for row in rows[1:]])
    except ValueError as exc:
        raise InputError(f"{path}: every row after the header must be numbers: {exc}") from exc
    table = check_finite(f"{path}", table)
    columns = {name: table[:, i] for i, name in enumerate(header)}
    if "t" not in columns:
        raise InputError(f"{path}: no column 't' [s]; columns: {header}")
    if np.any(np.diff(columns["t"]) <= 0.0):
        raise InputError(f"{path}: times must increase")
    return path, header, columns


def _refuse_other_columns(path: Path, header: list[str], independent: tuple[str, ...]) -> None:
    """Raise :class:`InputError` for the first column that is neither ``t`` nor a ``q_``,
    ``v_`` or ``a_`` column of an independent joint: a dependent joint's motion follows from the
    loops and cannot be prescribed too, and a misspelt column would be ignored."""
    taken = {"t"} | {f"{kind}_{joint}" for joint in independent for kind in "qva"}
    for name in header:
        if name not in taken:
            raise InputError(
                f"{path}: column {name!r} is not t nor q_/v_/a_ of the independent joints "
                f"{list(independent)}: remove it, or make its joint independent in the "
                "mechanism file"
            )
