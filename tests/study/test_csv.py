"""Reading and writing ``cycle.csv`` (feeder.study.csv): exact round trip, refusal of NaN,
atomic writes, and clear errors for files that are not cycle tables."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from feeder.exceptions import InputError
from feeder.study.csv import read_csv, write_csv

ROWS = 50


@pytest.fixture
def columns(rng):
    """Random floats over many magnitudes, a count column and a flag column."""
    return {
        "t": np.linspace(0.0, 1.0, ROWS),
        "stage": np.repeat([1, 2], ROWS // 2),
        "value": rng.normal(0.0, 1.0, ROWS) * 10.0 ** rng.integers(-12, 12, ROWS),
    }


def _folder_listing(folder: Path) -> list[str]:
    """Every entry of ``folder``, hidden temporary files included."""
    return sorted(path.name for path in folder.iterdir())


def test_round_trip_is_exact(columns, tmp_path):
    path = write_csv(tmp_path / "sub" / "cycle.csv", columns)
    table = read_csv(path)
    assert list(table) == list(columns)
    for name, values in columns.items():
        np.testing.assert_array_equal(table[name], values, err_msg=name)
    assert _folder_listing(path.parent) == ["cycle.csv"]


@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_refuses_nan_and_leaves_no_file(columns, tmp_path, bad):
    columns["value"][7] = bad
    path = tmp_path / "cycle.csv"
    with pytest.raises(InputError, match="'value'"):
        write_csv(path, columns)
    assert _folder_listing(tmp_path) == []


def test_refused_write_leaves_an_existing_file_untouched(columns, tmp_path):
    path = write_csv(tmp_path / "cycle.csv", columns)
    before = path.read_bytes()
    columns["t"] = columns["t"].copy()
    columns["t"][0] = np.nan
    with pytest.raises(InputError, match="'t'"):
        write_csv(path, columns)
    assert path.read_bytes() == before
    assert _folder_listing(tmp_path) == ["cycle.csv"]


def test_failed_write_is_atomic(columns, tmp_path, monkeypatch):
    """A write that fails half-way (disk full) leaves the previous file as it was, and no
    partial file beside it."""
    path = write_csv(tmp_path / "cycle.csv", columns)
    before = path.read_bytes()

    write_text = Path.write_text

    def half_written(self, text, *args, **kwargs):
        write_text(self, text[: len(text) // 2], *args, **kwargs)
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(Path, "write_text", half_written)
    with pytest.raises(InputError, match="No space left"):
        write_csv(path, columns)
    assert path.read_bytes() == before
    assert _folder_listing(tmp_path) == ["cycle.csv"]
    # Without a previous file, nothing is left at all.
    with pytest.raises(InputError, match="No space left"):
        write_csv(tmp_path / "new.csv", columns)
    assert _folder_listing(tmp_path) == ["cycle.csv"]


def test_shortest_text_that_reads_back(tmp_path):
    """Each number is written as the shortest text that reads back as the same float: 0.3, not
    its 17 significant digits 0.29999999999999999; 0.1 + 0.2 keeps all 17 it needs."""
    path = write_csv(tmp_path / "cycle.csv", {"a": np.array([0.3, 0.1 + 0.2, 1.0, -0.0])})
    assert path.read_text(encoding="utf-8").splitlines() == [
        "a",
        "0.3",
        "0.30000000000000004",
        "1.0",
        "-0.0",
    ]
    back = read_csv(path)["a"]
    np.testing.assert_array_equal(back, [0.3, 0.1 + 0.2, 1.0, -0.0])
    assert np.signbit(back[3])


def test_integer_and_flag_columns_are_whole_numbers(tmp_path):
    """A stage (1, 2, 3) and a flag (0, 1) read as REFERENCE.md lists them; a float column of
    whole values stays a float."""
    columns = {"stage": np.array([1, 2, 3]), "payload": np.array([False, True, True]),
               "t": np.array([0.0, 1.0, 2.0])}  # fmt: skip
    path = write_csv(tmp_path / "cycle.csv", columns)
    assert path.read_text(encoding="utf-8").splitlines()[1:] == ["1,0,0.0", "2,1,1.0", "3,1,2.0"]
    np.testing.assert_array_equal(read_csv(path)["stage"], [1.0, 2.0, 3.0])


def test_refuses_ragged_columns(columns, tmp_path):
    columns["t"] = columns["t"][:-1]
    with pytest.raises(InputError, match="one length"):
        write_csv(tmp_path / "cycle.csv", columns)
    assert _folder_listing(tmp_path) == []


def test_reading_a_missing_file_raises(tmp_path):
    with pytest.raises(InputError, match="table not found"):
        read_csv(tmp_path / "missing.csv")
    with pytest.raises(InputError, match="is a folder, not a file"):
        read_csv(tmp_path)  # a folder is not a table either


@pytest.mark.parametrize(
    "text",
    [
        "This is a README, not a table.\nIt has two lines.\n",
        "t,stage\n0.0,one\n",
        "t,stage\n0.0,1\n0.1,1,7\n",
    ],
    ids=["prose", "text-cell", "ragged"],
)
def test_reading_a_text_file_that_is_not_a_table_raises(tmp_path, text):
    path = tmp_path / "notes.csv"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputError, match="not a table of numbers"):
        read_csv(path)
