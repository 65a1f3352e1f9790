"""Measure what ``pip install .`` puts on disk: the site-packages of a fresh virtual environment
after a non-editable install of this repository, against issue 19's goal (≤ 750 MB), then the
same with each extra of ``pyproject.toml``.

The wheels are gathered once into a wheelhouse (``pip wheel``: this repository's, its
dependencies', its build requirements'), and every environment installs from it alone, so all
measure the same versions. Kept with ``--wheelhouse DIR``, it makes later runs offline
(``--offline``). Each environment is deleted once measured; the run takes minutes.

Run: ``.venv/bin/python benchmarks/bench_install.py [--wheelhouse DIR [--offline]]``.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))
GOAL_MB = 750.0
MB = 1e6  # [B]


def size_mb(folder: Path) -> float:
    """[MB] ``folder`` as ``du -sb`` counts it: every file's and folder's apparent size (wheels
    hold no symbolic links, so none to follow or not)."""
    total = 0
    for root, _, files in os.walk(folder):
        total += os.lstat(root).st_size
        total += sum(os.lstat(os.path.join(root, name)).st_size for name in files)
    return total / MB


def fill_wheelhouse(wheelhouse: Path, workdir: Path, offline: bool) -> None:
    """This repository's wheel with every extra's dependencies and the build requirements (so
    that an offline run can build the repository again from the wheelhouse)."""
    # Built from a copy: setuptools would leave build/ in the repository, and a module deleted
    # since would stay in build/lib and in later wheels.
    source = workdir / "source"
    shutil.copytree(
        REPO, source, ignore=shutil.ignore_patterns(".git", ".venv", "build", "*.egg-info")
    )
    extras = ",".join(PYPROJECT["project"]["optional-dependencies"])
    index = ["--no-index", "--find-links", str(wheelhouse)] if offline else []
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--quiet", "--wheel-dir", str(wheelhouse)]
        + index
        + [f"{source}[{extras}]", *PYPROJECT["build-system"]["requires"]],
        check=True,
    )


def environment_mb(venv: Path, wheelhouse: Path, requirement: str | None) -> float:
    """[MB] site-packages of a fresh environment at ``venv`` with ``requirement`` installed from
    the wheelhouse (nothing when None); the environment is removed afterwards."""
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    if requirement is not None:
        subprocess.run(
            [venv / "bin" / "pip", "install", "--quiet", "--no-index"]
            + ["--find-links", str(wheelhouse), requirement],
            check=True,
        )
    (site_packages,) = venv.glob("lib/python*/site-packages")
    size = size_mb(site_packages)
    shutil.rmtree(venv)
    return size


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--wheelhouse", type=Path, help="keep the wheels in this folder")
    parser.add_argument(
        "--offline", action="store_true", help="no package index: the --wheelhouse's wheels only"
    )
    args = parser.parse_args(argv)
    if args.offline and args.wheelhouse is None:
        parser.error("--offline installs from a kept --wheelhouse: name it")
    with tempfile.TemporaryDirectory(prefix="bench_install_") as tmp:
        workdir = Path(tmp)
        wheelhouse = args.wheelhouse or workdir / "wheels"
        fill_wheelhouse(wheelhouse, workdir, args.offline)
        venv = workdir / "venv"
        empty = environment_mb(venv, wheelhouse, None)
        print(f"fresh environment (pip, setuptools)  {empty:6.0f} MB")
        base = environment_mb(venv, wheelhouse, "feeder")
        met = "PASS" if base <= GOAL_MB else "MISS"
        print(f"pip install .                        {base:6.0f} MB  goal ≤ {GOAL_MB:g} MB  {met}")
        for extra in PYPROJECT["project"]["optional-dependencies"]:
            size = environment_mb(venv, wheelhouse, f"feeder[{extra}]")
            label = f"pip install '.[{extra}]'"
            print(f"{label:<36} {size:6.0f} MB  (+{size - base:.0f} MB)")


if __name__ == "__main__":
    main()
