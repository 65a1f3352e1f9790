"""The user reference documents every column of ``cycle.csv``."""

from __future__ import annotations

import importlib.util
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


def test_mechanisms_guide_check_report_is_the_program_s():
    """The guide's --check example is what the command prints for the four-bar, every number
    (the report once said 0.146 and 1.8 where the program said 0.157 and 1.42)."""
    from feeder.study.analyze import check_mechanism

    guide = (REPO / "docs" / "MECHANISMS.md").read_text(encoding="utf-8")
    block = re.search(r"## The mobility report \(`--check`\)\n+```\n(.*?)```", guide, flags=re.S)
    check = check_mechanism(REPO / "examples" / "four_bar" / "closures.toml")
    assert block.group(1) == check.text + "\n"


def _pictures_script():
    """docs/pictures.py, imported from its file (it is a script, not a module of the package)."""
    spec = importlib.util.spec_from_file_location("pictures", REPO / "docs" / "pictures.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_readme_pictures_are_current():
    """Every picture in the README is one docs/pictures.py makes, and was made from the files
    as they are now (the fingerprint it carries is recomputed from them): after a change to the
    drawing code, the model or the inputs, run ``python docs/pictures.py``."""
    pictures = _pictures_script()
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    shown = set(re.findall(r"\]\(docs/([\w.]+\.png)\)", readme))
    assert shown == set(pictures.PICTURES)
    stale = [
        name for name in sorted(shown) if pictures.stamped(name) != pictures.fingerprint(name)
    ]
    assert not stale, f"run `python docs/pictures.py {' '.join(stale)}`: made from older files"


def test_picture_fingerprints_see_their_sources(tmp_path):
    """A fingerprint changes when a file it covers does (a copy of the viewer picture's sources
    with one drawing module edited)."""
    pictures = _pictures_script()
    for pattern in pictures.PICTURES["viewer.png"]:
        for path in REPO.glob(pattern):
            copy = tmp_path / path.relative_to(REPO)
            copy.parent.mkdir(parents=True, exist_ok=True)
            copy.write_bytes(path.read_bytes())
    pictures.ROOT = tmp_path
    before = pictures.fingerprint("viewer.png")
    assert before == pictures.fingerprint("viewer.png")
    with (tmp_path / "feeder" / "viz" / "scene.py").open("a", encoding="utf-8") as source:
        source.write("# an edit\n")
    assert pictures.fingerprint("viewer.png") != before
