"""What the tests of the IFToMM examples (``examples/iftomm``) share: the README's
``feeder simulate`` command of an example, and an example's reference module."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from types import ModuleType

import numpy as np

from feeder.cli import main
from feeder.study.csv import read_csv

from ..conftest import REPO

FOLDER = REPO / "examples" / "iftomm"


def readme_states(stem: str, duration: float, out: Path) -> dict[str, np.ndarray]:
    """states.csv of ``feeder simulate examples/iftomm/STEM.urdf --closures STEM.toml --duration
    DURATION --rtol 1e-10 --atol 1e-12 --no-figures --out OUT``, the README's command without
    its figures."""
    arguments = [
        "simulate", str(FOLDER / f"{stem}.urdf"), "--closures", str(FOLDER / f"{stem}.toml"),
        "--duration", f"{duration:g}", "--rtol", "1e-10", "--atol", "1e-12", "--no-figures",
        "--out", str(out),
    ]  # fmt: skip
    assert main(arguments) == 0
    return read_csv(out / "states.csv")


def reference_module(stem: str) -> ModuleType:
    """examples/iftomm/STEM_reference.py, loaded from its file (an example, not a package)."""
    spec = importlib.util.spec_from_file_location(
        f"{stem}_reference", FOLDER / f"{stem}_reference.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
