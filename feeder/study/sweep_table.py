"""The table of a sweep: one row per case, its peaks and their times (``sweep_peaks.csv``).

Tidy: a row is one case (device, variant, elevation), a column one variable. Columns, in order:

* ``device``, ``variant``: names (the grid's);
* ``elevation_deg``: ε [deg];
* ``fingerprint``: a hash of the case's parameters and timing
  (:func:`~feeder.study.grid.fingerprint`): a resumed sweep reuses a row only if it matches;
* for each quantity of :func:`~feeder.study.peaks.cycle_peaks` (a ``cycle.csv`` column: its unit
  is the column's, SI, docs/REFERENCE.md): ``<name>``, the value where |value| peaks (signed for
  the actuator loads and pressures, a magnitude for a reaction), and ``<name>_time`` [s], when.

Floats are written as Python's shortest repr, which reads back as the same float. The same
table can be written as Parquet (``pyarrow``, the optional ``parquet`` extra).
"""

from __future__ import annotations

import csv
import io
from collections.abc import Mapping, Sequence
from pathlib import Path

from ..exceptions import InputError
from ..files import atomic_path

TABLE = "sweep_peaks.csv"
"""File name of the table in a sweep's output folder."""

PARQUET = "sweep_peaks.parquet"
"""File name of its Parquet copy."""

TEXT_COLUMNS = ("device", "variant", "fingerprint")
"""The columns that hold names; every other column holds floats."""

KEY_COLUMNS = ("device", "variant", "elevation_deg")
"""The columns that identify a case."""

Row = dict[str, str | float]


def table_columns(quantities: Sequence[str]) -> list[str]:
    """Every column of a table with peaks of ``quantities``, in file order."""
    columns = ["device", "variant", "elevation_deg", "fingerprint"]
    for name in quantities:
        columns += [name, f"{name}_time"]
    return columns


def row_key(row: Mapping[str, str | float]) -> tuple[str, str, float]:
    """(device, variant, elevation [deg]) of a row."""
    return (str(row["device"]), str(row["variant"]), float(row["elevation_deg"]))


def write_table(path: str | Path, rows: Sequence[Row], columns: Sequence[str]) -> Path:
    """Write ``rows`` (each with every one of ``columns``) as CSV, atomically.

    Raises:
        InputError: A row that lacks a column, or the file cannot be written.
    """
    path = Path(path)
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(columns)
    for row in rows:
        try:
            writer.writerow([row[name] for name in columns])  # str(float) is its exact repr
        except KeyError as exc:
            raise InputError(f"sweep row {row_key(row)} has no column {exc}") from exc
    with atomic_path(path) as temporary:
        temporary.write_text(buffer.getvalue(), encoding="utf-8")
    return path


def check_parquet() -> None:
    """Raise :class:`InputError`, saying how to install it, unless pyarrow can be imported."""
    try:
        import pyarrow.parquet  # noqa: F401
    except ImportError as exc:
        raise InputError("writing Parquet needs pyarrow: pip install 'feeder[parquet]'") from exc


def write_parquet(path: str | Path, rows: Sequence[Row], columns: Sequence[str]) -> Path:
    """Write the same table as Parquet (needs ``pyarrow``), atomically.

    Raises:
        InputError: pyarrow is not installed (the message says how to install it).
    """
    check_parquet()
    import pyarrow as pa
    import pyarrow.parquet as pq

    path = Path(path)
    table = pa.table({name: [row[name] for row in rows] for name in columns})
    with atomic_path(path) as temporary:
        pq.write_table(table, temporary)
    return path


def read_table(path: str | Path) -> tuple[list[Row], list[str]]:
    """Read a sweep table: its rows and its columns.

    Raises:
        InputError: A missing file, or one that is not a sweep table (a header with the key
            columns, then rows of names and numbers of the header's width).
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(f"no such file: {path}")
    try:
        with path.open(encoding="utf-8", newline="") as handle:
            lines = list(csv.reader(handle))
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise InputError(f"{path} is not a sweep table: {exc}") from exc
    if not lines or not set(KEY_COLUMNS + ("fingerprint",)) <= set(lines[0]):
        raise InputError(f"{path} is not a sweep table: no header with {', '.join(KEY_COLUMNS)}")
    columns = lines[0]
    rows = []
    for number, cells in enumerate(lines[1:], start=2):
        if len(cells) != len(columns):
            raise InputError(
                f"{path}, line {number}: {len(cells)} cells for {len(columns)} columns"
            )
        try:
            rows.append(
                {
                    name: cell if name in TEXT_COLUMNS else float(cell)
                    for name, cell in zip(columns, cells, strict=True)
                }
            )
        except ValueError as exc:
            raise InputError(f"{path}, line {number}: {exc}") from exc
    return rows, columns
