"""The files a study writes into its output folder: ``cycle.csv``, its figures and a manifest.

This is the last step of the data flow (parameters → model → kinematics → dynamics →
cross-check → study → figures → files); the command line calls it. An output folder holds the
outputs of one run, written by one run at a time (:class:`~feeder.files.OutputFolder`: checked
before anything is computed, locked, every file atomic, a manifest :data:`MANIFEST` with the
SHA-256 of each output, the previous run's outputs removed only if they are still the files it
wrote).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from functools import cache, partial
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .files import LOCK as LOCK  # re-exported: the output folder's names, for its users
from .files import MANIFEST as MANIFEST
from .files import OutputFolder, Writer, write_text
from .study.csv import write_csv
from .viz.png import png_bytes, write_png

if TYPE_CHECKING:  # the device's modules load with the device's outputs only (issue 29)
    from matplotlib.figure import Figure

    from .chain.dynamics.inverse import ChainLoads
    from .chain.model.closure import ClosedChain
    from .device.feeder import Feeder
    from .motion.cycle import CycleKinematics
    from .study.analyze import Analysis
    from .study.cycle_study import CycleStudy
    from .study.simulate import Simulation
    from .study.view import MechanismView
    from .viz.forked import FigureProcess
    from .viz.panels import Stack
    from .viz.report import FigureWorkers


INDETERMINATE = "indeterminate.txt"
"""The sidecar of a mechanism's table that lists its statically indeterminate columns
(:func:`~feeder.study.mechanism_table.indeterminate_columns`), one a line after a comment."""


def run_record(feeder: Feeder, cycle: CycleKinematics, command: str | None) -> dict[str, object]:
    """The manifest's description of a run: command, device, parameter hash, cycle inputs."""
    from .device.parameter_file import parameters_sha256

    return {
        "command": command or "Python API (feeder.outputs)",
        "device": feeder.params.name,
        "parameters_sha256": parameters_sha256(feeder.params),
        "elevation_deg": round(math.degrees(cycle.elevation), 12),  # 30, not 29.999999999999996
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
    from .viz.report import FigureData, FigureWorkers

    kinematics = study.dynamics.kinematics
    outputs: dict[str, Writer] = {"cycle.csv": lambda path: write_csv(path, study.columns())}
    if figures:
        drawing = FigureWorkers(1) if workers is None else workers
        data = FigureData.of_study(study)
        outputs |= drawing.writers(data, data.figure_names())
    record = run_record(study.feeder, kinematics, command)
    record["forward_run"] = study.dynamics.forward is not None
    controlled = study.dynamics.controlled
    if controlled is not None:
        record["controlled_run"] = controlled.gains.describe()
    base = study.dynamics.base
    record["base"] = "standing level" if base is None else base.describe()
    return _write(directory, outputs, record)


def write_kinematics_outputs(
    feeder: Feeder,
    cycle: CycleKinematics,
    directory: str | Path | OutputFolder,
    command: str | None = None,
    figures: bool = True,
) -> list[Path]:
    """Write the kinematic columns of ``cycle.csv``, Figs. 4 and 10 (if ``figures``) and the
    manifest into ``directory`` (as :func:`write_cycle_outputs`); returns the paths, the table
    first."""
    from .study.columns import kinematic_columns
    from .viz.report import kinematics_figures

    outputs: dict[str, Writer] = {
        "cycle.csv": lambda path: write_csv(path, kinematic_columns(cycle))
    }
    if figures:
        outputs |= _figure_writers(kinematics_figures(feeder, cycle))
    return _write(directory, outputs, run_record(feeder, cycle, command))


def write_analysis_outputs(
    analysis: Analysis,
    directory: str | Path | OutputFolder,
    command: str | None = None,
    figures: bool = True,
    drawing: FigureProcess | None = None,
) -> list[Path]:
    """Write a mechanism's analysis (``feeder analyze``): ``loads.csv``
    (:meth:`~feeder.study.analyze.Analysis.columns`), ``summary.txt`` (the mobility report, the
    assembled pose and the peaks), ``assembled_pose.csv``, ``indeterminate.txt`` (when some
    columns are statically indeterminate), its figures (the panels of
    :func:`~feeder.viz.panels.analysis_stacks`, drawn by
    :func:`~feeder.viz.mechanism_figures.stack_pngs`) and ``report.html`` if ``figures``, and the
    manifest; returns the paths, the table first. ``drawing``: the process that draws the
    figures (:func:`~feeder.viz.mechanism_figures.figure_process`, entered before the
    analysis); without it they are drawn here."""
    from .study.view import analysis_view

    record = {
        "actuated": list(analysis.spec.actuated),
        "independent": list(analysis.spec.independent),
        "samples": int(analysis.motion.t.size),
        "gravity": {
            "value": analysis.chain.model.gravity.linear.tolist(),
            "assumed": analysis.spec.gravity is None,
        },
    }

    def stacks() -> Mapping[str, Stack]:  # imported here: a run without figures plots nothing
        from .viz.panels import analysis_stacks

        return analysis_stacks(analysis)

    return _write_mechanism(
        directory,
        command,
        analysis,
        ("loads.csv", analysis.loads),
        (stacks, drawing) if figures else None,
        lambda: analysis_view(analysis, "prescribed motion"),
        record,
    )


def write_simulation_outputs(
    simulation: Simulation,
    directory: str | Path | OutputFolder,
    command: str | None = None,
    figures: bool = True,
    drawing: FigureProcess | None = None,
) -> list[Path]:
    """Write a mechanism's forward run (``feeder simulate``): ``states.csv``
    (:meth:`~feeder.study.simulate.Simulation.columns`), ``summary.txt`` (the mobility report,
    the assembled pose, the run's statistics, drift and energy balance, the peaks),
    ``assembled_pose.csv``, ``indeterminate.txt`` (when some columns are statically
    indeterminate), its figures (the panels of :func:`~feeder.viz.panels.simulation_stacks`,
    drawn by :func:`~feeder.viz.mechanism_figures.stack_pngs`) and ``report.html`` if
    ``figures``, and the manifest; returns the paths, the table first.
    ``drawing``: as :func:`write_analysis_outputs`'s."""
    from .study.view import simulation_view

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
        "initial_rates": {"given": simulation.start.given, "used": simulation.start.used},
    }
    duration = simulation.run.t[-1] - simulation.run.t[0]

    def stacks() -> Mapping[str, Stack]:  # imported here: a run without figures plots nothing
        from .viz.panels import simulation_stacks

        return simulation_stacks(simulation)

    return _write_mechanism(
        directory,
        command,
        simulation,
        ("states.csv", simulation.run.loads),
        (stacks, drawing) if figures else None,
        lambda: simulation_view(simulation, f"forward run over {duration:g} s"),
        record,
    )


def _write_mechanism(
    directory: str | Path | OutputFolder,
    command: str | None,
    result: Analysis | Simulation,
    table: tuple[str, ChainLoads],
    figures: tuple[Callable[[], Mapping[str, Stack]], FigureProcess | None] | None,
    view: Callable[[], MechanismView],
    record: dict,
) -> list[Path]:
    """The outputs of a user mechanism's study: its table (``table``: its name and the loads it
    holds; ``result.columns()``), summary, assembled pose, the sidecar list of its statically
    indeterminate columns (:data:`INDETERMINATE`, when there are some), and unless ``figures`` is
    None the figures (``figures``: their panels, and the process that draws them or None to draw
    them here) and the report page (``report.html``: the summary, the 3-D view of ``view`` and
    the figures), with the manifest's model and closures before ``record``. The figures are
    drawn while the table and the page's 3-D view are written."""
    command = command or "Python API (feeder.outputs)"
    summary = result.summary()
    name, loads = table
    outputs: dict[str, Writer] = {
        name: lambda path: write_csv(path, result.columns()),
        "summary.txt": lambda path: write_text(path, summary + "\n"),
        "assembled_pose.csv": lambda path: write_text(
            path, _pose_csv(result.chain, result.assembled)
        ),
    }
    from .study.mechanism_table import indeterminate_columns

    indeterminate = indeterminate_columns(loads.indeterminacy)
    if indeterminate:
        outputs[INDETERMINATE] = lambda path: write_text(
            path, _indeterminate_text(name, loads, indeterminate)
        )
    if figures is not None:
        from .viz.mechanism_figures import stack_pngs
        from .viz.report_page import report_page
        from .viz.viewer import mechanism_html

        stacks, drawing = figures
        panels = stacks()
        work = partial(stack_pngs, panels)
        pngs = cache(work if drawing is None else drawing.submit(work))
        shown = view()
        title = f"{Path(result.spec.model).name}: {shown.source}"
        outputs["report.html"] = lambda path: write_text(
            path, report_page(title, command, summary, mechanism_html(shown), pngs())
        )
        outputs |= {png: partial(_write_drawn, png, pngs) for png in panels}
    record = {
        "command": command,
        "model": str(result.spec.model),
        "closures": [closure.label for closure in result.chain.closures],
        **record,
    }
    return _write(directory, outputs, record)


def _indeterminate_text(table: str, loads: ChainLoads, columns: list[str]) -> str:
    """The sidecar :data:`INDETERMINATE`: a comment saying what the columns are, then one
    column name of ``table`` a line."""
    rows = ", ".join(loads.indeterminacy.rows)
    return (
        f"# Columns of {table} that a rigid model does not determine: the self-stresses of the\n"
        f"# closures (rows {rows}) change them without changing any other load.\n"
        f"# Their values: {loads.convention}.\n" + "".join(f"{column}\n" for column in columns)
    )


def _pose_csv(chain: ClosedChain, assembled: np.ndarray) -> str:
    """The assembled pose as CSV: joint, coordinate, value (SI units; the coordinates of
    :func:`~feeder.study.mechanism_table.joint_columns`)."""
    from .study.mechanism_table import pose_rows

    rows = pose_rows(chain.model, assembled)
    return "joint,coordinate,value\n" + "".join(f"{j},{c},{x:.17g}\n" for j, c, x in rows)


def _write_drawn(name: str, pngs: Callable[[], Mapping[str, bytes]], path: Path) -> Path:
    return write_png(path, pngs()[name])


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
