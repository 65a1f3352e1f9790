"""The table of a sweep: one row per case, its peaks and their times (``sweep_peaks.csv``).

Tidy: a row is one case (device, variant, elevation), a column one variable. Columns, in order
(:data:`TABLE_COLUMNS`):

* ``device``, ``variant``: names (the grid's);
* ``elevation_deg``: ε [deg];
* ``case_sha256``: SHA-256 of what defines the case's computation (its key, parameters and
  timing: :attr:`~feeder.study.grid.SweepCase.sha256`): a resumed sweep reuses a row only if it
  matches;
* for each quantity of :data:`QUANTITIES` (a ``cycle.csv`` column: its unit is the column's, SI,
  docs/REFERENCE.md): ``<name>``, the value where |value| peaks (signed for the actuator loads
  and pressures, a magnitude for a reaction), and ``<name>_time`` [s], when;
* the controlled forward run's results (:data:`LOADING_COLUMNS`; ``nan`` in the rows of
  variants without it, and ``loading_settling`` ``nan`` where it does not settle);
* ``row_sha256``: SHA-256 of the row's other cells as written (:func:`row_sha256`): a row edited
  or damaged after it was written no longer matches it.

Floats are written as Python's shortest repr, which reads back as the same float. The same
table can be written as Parquet (``pyarrow``, the optional ``parquet`` extra).
"""

from __future__ import annotations

import csv
import hashlib
import io
import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path

from ..exceptions import InputError
from ..files import atomic_path
from ..validation import check_file
from .columns import VECTORS

TABLE = "sweep_peaks.csv"
"""File name of the table in a sweep's output folder."""

PARQUET = "sweep_peaks.parquet"
"""File name of its Parquet copy."""

QUANTITIES = (
    "piston_force",
    "cylinder_cap_pressure",
    "cylinder_rod_pressure",
    "forearm_torque",
    "rack_force",
    *(name for name, *_ in VECTORS),
)
"""The quantities whose peaks a row holds, in the order of
:func:`~feeder.study.peaks.cycle_peaks`."""

KEY_COLUMNS = ("device", "variant", "elevation_deg")
"""The columns that identify a case."""

LOADING_COLUMNS = (
    "loading_off_line",
    "loading_along_line",
    "loading_angle",
    "loading_settling",
    "controlled_peak_pressure",
    "controlled_peak_rack_force",
    "controlled_saturated_duration",
)
"""The controlled run's columns (:mod:`feeder.dynamics.loading`): at the end of stage 3 the
payload's distance from the rammer's line [m], its offset along it [m] and its axis's angle to it
[rad]; the time to settle within the tolerances [s]; the largest chamber pressure [Pa] and
|rack force| [N] over the cycle; how long a drive's command passes its limit [s]. ``nan`` where
there is no such run (or no settling within the hold)."""

TABLE_COLUMNS = (
    *KEY_COLUMNS,
    "case_sha256",
    *(column for name in QUANTITIES for column in (name, f"{name}_time")),
    *LOADING_COLUMNS,
    "row_sha256",
)
"""Every column of the table, in file order."""

TEXT_COLUMNS = ("device", "variant", "case_sha256", "row_sha256")
"""The columns that hold names and hashes; every other column holds floats."""

Row = dict[str, str | float]
"""A row in memory: every column of :data:`TABLE_COLUMNS` but ``row_sha256`` (the checksum
belongs to the row as written)."""


def row_key(row: Mapping[str, str | float]) -> tuple[str, str, float]:
    """(device, variant, elevation [deg]) of a row."""
    return (str(row["device"]), str(row["variant"]), float(row["elevation_deg"]))


def row_quantities(row: Row) -> list[str]:
    """The quantities of a table row, in column order."""
    return [name for name in row if f"{name}_time" in row]


def row_sha256(cells: Sequence[str]) -> str:
    """SHA-256 of a row's cells as written, every column but ``row_sha256``, in file order
    (as a JSON list: no separator can be mistaken for a cell's text)."""
    return hashlib.sha256(json.dumps(list(cells)).encode("utf-8")).hexdigest()


def _cells(row: Row) -> list[str]:
    """The row as written: every cell (a float as its shortest repr), its checksum last.

    Raises:
        InputError: The row lacks a column.
    """
    try:
        cells = [str(row[name]) for name in TABLE_COLUMNS[:-1]]
    except KeyError as exc:
        raise InputError(f"sweep row {row_key(row)} has no column {exc}") from exc
    return [*cells, row_sha256(cells)]


def write_table(path: str | Path, rows: Sequence[Row]) -> Path:
    """Write ``rows`` as CSV with :data:`TABLE_COLUMNS`, each with its checksum, atomically.

    Raises:
        InputError: A row that lacks a column, or the file cannot be written.
    """
    path = Path(path)
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(TABLE_COLUMNS)
    writer.writerows(_cells(row) for row in rows)
    with atomic_path(path) as temporary:
        temporary.write_text(buffer.getvalue(), encoding="utf-8")
    return path


def check_parquet() -> None:
    """Raise :class:`InputError`, saying how to install it, unless pyarrow can be imported."""
    try:
        import pyarrow.parquet  # noqa: F401
    except ImportError as exc:
        raise InputError("writing Parquet needs pyarrow: pip install 'feeder[parquet]'") from exc


def write_parquet(path: str | Path, rows: Sequence[Row]) -> Path:
    """Write the same table (the same columns, checksums included) as Parquet (needs
    ``pyarrow``), atomically.

    Raises:
        InputError: pyarrow is not installed (the message says how to install it).
    """
    check_parquet()
    import pyarrow as pa
    import pyarrow.parquet as pq

    path = Path(path)
    columns = {name: [row[name] for row in rows] for name in TABLE_COLUMNS[:-1]}
    columns["row_sha256"] = [_cells(row)[-1] for row in rows]
    with atomic_path(path) as temporary:
        pq.write_table(pa.table(columns), temporary)
    return path


def _check_header(path: Path, header: Sequence[str]) -> None:
    """Refuse a table whose columns are not :data:`TABLE_COLUMNS` (another version's table, or
    one edited as a whole): its rows cannot be checked, and recomputing them all would discard
    the file without the user deciding it."""
    if list(header) == list(TABLE_COLUMNS):
        return
    missing = [name for name in TABLE_COLUMNS if name not in header]
    unknown = [name for name in header if name not in TABLE_COLUMNS]
    if missing or unknown:
        problem = "; ".join(
            f"{what} column{'s' if len(names) > 1 else ''} {', '.join(names[:3])}"
            f"{f' and {len(names) - 3} more' if len(names) > 3 else ''}"
            for what, names in (("no", missing), ("unknown", unknown))
            if names
        )
    else:
        problem = "its columns in another order"
    raise InputError(
        f"{path} is not a sweep table of this feeder ({problem}): delete it to start afresh, "
        "or write to another folder"
    )


def _parse(cells: Sequence[str]) -> tuple[Row | None, str]:
    """A written row's values, or None and why it cannot be trusted."""
    if len(cells) != len(TABLE_COLUMNS):
        return None, "unreadable"
    if row_sha256(cells[:-1]) != cells[-1]:
        return None, "checksum mismatch"
    row: Row = {}
    for name, cell in zip(TABLE_COLUMNS[:-1], cells, strict=False):
        if name in TEXT_COLUMNS:
            row[name] = cell
            continue
        try:
            row[name] = float(cell)
        except ValueError:
            return None, "unreadable"
        if not math.isfinite(row[name]) and not (name in LOADING_COLUMNS and cell == "nan"):
            return None, "non-finite value"
    return row, ""


def read_sweep_table(path: str | Path) -> tuple[list[Row], list[tuple[int, str]]]:
    """Read a sweep table: the rows that pass their checks, and the rejected ones.

    A row is rejected when it is unreadable (not one cell per column, or a number that is not
    one), when its ``row_sha256`` does not match its cells (edited or damaged after it was
    written), when a value is not finite, or when its case has more than one row (every one of
    them: which, if any, is right cannot be told).

    Returns:
        (rows, rejected): the rows in file order; (line number, reason) of each rejected row.

    Raises:
        InputError: A missing or unreadable file, or one whose header is not
            :data:`TABLE_COLUMNS` (naming the missing and unknown columns).
    """
    path = check_file("sweep table", path)
    try:
        with path.open(encoding="utf-8", newline="") as handle:
            lines = list(csv.reader(handle))
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise InputError(f"{path} is not a sweep table: {exc}") from exc
    _check_header(path, lines[0] if lines else [])
    parsed: dict[tuple[str, str, float], list[tuple[int, Row]]] = {}
    rejected = []
    for number, cells in enumerate(lines[1:], start=2):
        row, reason = _parse(cells)
        if row is None:
            rejected.append((number, reason))
        else:
            parsed.setdefault(row_key(row), []).append((number, row))
    rows = []
    for copies in parsed.values():
        if len(copies) == 1:
            rows.append(copies[0])
        else:
            rejected += [(number, "duplicated") for number, _ in copies]
    return [row for _, row in sorted(rows, key=lambda pair: pair[0])], sorted(rejected)
