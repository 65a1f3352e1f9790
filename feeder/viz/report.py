"""The figures of a study by file name (what ``feeder cycle``, ``feeder kinematics`` and
``feeder sweep`` write) and their drawing, in worker processes while the study computes.

Drawing thirteen figures takes longer than the study, and importing matplotlib about as long as
the study: :class:`FigureWorkers` starts a worker process first (it imports matplotlib while
this process computes), then draws the figures there from :class:`FigureData` (the numbers the
figures need, no Pinocchio objects) into PNG bytes, sharing them with processes forked from that
worker (they have matplotlib loaded already: it is imported once, not once per process), each
time history on the figure of the one before (its axes and ticks kept); a writer per file puts
them in place atomically. A sweep's figures are drawn alike in a process forked before its cases
(:class:`SweepFigures`). This module imports matplotlib only inside the functions that draw, so
``feeder cycle --no-figures`` never loads it.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from concurrent.futures import Future, ProcessPoolExecutor
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..device.feeder import Feeder
from ..device.parameters import FeederParameters
from ..exceptions import InputError
from ..motion.cycle import CycleKinematics
from ..motion.laws import CycleSpec
from ..motion.workspace import workspace
from ..study.columns import kinematic_columns
from ..study.cycle_study import CycleStudy
from ..study.elevation_sweeps import sweeps_of
from ..study.sweep import cached_feeder
from ..study.sweep_table import read_sweep_table
from ..workers import check_workers, fork_safe, local_workers, process_pool
from .catalog import CYCLE_FIGURES, file_name
from .forked import FigureProcess, ForkedDrawing, freeze_imports, import_matplotlib
from .png import png_bytes, write_png

if TYPE_CHECKING:
    from matplotlib.figure import Figure

WORKSPACE_STEP_DEG = 10.0
"""Elevation step [deg] of the ramming poses drawn in the workspace figure (Fig. 4)."""

FIGURE_WORKERS = 2
"""Default processes that draw one study's figures (fewer if there are fewer cores): one worker
that imports matplotlib (about as long as drawing three figures, 0.3 s of CPU), and the others
forked from it once it has (:class:`FigureWorkers`)."""

Writer = Callable[[Path], Path]
"""Writes one file atomically at the path it is given, and returns the path."""


@dataclass(frozen=True)
class FigureData:
    """The numbers the figures of one cycle need (picklable, so workers can be sent them).

    Attributes:
        params: The device's parameters.
        elevation: ε [rad].
        spec: The cycle's timing.
        columns: The cycle's ``cycle.csv`` columns (all, or the kinematic ones), each (N,).
        base: On a moving or tilted base, its description and every peak against the cycle
            standing level: (name, peak here, peak standing, SI unit), magnitudes; else None.
        controlled: The controlled run's errors over the cycle and the hold (the series of
            :func:`~feeder.viz.loading.loading_error_figure`), or None without that run.
    """

    params: FeederParameters
    elevation: float
    spec: CycleSpec
    columns: dict[str, np.ndarray]
    base: tuple[str, tuple[tuple[str, float, float, str], ...]] | None = None
    controlled: dict[str, np.ndarray] | None = None

    @classmethod
    def of_study(cls, study: CycleStudy) -> FigureData:
        """The data of a full study."""
        k = study.dynamics.kinematics
        base, pairs = None, study.against_level()
        if pairs is not None:
            rows = tuple(
                (peak.name, abs(peak.value), abs(level.value), peak.unit) for peak, level in pairs
            )
            base = (study.dynamics.base.describe(), rows)
        run, controlled = study.dynamics.controlled, None
        if run is not None:
            pose = run.loading_pose()
            controlled = {
                "t": run.t,
                "payload_error": run.payload_error,
                "off_line": run.off_line,
                "axis_error": run.axis_error,
                "phi3_error": np.abs(run.q[:, 2] - run.reference[:, 2]),
                "phi4_error": np.abs(run.q[:, 3] - run.reference[:, 3]),
                "position_tolerance": np.array([pose.position_tolerance]),
                "angle_tolerance": np.array([pose.angle_tolerance]),
            }
        return cls(study.feeder.params, k.elevation, k.spec, study.columns(), base, controlled)

    def figure_names(self) -> tuple[str, ...]:
        """The figures of this study (:func:`study_figure_names`, ``base_peaks.png`` on a
        moving or tilted base, ``loading_error.png`` with the controlled run)."""
        names = study_figure_names() + (() if self.base is None else (BASE_FIGURE,))
        return names + (() if self.controlled is None else (LOADING_FIGURE,))

    @classmethod
    def of_cycle(cls, feeder: Feeder, cycle: CycleKinematics) -> FigureData:
        """The data of a cycle's kinematics alone."""
        return cls(feeder.params, cycle.elevation, cycle.spec, kinematic_columns(cycle))

    def file_name(self, figure: str) -> str:
        """The file name of ``figure`` (one of :func:`study_figure_names`) for this payload."""
        return file_name(figure, self.params.payload_name)

    def coordinates(self) -> np.ndarray:
        """q = [φ1, r2, φ3, φ4] at every sample, (N, 4)."""
        return np.column_stack([self.columns[f"q_{c}"] for c in ("phi1", "r2", "phi3", "phi4")])


BASE_FIGURE = "base_peaks.png"
"""The figure of every peak on a moving or tilted base against the cycle standing level."""

LOADING_FIGURE = "loading_error.png"
"""The controlled run's errors over the cycle and the hold
(:func:`~feeder.viz.loading.loading_error_figure`)."""

POSITION_FIGURE = "fig10_{payload}_position.png"
"""The payload's position against time (Fig. 10), a time history."""

KINEMATICS_FIGURES = ("fig04_workspace.png", POSITION_FIGURE)
"""The figures of ``feeder kinematics``: the workspace (Fig. 4) and the payload path (Fig. 10)."""

TIME_HISTORIES = frozenset({POSITION_FIGURE, *(s.file for s in CYCLE_FIGURES)})
"""The figures of a study that are time histories (:func:`~feeder.viz.figures.time_history`):
one is drawn on another's figure once that is written (:func:`draw`)."""

_COST = {"lagrange_cross_check.png": 3.0, "device_side_view.png": 1.5}
"""Drawing time of a figure relative to a time history's (measured): for sharing the work."""


def study_figure_names() -> tuple[str, ...]:
    """The figures of ``feeder cycle``: the side view, Figs. 4, 8, 10–15, the arm-pivot
    reaction, the cylinder pressures, the rack force and the cross-check. Each name is a file
    name in which ``{payload}`` stands for the payload's (:meth:`FigureData.file_name`: the
    charge feeder's speed figure is ``fig08_charge_speed.png``)."""
    return (
        "device_side_view.png",
        *KINEMATICS_FIGURES,
        *(spec.file for spec in CYCLE_FIGURES),
        "lagrange_cross_check.png",
    )


def draw(name: str, data: FigureData, reuse: Figure | None = None) -> Figure:
    """The figure ``name`` (one of :func:`study_figure_names`, or its file name for the data's
    payload) of a cycle; a time history (:data:`TIME_HISTORIES`) is drawn on ``reuse`` if it is
    one written already (:func:`~feeder.viz.figures.time_history`).

    Raises:
        InputError: An unknown name, or a figure that needs columns the data lack (a full
            study's figure from the kinematics alone).
    """
    from .comparisons import base_peaks_figure, cross_check
    from .drawings import device_side_view, workspace_figure
    from .figures import cycle_figure, payload_position_figure

    name = {data.file_name(figure): figure for figure in study_figure_names()}.get(name, name)
    boundaries = data.spec.boundaries
    t = data.columns["t"]
    cycle = {spec.file: spec for spec in CYCLE_FIGURES}
    try:
        if name in cycle:
            return cycle_figure(cycle[name], data.columns, boundaries, data.elevation, reuse)
        if name == POSITION_FIGURE:
            position = np.column_stack([data.columns[f"projectile_{a}"] for a in "xyz"])
            return payload_position_figure(t, position, boundaries, data.elevation, reuse)
        if name == "lagrange_cross_check.png":
            return cross_check(data.params, data.columns, boundaries)
        if name == BASE_FIGURE and data.base is not None:
            return base_peaks_figure(data.base[1], data.base[0], data.elevation)
        if name == LOADING_FIGURE and data.controlled is not None:
            from .loading import loading_error_figure

            base = "standing level" if data.base is None else data.base[0]
            return loading_error_figure(data.controlled, boundaries, data.elevation, base)
    except KeyError as exc:
        raise InputError(
            f"figure {data.file_name(name)} needs the column {exc}: draw it from a full study"
        ) from exc
    feeder = cached_feeder(data.params)
    if name == "fig04_workspace.png":
        low, high = np.degrees(data.params.elevation_limits)
        space = workspace(feeder, np.radians(np.arange(low, high + 1.0, WORKSPACE_STEP_DEG)))
        return workspace_figure(space, data.params.name)
    if name == "device_side_view.png":
        return device_side_view(feeder, t, data.coordinates(), boundaries, data.elevation)
    files = ", ".join(map(data.file_name, study_figure_names()))
    raise InputError(f"no figure named {name!r}; the figures: {files}")


def study_figures(study: CycleStudy) -> dict[str, Figure]:
    """Every figure of the standard study, by file name, drawn here."""
    data = FigureData.of_study(study)
    return {data.file_name(name): draw(name, data) for name in data.figure_names()}


def kinematics_figures(feeder: Feeder, cycle: CycleKinematics) -> dict[str, Figure]:
    """Fig. 4 (the workspace, ramming poses every 10°) and Fig. 10 (payload position)."""
    data = FigureData.of_cycle(feeder, cycle)
    return {data.file_name(name): draw(name, data) for name in KINEMATICS_FIGURES}


def _render(names: Sequence[str], data: FigureData) -> dict[str, bytes]:
    """Draw ``names`` into PNG bytes (in a worker process), each time history on the figure of
    the one before (:func:`draw`)."""
    pngs, history = {}, None
    for name in names:
        fig = draw(name, data, history)
        pngs[name] = png_bytes(fig)
        history = fig if name in TIME_HISTORIES else history
    return pngs


def _render_shared(shares: Sequence[Sequence[str]], data: FigureData) -> dict[str, bytes]:
    """Draw every share of figure names into PNG bytes: the first here (the figure worker), each
    other in a process forked from here (:class:`~feeder.viz.forked.ForkedDrawing`), which has
    matplotlib loaded already, inherits its work and the data (sending them through a pipe,
    3 MB pickled for a cycle of 4001 samples, held this process back 11–39 ms) and sends its
    PNG bytes back (an error it meets is raised here)."""
    if not fork_safe():  # draw here
        return _render([name for share in shares for name in share], data)
    children: list[ForkedDrawing] = []
    try:
        for share in shares[1:]:
            work = partial(_render, share, data)
            children.append(ForkedDrawing(what=f"drawing {share}", work=work))
        pngs = _render(shares[0], data)
    finally:
        answers = [child.answer() for child in children]
    for drawn, result in answers:
        if not drawn:
            raise result
        pngs |= result
    return pngs


def _import_drawing() -> None:
    """Import what drawing needs, in a process of feeder's own (forked: it only draws), before
    there is anything to draw: matplotlib lean (:func:`~feeder.viz.forked.import_matplotlib`)
    and the figure modules (a :class:`~feeder.viz.forked.ForkedDrawing` then leaves their
    objects out of the garbage collector's passes itself)."""
    import_matplotlib()
    from . import comparisons, drawings  # noqa: F401


def _warm_up() -> None:
    """The figure worker's start (:class:`FigureWorkers`): :func:`_import_drawing`, the
    objects imported then left out of the garbage collector's passes
    (:func:`~feeder.viz.forked.freeze_imports`)."""
    _import_drawing()
    freeze_imports()


def _shares(names: Sequence[str], count: int) -> list[list[str]]:
    """``names`` split into ``count`` lists of about equal drawing time (longest first)."""
    shares: list[list[str]] = [[] for _ in range(count)]
    load = [0.0] * count
    for name in sorted(names, key=lambda n: -_COST.get(n, 1.0)):
        k = load.index(min(load))
        shares[k].append(name)
        load[k] += _COST.get(name, 1.0)
    return [share for share in shares if share]


class FigureWorkers:
    """Processes that draw figures (a context manager): enter it before computing, so that the
    figure worker loads matplotlib meanwhile; :meth:`writers` then draws there, in ``workers``
    processes: the worker and processes forked from it for the drawing (matplotlib loaded once).

    The worker is forked (:func:`feeder.workers.process_pool` with ``fork_only``: the sweep's
    start and signal policy) and single-threaded, so forking it is safe; where forking this
    process is not, or with ``workers=1``, figures are drawn in this process when their writer
    runs.

    Args:
        workers: Processes (default :data:`FIGURE_WORKERS`, at most one per core).

    Raises:
        InputError: ``workers`` not a whole number ≥ 1.
    """

    def __init__(self, workers: int | None = None):
        self.workers = (
            min(FIGURE_WORKERS, local_workers())
            if workers is None
            else check_workers("figure workers", workers)
        )
        self._pool: ProcessPoolExecutor | None = None

    def __enter__(self) -> FigureWorkers:
        if self.workers > 1:
            self._pool = process_pool(1, fork_only=True, warm_up=_warm_up)
        return self

    def __exit__(self, kind, error, traceback) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=kind is not None)
            self._pool = None

    def writers(self, data: FigureData, names: Sequence[str]) -> dict[str, Writer]:
        """Start drawing ``names`` (of :func:`study_figure_names`) and return a writer per file
        name (:meth:`FigureData.file_name`), in the order of ``names``: each waits for its
        figure and writes it atomically."""
        if self._pool is None:
            return {data.file_name(name): partial(_draw_and_write, name, data) for name in names}
        future = self._pool.submit(_render_shared, _shares(names, self.workers), data)
        return {data.file_name(name): partial(_write_drawn, name, future) for name in names}


def _draw_and_write(name: str, data: FigureData, path: Path) -> Path:
    return write_png(path, png_bytes(draw(name, data)))


def _write_drawn(name: str, future: Future, path: Path) -> Path:
    return write_png(path, future.result()[name])


def sweep_pngs(table: str | Path) -> dict[str, bytes]:
    """The PNG bytes of :func:`sweep_figures`, by file name."""
    return {name: png_bytes(fig) for name, fig in sweep_figures(table).items()}


class SweepFigures(FigureProcess):
    """The figures of a sweep (:func:`sweep_pngs`) drawn in a process forked when this context
    is entered (:class:`~feeder.viz.forked.FigureProcess`), which imports matplotlib while the
    sweep computes its cases, then waits for the finished table: what is left after the last
    case is the drawing alone (importing matplotlib was half of that serial tail, issue 29).
    Where forking is not safe (a threaded process: the sweep's own pool is made after this one
    is entered) or not possible, :meth:`pngs` draws in this process.
    """

    def __init__(self) -> None:
        super().__init__(_import_drawing, "drawing the sweep")

    def pngs(self, table: str | Path) -> dict[str, bytes]:
        """:func:`sweep_pngs` of ``table``, drawn by the forked process (once) or here.

        Raises:
            InputError: As :func:`sweep_figures`.
        """
        return self.submit(partial(sweep_pngs, str(table)))()


def sweep_figures(table: str | Path) -> dict[str, Figure]:
    """Peaks against elevation from a sweep table (``sweep_peaks.csv``): one figure per device,
    a curve style per variant (:func:`~feeder.viz.comparisons.sweep_figure`), by file name
    ``sweep_<device>.png``.

    Raises:
        InputError: The table is not a sweep table, or has a row that fails its checks
            (:func:`~feeder.study.sweep_table.read_sweep_table`).
    """
    from .comparisons import sweep_figure

    rows, rejected = read_sweep_table(table)
    if rejected:
        number, reason = rejected[0]
        raise InputError(f"{table}, line {number}: {reason}: run the sweep again to recompute it")
    groups: dict[str, dict[str, object]] = {}
    for (device, variant), sweep in sweeps_of(rows).items():
        groups.setdefault(device, {})[variant] = sweep
    return {
        f"sweep_{re.sub(r'[^A-Za-z0-9_.+-]', '_', device)}.png": sweep_figure(
            sweeps, title=f"Peak loads against elevation: {device}"
        )
        for device, sweeps in groups.items()
    }
