"""The user reference documents every column of ``cycle.csv``."""

from __future__ import annotations

import re

from feeder.study.columns import COLUMNS, VECTORS

from .conftest import REPO

REFERENCE = (REPO / "docs" / "REFERENCE.md").read_text(encoding="utf-8")


def test_every_column_is_documented():
    documented = set(re.findall(r"`([a-z0-9_]+)`", REFERENCE))
    vectors = {name for name, *_ in VECTORS}
    missing = []
    for column in COLUMNS:
        base = column.name[:-2] if column.name[-2:] in ("_x", "_y", "_z") else None
        if column.name in documented or (base in vectors and base in documented):
            continue
        missing.append(column.name)
    assert not missing, f"columns not in docs/REFERENCE.md: {missing}"
    assert "followed by its world components `_x`, `_y`, `_z`" in REFERENCE


def test_documented_columns_exist():
    """No stale name: every `name` in the tables' first column is a real column."""
    names = {column.name for column in COLUMNS}
    rows = re.findall(r"^\| (`[a-z0-9_]+`(?:, `[a-z0-9_]+`)*) \|", REFERENCE, flags=re.M)
    for row in rows:
        for name in re.findall(r"`([a-z0-9_]+)`", row):
            if name.endswith(("_joint", "_pin")) or name in ("frame", "cylinder", "piston"):
                continue  # URDF names in the coordinates table
            assert name in names, name


def test_mechanisms_guide_python_example_runs(monkeypatch):
    guide = (REPO / "docs" / "MECHANISMS.md").read_text(encoding="utf-8")
    block = re.search(r"## From Python\n+```python\n(.*?)```", guide, flags=re.S).group(1)
    monkeypatch.chdir(REPO)  # the example's paths are relative to the repository
    exec(compile(block, "docs/MECHANISMS.md", "exec"), {})
