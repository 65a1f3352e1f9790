"""The files a study writes into its output folder: ``cycle.csv``, its figures and a manifest.

This is the last step of the data flow (parameters → model → kinematics → dynamics →
cross-check → study → figures → files); the command line calls it. An output folder holds the
outputs of one run, written by one run at a time:

* :class:`OutputFolder` checks the path before anything is computed, and creates nothing: not
  empty, not a file, and a new folder, an empty one, or one that an earlier feeder run wrote
  (it has a manifest). Any other folder is refused: its files could pass for this run's.
* For the run it creates the folder and locks it (:func:`~feeder.files.exclusive_lock`): a
  second run on the same folder is refused at once. A run that fails or is interrupted removes
  the folder if it created it.
* Every file is written atomically (:mod:`feeder.files`). The manifest :data:`MANIFEST` says
  which command, feeder version and parameter set (with its SHA-256) made the outputs, when,
  and the SHA-256 of each output. It is written first marked incomplete (listing this run's
  files and the previous run's), then complete once every output is in place; then the
  previous run's outputs that this run did not rewrite are removed. So the folder never mixes
  two runs without its manifest saying so.
"""

from __future__ import annotations

import hashlib
import importlib.metadata
import json
import math
from collections.abc import Callable, Mapping
from datetime import UTC, datetime
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .chain.model.closure import ClosedChain
from .device.feeder import Feeder
from .device.parameter_file import parameters_sha256
from .exceptions import InputError
from .files import exclusive_lock, write_text
from .motion.cycle import CycleKinematics
from .study.analyze import Analysis
from .study.columns import kinematic_columns
from .study.csv import write_csv
from .study.cycle_study import CycleStudy
from .study.simulate import Simulation
from .study.view import MechanismView, analysis_view, simulation_view
from .validation import check_path
from .viz.report import (
    FigureData,
    FigureWorkers,
    kinematics_figures,
    png_bytes,
    study_figure_names,
    write_png,
)

if TYPE_CHECKING:
    from matplotlib.figure import Figure

MANIFEST = "feeder-run.json"
"""The manifest of the run that wrote an output folder (JSON)."""

LOCK = ".feeder-run.lock"
"""The lock file of an output folder while a run writes it (removed when the run ends)."""

Writer = Callable[[Path], object]
"""Writes one output file, atomically, at the path it is given."""


class OutputFolder:
    """The output folder of one run: checked now, created and locked in a ``with`` block.

    Args:
        path: The folder.

    Raises:
        InputError: An empty path, a path that is a file or lies under one, or a folder that
            holds files but no feeder manifest (or a manifest that cannot be read).
    """

    def __init__(self, path: str | Path):
        self.path = check_path("the output folder", path)
        self._created = False
        self._lock = None
        self._written: tuple[str, ...] = ()
        self._previous_files()  # the checks, before anything exists

    def __enter__(self) -> OutputFolder:
        try:
            self.path.mkdir(parents=True)  # raises if it exists: of two runs, one created it
            self._created = True
        except FileExistsError:
            self._created = False
        except OSError as exc:
            raise InputError(
                f"cannot create the output folder {self.path}: {exc.strerror or exc}"
            ) from exc
        lock = exclusive_lock(self.path / LOCK, f"the output folder {self.path}")
        try:
            lock.__enter__()
        except BaseException:
            self._remove_if_created(())
            raise
        self._lock = lock
        try:
            self._previous_files()  # again, now that no other run can change the folder
        except BaseException as error:
            self.__exit__(type(error), error, error.__traceback__)  # unlock, then clean up
            raise
        return self

    def __exit__(self, kind, error, traceback) -> None:
        self._lock.__exit__(None, None, None)
        self._lock = None
        if kind is not None:
            self._remove_if_created(self._written)

    def write(self, outputs: Mapping[str, Writer], record: Mapping[str, object]) -> list[Path]:
        """Write every output (name → writer) and the manifest; remove the previous run's
        outputs that were not rewritten. Returns the paths, in the order of ``outputs``.

        Args:
            outputs: File name (in this folder) → function writing that file atomically.
            record: What the run computed and from what (JSON-serialisable), for the manifest.

        Raises:
            InputError: Not inside the ``with`` block, or a file cannot be written.
        """
        if self._lock is None:
            raise InputError(f"write into the output folder {self.path} inside its with block")
        previous = self._previous_files()
        started = _now()
        self._written = tuple(outputs) + (MANIFEST,)
        listed = dict.fromkeys([*outputs, *previous])
        self._write_manifest(record, started, None, dict.fromkeys(listed))
        paths = []
        for name, writer in outputs.items():
            writer(self.path / name)
            paths.append(self.path / name)
        hashes = {name: _sha256(self.path / name) for name in outputs}
        self._write_manifest(record, started, _now(), hashes)
        for name in previous:
            if name not in outputs:
                (self.path / name).unlink(missing_ok=True)
        return paths

    def _previous_files(self) -> list[str]:
        """The outputs an earlier run listed in this folder's manifest ([] for a new or empty
        folder); raises if the folder is not an output folder."""
        if not self.path.exists():
            parent = next(p for p in self.path.parents if p.exists())
            if not parent.is_dir():
                raise InputError(
                    f"cannot create the output folder {self.path}: {parent} is a file"
                )
            return []
        if not self.path.is_dir():
            raise InputError(f"the output folder {self.path} is a file")
        manifest = self.path / MANIFEST
        if not manifest.is_file():
            others = sorted(p.name for p in self.path.iterdir() if p.name != LOCK)
            if others:
                raise InputError(
                    f"the output folder {self.path} holds files that no feeder run wrote "
                    f"({', '.join(others[:3])}{', …' if len(others) > 3 else ''}): choose a new "
                    "or empty folder"
                )
            return []
        try:
            files = json.loads(manifest.read_text(encoding="utf-8"))["files"]
            if not isinstance(files, dict):
                raise TypeError(f"its files are {files!r}, not a table of names")
            names = list(files)
        except (OSError, ValueError, KeyError, TypeError) as exc:
            raise InputError(
                f"the output folder {self.path} has a {MANIFEST} that is not a feeder manifest "
                f"({exc}): choose a new or empty folder"
            ) from exc
        if any(
            Path(name).name != name or name in ("", ".", "..", MANIFEST, LOCK) for name in names
        ):
            raise InputError(f"the manifest {manifest} lists files outside its folder: {names}")
        return names

    def _write_manifest(
        self,
        record: Mapping[str, object],
        started: str,
        finished: str | None,
        files: Mapping[str, str | None],
    ) -> None:
        manifest = {
            "complete": finished is not None,
            **record,
            "feeder_version": importlib.metadata.version("feeder"),
            "started": started,
            "finished": finished,
            "files": dict(files),
        }
        write_text(self.path / MANIFEST, json.dumps(manifest, indent=2, ensure_ascii=False) + "\n")

    def _remove_if_created(self, names: tuple[str, ...]) -> None:
        """After a failed run: remove the folder if this run created it (its files only)."""
        if not self._created:
            return
        for name in names:
            (self.path / name).unlink(missing_ok=True)
        try:
            self.path.rmdir()
        except OSError:
            pass  # something else was put there meanwhile: leave it
        self._created = False


def run_record(feeder: Feeder, cycle: CycleKinematics, command: str | None) -> dict[str, object]:
    """The manifest's description of a run: command, device, parameter hash, cycle inputs."""
    return {
        "command": command or "Python API (feeder.outputs)",
        "device": feeder.params.name,
        "parameters_sha256": parameters_sha256(feeder.params),
        "elevation_deg": math.degrees(cycle.elevation),
        "stage_durations_s": list(cycle.spec.durations),
        "sample_rate_hz": cycle.spec.rate,
    }


def write_cycle_outputs(
    study: CycleStudy,
    directory: str | Path | OutputFolder,
    command: str | None = None,
    figures: bool = True,
    workers: FigureWorkers | None = None,
) -> list[Path]:
    """Write ``cycle.csv``, every figure of the study (:func:`~feeder.viz.study_figures`) and
    the manifest into ``directory`` (an :class:`OutputFolder` already entered, or a path: it is
    checked, locked and written); returns the paths, the table first.

    Args:
        study: The cycle.
        directory: The output folder.
        command: The command line that made the study, for the manifest.
        figures: Draw the figures (False: the table and the manifest only, for batch use).
        workers: Figure worker processes entered before the study was computed (they have
            imported matplotlib meanwhile), which draw while the table is written; default:
            draw here, one figure after the other.
    """
    kinematics = study.dynamics.kinematics
    outputs: dict[str, Writer] = {"cycle.csv": lambda path: write_csv(path, study.columns())}
    if figures:
        drawing = FigureWorkers(1) if workers is None else workers
        outputs |= drawing.writers(FigureData.of_study(study), study_figure_names())
    record = run_record(study.feeder, kinematics, command)
    record["forward_run"] = study.dynamics.forward is not None
    return _write(directory, outputs, record)


def write_kinematics_outputs(
    feeder: Feeder,
    cycle: CycleKinematics,
    directory: str | Path | OutputFolder,
    command: str | None = None,
) -> list[Path]:
    """Write the kinematic columns of ``cycle.csv``, Figs. 4 and 10 and the manifest into
    ``directory`` (as :func:`write_cycle_outputs`); returns the paths, the table first."""
    outputs: dict[str, Writer] = {
        "cycle.csv": lambda path: write_csv(path, kinematic_columns(cycle))
    }
    outputs |= _figure_writers(kinematics_figures(feeder, cycle))
    return _write(directory, outputs, run_record(feeder, cycle, command))


def write_analysis_outputs(
    analysis: Analysis, directory: str | Path | OutputFolder, command: str | None = None
) -> list[Path]:
    """Write a mechanism's analysis (``feeder analyze``): ``loads.csv``
    (:meth:`~feeder.study.analyze.Analysis.columns`), ``summary.txt`` (the mobility report, the
    assembled pose and the peaks), ``assembled_pose.csv``, its figures
    (:func:`~feeder.viz.analysis.analysis_figures`) and the manifest;
    returns the paths, the table first."""
    from .viz.analysis import analysis_figures

    record = {
        "actuated": list(analysis.spec.actuated),
        "independent": list(analysis.spec.independent),
        "samples": int(analysis.motion.t.size),
        "gravity": {
            "value": analysis.chain.model.gravity.linear.tolist(),
            "assumed": analysis.spec.gravity is None,
        },
    }
    return _write_mechanism(
        directory,
        command,
        analysis,
        "loads.csv",
        analysis_figures(analysis),
        analysis_view(analysis, "prescribed motion"),
        record,
    )


def write_simulation_outputs(
    simulation: Simulation, directory: str | Path | OutputFolder, command: str | None = None
) -> list[Path]:
    """Write a mechanism's forward run (``feeder simulate``): ``states.csv``
    (:meth:`~feeder.study.simulate.Simulation.columns`), ``summary.txt`` (the mobility report,
    the assembled pose, the run's statistics, drift and energy balance, the peaks),
    ``assembled_pose.csv``, its figures (:func:`~feeder.viz.analysis.simulation_figures`) and
    the manifest; returns the paths, the table first."""
    from .viz.analysis import simulation_figures

    record = {
        "force_elements": [element.name for element in simulation.elements],
        "integrator": {
            "method": simulation.method,
            "rtol": simulation.rtol,
            "atol": simulation.atol,
        },
        "samples": int(simulation.run.t.size),
        "gravity": {
            "value": simulation.chain.model.gravity.linear.tolist(),
            "assumed": simulation.spec.gravity is None,
        },
    }
    duration = simulation.run.t[-1] - simulation.run.t[0]
    return _write_mechanism(
        directory,
        command,
        simulation,
        "states.csv",
        simulation_figures(simulation),
        simulation_view(simulation, f"forward run over {duration:g} s"),
        record,
    )


def _write_mechanism(
    directory: str | Path | OutputFolder,
    command: str | None,
    result: Analysis | Simulation,
    table: str,
    figures: Mapping[str, Figure],
    view: MechanismView,
    record: dict,
) -> list[Path]:
    """The outputs of a user mechanism's study: its table (``result.columns()``), summary,
    assembled pose, figures and report page (``report.html``: the summary, the 3-D view of
    ``view`` and the figures), with the manifest's model and closures before ``record``."""
    from .viz.report_page import report_page
    from .viz.viewer import mechanism_html

    command = command or "Python API (feeder.outputs)"
    summary = result.summary()
    pngs = {name: png_bytes(fig) for name, fig in figures.items()}
    title = f"{Path(result.spec.model).name}: {view.source}"
    outputs: dict[str, Writer] = {
        table: lambda path: write_csv(path, result.columns()),
        "summary.txt": lambda path: write_text(path, summary + "\n"),
        "assembled_pose.csv": lambda path: write_text(
            path, _pose_csv(result.chain, result.assembled)
        ),
        "report.html": lambda path: write_text(
            path, report_page(title, command, summary, mechanism_html(view), pngs)
        ),
    }
    outputs |= {name: partial(write_png, png=png) for name, png in pngs.items()}
    record = {
        "command": command,
        "model": str(result.spec.model),
        "closures": [closure.label for closure in result.chain.closures],
        **record,
    }
    return _write(directory, outputs, record)


def _pose_csv(chain: ClosedChain, assembled: np.ndarray) -> str:
    """The assembled pose as CSV: joint, coordinate, value (SI units; the coordinates of
    :func:`~feeder.study.analyze.joint_columns`)."""
    from .study.analyze import pose_rows

    rows = pose_rows(chain.model, assembled)
    return "joint,coordinate,value\n" + "".join(f"{j},{c},{x:.17g}\n" for j, c, x in rows)


def _figure_writers(figures: Mapping[str, Figure]) -> dict[str, Writer]:
    return {name: partial(_write_figure, fig) for name, fig in figures.items()}


def _write_figure(fig: Figure, path: Path) -> Path:
    return write_png(path, png_bytes(fig))


def _write(
    directory: str | Path | OutputFolder, outputs: Mapping[str, Writer], record: dict
) -> list[Path]:
    if isinstance(directory, OutputFolder):
        return directory.write(outputs, record)
    with OutputFolder(directory) as folder:
        return folder.write(outputs, record)


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with path.open("rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _now() -> str:
    return datetime.now(UTC).isoformat(timespec="seconds")
