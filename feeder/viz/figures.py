"""Time histories of the feeding cycle, after the paper's Figs. 8 and 10–15, and the conventions
every figure shares.

Every figure shows a quantity in the unit an engineer reads
(:func:`~feeder.viz.catalog.display_unit`: mm, kN, bar, deg; N·m and m/s as they are), one unit
per axis, the elevation in one format (:func:`~feeder.viz.catalog.elevation_text`), follows the
axis rules of :mod:`feeder.viz.axes` (round-off drawn as zero, equal curves drawn once, tick
labels that carry their whole value) and has fixed margins (:func:`finish`: no
``tight_layout``, whose text measuring costs as much as drawing the figure). A time history
marks the stage boundaries; a vector's magnitude is drawn over its components, never under
them. Every function returns a
:class:`matplotlib.figure.Figure` (no pyplot state, so any backend, notebooks included, is left
alone); writing it is :mod:`feeder.viz.report`'s.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from ..motion.cycle import CycleKinematics
from ..study.cycle_study import CycleStudy
from .axes import (
    STYLES,
    distinct_curves,
    label_ticks,
    leave_out,
    panel_title,
    zero_note,
)
from .catalog import CYCLE_FIGURES, CycleFigure, display_unit, elevation_text, file_name

_STAGE_NAMES = ("1: swing to conveyor", "2: swing back, loaded", "3: arm to elevation")


def finish(
    fig: Figure,
    left: float = 0.8,
    right: float = 0.2,
    bottom: float = 0.55,
    top: float = 0.6,
    wspace: float = 0.9,
    hspace: float = 0.9,
) -> None:
    """The last step of every figure: its ticks labelled (:func:`~feeder.viz.axes.label_ticks`)
    and fixed margins and gaps between panels, in inches (the figure's size may vary)."""
    label_ticks(fig)
    width, height = fig.get_size_inches()
    columns, rows = (max(1, n) for n in _grid_shape(fig))
    panel_width = (width - left - right - (columns - 1) * wspace) / columns
    panel_height = (height - top - bottom - (rows - 1) * hspace) / rows
    fig.subplots_adjust(
        left=left / width,
        right=1.0 - right / width,
        bottom=bottom / height,
        top=1.0 - top / height,
        wspace=wspace / panel_width,
        hspace=hspace / panel_height,
    )


def _grid_shape(fig: Figure) -> tuple[int, int]:
    """(columns, rows) of the figure's subplot grid."""
    specs = [ax.get_subplotspec() for ax in fig.axes if ax.get_subplotspec() is not None]
    if not specs:
        return 1, 1
    rows, columns = specs[0].get_gridspec().get_geometry()
    return columns, rows


def mark_stages(ax: Axes, boundaries: Sequence[float]) -> None:
    """Dashed lines at the stage boundaries [s] and the stage names along the top."""
    for t in boundaries[1:-1]:
        ax.axvline(t, color="0.4", linestyle="--", linewidth=0.8)
    for k in range(3):
        middle = 0.5 * (boundaries[k] + boundaries[k + 1])
        ax.text(
            middle,
            1.01,
            _STAGE_NAMES[k],
            transform=ax.get_xaxis_transform(),
            ha="center",
            va="bottom",
            fontsize=7,
            color="0.3",
        )
    ax.set_xlim(boundaries[0], boundaries[-1])


LEGEND_WIDTH = 1.25
"""Right margin [in] of a time history with a legend: the legend sits beside the axes, where it
hides no curve."""


def time_history(
    t: np.ndarray,
    boundaries: Sequence[float],
    series: Sequence[tuple[str, np.ndarray]],
    title: str,
    quantity: str,
    unit: str,
    magnitude: str | None = None,
    reuse: Figure | None = None,
) -> Figure:
    """One figure: ``series`` (label, values (N,) in the SI ``unit``) against time, stages
    marked, in the display unit (:func:`display_unit`).

    Args:
        t: Times [s], (N,).
        boundaries: Stage boundaries [s], (4,).
        series: Curves to draw, all in ``unit``.
        title: Figure title (name the paper's figure it mirrors).
        quantity: What the axis shows, without its unit (e.g. "force").
        unit: The SI unit of every curve.
        magnitude: Label of the curve that is a vector's magnitude: drawn last, black and
            thicker, over its components.
        reuse: A figure this function returned before, whose picture is no longer needed
            (written): drawn again with these curves, the same pixels as a new figure's; its
            axes and their ticks are kept, whose making is a third of drawing a time history.
    """
    factor, shown = display_unit(unit)
    if reuse is None:
        fig = Figure(figsize=(8.0, 4.2))
        ax = fig.subplots()
    else:
        fig, ax = reuse, _emptied(reuse)
    curves = distinct_curves([(label, np.asarray(v) * factor) for label, v in series], shown)
    if all(curve.zero for curve in curves):
        leave_out(ax, zero_note(title, curves, shown))
        finish(fig)
        return fig
    for k, curve in enumerate(curves):
        emphasis = any(series[m][0] == magnitude for m in curve.members)
        ax.plot(
            t,
            curve.values,
            label=curve.label,
            linewidth=2.0 if emphasis else 1.2,
            color="k" if emphasis else f"C{k}",
            linestyle="-" if emphasis else STYLES[k % len(STYLES)],
            zorder=3 if emphasis else 2,
        )
    mark_stages(ax, boundaries)
    ax.set_xlabel("time t [s]")
    ax.set_ylabel(f"{quantity} [{shown}]" if shown else quantity)
    panel_title(ax, title, pad=16)
    ax.grid(True, linewidth=0.4, alpha=0.6)
    legend = len(series) > 1
    if legend:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0.0)
    finish(fig, right=LEGEND_WIDTH if legend else 0.2)
    return fig


def _emptied(fig: Figure) -> Axes:
    """The axes of a time history (:func:`time_history`) with nothing drawn on them: curves,
    stage marks, note, legend, labels and title removed, shown, their data limits cleared (the
    next curves set them), their ticks kept."""
    (ax,) = fig.axes
    for artist in [*ax.lines, *ax.texts]:
        artist.remove()
    if ax.get_legend() is not None:
        ax.get_legend().remove()
    ax.set_title("")
    ax.set_xlabel("")
    ax.set_ylabel("")
    ax.set_axis_on()
    ax.relim()
    return ax


def cycle_figure(
    spec: CycleFigure,
    columns: Mapping[str, np.ndarray],
    boundaries: Sequence[float],
    elevation: float,
    reuse: Figure | None = None,
) -> Figure:
    """One figure of :data:`CYCLE_FIGURES` from a cycle's columns and stage boundaries [s]
    (``reuse``: as :func:`time_history`'s)."""
    return time_history(
        columns["t"],
        boundaries,
        [(label, columns[column]) for label, column in spec.curves],
        f"{spec.title}, {elevation_text(elevation)}",
        spec.quantity,
        spec.unit,
        magnitude=spec.magnitude,
        reuse=reuse,
    )


def cycle_figures(study: CycleStudy) -> dict[str, Figure]:
    """The time histories of :data:`CYCLE_FIGURES` of a study, by file name (named for the
    study's payload: :func:`~feeder.viz.catalog.file_name`)."""
    kinematics = study.dynamics.kinematics
    columns = study.columns()
    payload = study.feeder.params.payload_name
    return {
        file_name(spec.file, payload): cycle_figure(
            spec, columns, kinematics.spec.boundaries, kinematics.elevation
        )
        for spec in CYCLE_FIGURES
    }


def payload_position_figure(
    t: np.ndarray,
    position: np.ndarray,
    boundaries: Sequence[float],
    elevation: float,
    reuse: Figure | None = None,
) -> Figure:
    """Paper Fig. 10: payload CG coordinates x, y, z [m] (N, 3) against time (``reuse``: as
    :func:`time_history`'s)."""
    return time_history(
        t,
        boundaries,
        [(axis, position[:, k]) for k, axis in enumerate("xyz")],
        f"Payload CG position, {elevation_text(elevation)} (cf. paper Fig. 10)",
        "position",
        "m",
        reuse=reuse,
    )


def position_figure(cycle: CycleKinematics) -> Figure:
    """Paper Fig. 10 of a sampled cycle."""
    return payload_position_figure(
        cycle.t, cycle.payload_position, cycle.spec.boundaries, cycle.elevation
    )
