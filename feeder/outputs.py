"""The files a study writes: ``cycle.csv`` and its figures, each written atomically.

This is the last step of the data flow (parameters → model → kinematics → dynamics →
cross-check → study → figures → files); the command line calls it.
"""

from __future__ import annotations

from pathlib import Path

from matplotlib.figure import Figure

from .device.feeder import Feeder
from .exceptions import InputError
from .files import atomic_path
from .motion.cycle import CycleKinematics
from .study.columns import kinematic_columns
from .study.csv import write_csv
from .study.cycle_study import CycleStudy
from .viz.report import kinematics_figures, study_figures

FIGURE_DPI = 120
"""Resolution of the written figures [dots per inch]: an 8 × 4.2 in time history is 960 × 504."""


def output_folder(path: str | Path) -> Path:
    """Create the output folder (and its parents) now, so that a bad path fails before any
    computation.

    Raises:
        InputError: The folder cannot be created.
    """
    directory = Path(path)
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot create the output folder {directory}: {exc}") from exc
    return directory


def save_figure(fig: Figure, path: str | Path) -> Path:
    """Write ``fig`` to ``path`` (format from the suffix, e.g. ``.png``), atomically."""
    path = Path(path)
    with atomic_path(path) as temporary:
        fig.savefig(temporary, dpi=FIGURE_DPI, format=path.suffix.lstrip(".") or "png")
    return path


def write_cycle_outputs(study: CycleStudy, directory: str | Path) -> list[Path]:
    """Write ``cycle.csv`` and every figure of the study (:func:`~feeder.viz.study_figures`)
    into ``directory``; returns the paths, the table first."""
    directory = output_folder(directory)
    paths = [write_csv(directory / "cycle.csv", study.columns())]
    for name, fig in study_figures(study).items():
        paths.append(save_figure(fig, directory / name))
    return paths


def write_kinematics_outputs(
    feeder: Feeder, cycle: CycleKinematics, directory: str | Path
) -> list[Path]:
    """Write the kinematic columns of ``cycle.csv`` and Figs. 4 and 10 into ``directory``;
    returns the paths, the table first."""
    directory = output_folder(directory)
    paths = [write_csv(directory / "cycle.csv", kinematic_columns(cycle))]
    for name, fig in kinematics_figures(feeder, cycle).items():
        paths.append(save_figure(fig, directory / name))
    return paths
