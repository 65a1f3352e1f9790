"""The motion table (CSV, header row): ``t`` [s] and, for every independent joint j, ``q_j`` and
optionally ``v_j``, ``a_j`` (SI units); rates that are missing are differentiated from the
positions (second-order central differences, ``numpy.gradient``), rates that are given are
checked against them (:func:`check_rates`): all-zero rates beside moving positions once cost an
excavator's cylinder forces 8–21 % of their peaks, silently."""

from __future__ import annotations

from dataclasses import dataclass
from decimal import Decimal
from pathlib import Path

import numpy as np

from ...exceptions import InputError
from ...validation import check_file, check_finite


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
            (named), non-finite values, times that do not increase, rates that contradict the
            positions (:func:`check_rates`).
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
        _check_given_rates(path, columns, joint)
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


def _check_given_rates(path: Path, columns: dict[str, np.ndarray], joint: str) -> None:
    """:func:`check_rates` on the rate columns the table gives for ``joint``: ``v_`` against
    ``q_``, ``a_`` against ``v_`` or, without it, ``q_``."""
    q, v, a = (f"{kind}_{joint}" for kind in "qva")
    given = {name: (columns[name], name) for name in (q, v, a) if name in columns}
    if v in given:
        check_rates(path, columns["t"], given[q], given[v])
    if a in given:
        below = given.get(v, given[q])
        check_rates(path, columns["t"], below, given[a], order=1 if v in given else 2)


def check_rates(
    path: Path,
    t: np.ndarray,
    values: tuple[np.ndarray, str],
    rates: tuple[np.ndarray, str],
    order: int = 1,
    unit: float = 1.0,
) -> None:
    """Refuse a table's rates (a column (N,) and its name) that contradict the values (N,) they
    are the ``order``-th time derivative of (1: a position's speed or a speed's acceleration; 2:
    a position's acceleration), at times ``t`` [s] (N,). ``unit`` is the rates' unit in the
    values' unit (per second or second²): π/180 for rates in degrees beside values in radians;
    both columns are taken as written, for their digits.

    Over each run of ``order`` + 1 samples i … i + order, the values' divided difference times
    order! is their derivative at some instant of the run (the mean value theorem; a weighted
    mean of it where it steps), and must match the mean of the rates at those samples within
    what the table's sampling leaves open:

    * the rates' spread over the run and one sample on each side: the derivative stays there
      (a peak between two samples is within its neighbours' reach, a step of the acceleration
      inside an interval, as in a trapezoidal speed profile, within its two ends);
    * the values' and rates' written digits: half a unit in the last digit of each number
      (:func:`_half_units`), carried through the divided difference;
    * the times' rounding: each step is uncertain by its two times' last digits, or by its
      difference from the mean step if that is less (a uniform grid's steps differ only by their
      rounding: 0 on an exact grid such as 0, 0.01, 0.02 …, whose digits alone would leave
      0.01 s open), carried through likewise.

    Raises:
        InputError: The first run that disagrees, with the two columns, its times and data rows,
            both rates and the tolerance.
    """
    (value, value_name), (rate, rate_name) = values, rates
    rate_digits = _half_units(rate) * unit
    rate = rate * unit
    window = np.lib.stride_tricks.sliding_window_view
    steps, digits_t = np.diff(t), _half_units(t)
    step_error = np.minimum(digits_t[:-1] + digits_t[1:], np.abs(steps - steps.mean()))
    derivative, error = value, _half_units(value)
    for level in range(1, order + 1):
        span = t[level:] - t[:-level]
        span_error = window(step_error, level).sum(axis=1)
        derivative = level * np.diff(derivative) / span
        error = level * (error[1:] + error[:-1]) / span + np.abs(derivative) * span_error / span
    reach = window(np.pad(rate, 1, mode="edge"), order + 3)
    mean = window(rate, order + 1).mean(axis=1)
    digits = window(rate_digits, order + 1).max(axis=1)
    tolerance = reach.max(axis=1) - reach.min(axis=1) + error + digits
    miss = np.abs(derivative - mean)
    bad = np.flatnonzero(miss > tolerance)
    if bad.size:
        i = int(bad[0])
        per = "per second" if order == 1 else "per second²"
        converted = "" if unit == 1.0 else f" in the unit of {value_name!r}"
        raise InputError(
            f"{path}: column {rate_name!r} contradicts {value_name!r} between t = {t[i]:g} s and "
            f"{t[i + order]:g} s (data rows {i + 1} to {i + order + 1}): {value_name!r} changes "
            f"by {derivative[i]:.6g} {per} there, {rate_name!r} says {mean[i]:.6g}{converted} "
            f"(off by {miss[i]:.3g}, more than the {tolerance[i]:.3g} the sampling allows): "
            "correct it, or leave the column out to have the rates differentiated"
        )


def _half_units(column: np.ndarray) -> np.ndarray:
    """Half a unit in the last digit each value (N,) was written with, at least its rounding to
    binary. The column is taken as written with a fixed number of decimals or of significant
    digits (the most any of its values shows in its shortest form, ``repr``, which drops
    trailing zeros: 1.5 among 1.5015, 1.503 is 1.5000), whichever leaves a value the larger
    rounding: 0.698 → 5e-4 in a column of 3 decimals, 12.3457 → 5e-5 in one of 6 digits."""
    forms = [Decimal(repr(x)).normalize() for x in column.tolist()]
    written = [form.as_tuple() for form in forms if form]
    units = np.zeros(column.size)
    if written:
        decimals = max(-form.exponent for form in written)
        significant = max(len(form.digits) for form in written)
        leading = np.array([form.adjusted() if form else -np.inf for form in forms])
        units = 0.5 * np.maximum(10.0**-decimals, 10.0 ** (leading - significant + 1))
    return np.maximum(units, np.spacing(np.abs(column)))


def read_columns(path: str | Path, what: str) -> tuple[Path, list[str], dict[str, np.ndarray]]:
    """A CSV table of numbers with a header row and a column ``t`` [s] of increasing times:
    (the path, the header, column name → values (N,)).

    Raises:
        InputError: A missing or unreadable file, rows of other lengths than the header, text
            or non-finite values, fewer than two rows, no ``t``, times that do not increase.
    """
    path = check_file(what, path)
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
