"""Figures of a user mechanism's analysis (``feeder analyze``) and forward run (``feeder
simulate``), drawn from the panels :mod:`feeder.viz.panels` gives them (the drive loads, every
joint's reaction, the cut forces, the distance to a singular pose, the motion, the force
elements, and the run's energy balance and drift). Each figure is a stack of panels against time
that follows :mod:`feeder.viz.axes` (a panel at round-off level is a note), drawn by
:func:`stacked_figure` into a :class:`matplotlib.figure.Figure`; the figures of a run are drawn
into PNG bytes by :func:`~feeder.viz.mechanism_figures.stack_pngs`."""

from __future__ import annotations

import dataclasses
import math
import textwrap
from collections.abc import Sequence

import numpy as np
from matplotlib.figure import Figure

from .axes import (
    Curve,
    distinct_curves,
    draw_curves,
    label_ticks,
    leave_out,
    log_curves,
    panel_title,
    zero_note,
)
from .panels import Panel

PANEL_HEIGHT = 2.6
"""Height of a drawn panel [in]."""

NOTE_HEIGHT = 0.6
"""Height of a panel left out for its note [in]."""

FIGURE_WIDTH = 8.0
"""Width of a figure with one legend column [in]."""

LEGEND_ROWS = 16
"""Most legend entries in one column beside a panel (a mechanism with many joints has dozens of
curves in a panel); more take further columns, each widening the figure by
:data:`LEGEND_COLUMN`."""

LEGEND_COLUMN = 2.4
"""Width added to the figure per legend column beyond the first [in]."""

LEGEND_LINE = 0.19
"""Height of one line of a legend at font size 8, spacing included [in]; a panel is made tall
enough for its legend's tallest column."""

LEGEND_WRAP = 40
"""Longest line of a legend entry [characters]: longer labels (curves named together,
``a = b = … = 0``) are wrapped onto more lines."""


def stacked_figure(t: np.ndarray, panels: Sequence[Panel]) -> Figure:
    """``panels`` one above the other against the times ``t`` [s], sharing the time axis: its
    label and tick labels under the lowest drawn panel; a panel whose curves are all zero is a
    note (:func:`~feeder.viz.axes.leave_out`). Each drawn panel's legend stands beside it, in
    columns of at most :data:`LEGEND_ROWS` entries, the panel as tall as the legend; the margins
    are measured once (:func:`_lay_out`) to make room for the legends and labels."""
    curves = [[_wrapped(curve) for curve in _curves(panel)] for panel in panels]
    drawn = [not all(curve.zero for curve in panel) for panel in curves]
    columns = [math.ceil(len(panel) / LEGEND_ROWS) for panel in curves]
    heights = [
        max(PANEL_HEIGHT, _legend_height(panel, n)) if shown else NOTE_HEIGHT
        for panel, n, shown in zip(curves, columns, drawn, strict=True)
    ]
    width = FIGURE_WIDTH + LEGEND_COLUMN * (max(columns, default=1) - 1)
    fig = Figure(figsize=(width, sum(heights) + 0.5))
    grid = {"height_ratios": heights}
    axes = fig.subplots(len(panels), 1, sharex=True, squeeze=False, gridspec_kw=grid)[:, 0]
    for ax, panel, panel_curves, n, shown in zip(
        axes, panels, curves, columns, drawn, strict=True
    ):
        if not shown:
            leave_out(ax, zero_note(panel.title, panel_curves, panel.unit))
            continue
        draw_curves(ax, t, panel_curves)
        if panel.log:
            ax.set_yscale("log")
        if panel.reference is not None:
            ax.axhline(panel.reference, color="0.5", linestyle="--", linewidth=0.8)
        ax.set_ylabel(panel.ylabel)
        panel_title(ax, panel.title, fontsize=10)
        ax.grid(True, linewidth=0.4, alpha=0.6)
        ax.legend(
            loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, fontsize=8, ncols=n
        )
    lowest = [ax for ax, shown in zip(axes, drawn, strict=True) if shown]
    if lowest:
        lowest[-1].xaxis.set_tick_params(labelbottom=True)
        lowest[-1].set_xlabel("time t [s]")
    label_ticks(fig)
    _lay_out(fig, [ax is lowest[-1] for ax in axes] if lowest else [False] * len(axes))
    return fig


TOP = 0.45
"""Height above the highest panel [in]: its title (10 pt) and its pad."""

GAP = 0.45
"""Height between two panels [in]: the lower one's title and pad."""

TIME_AXIS = 0.5
"""Height of the time axis's tick labels and label under the lowest drawn panel [in]."""

EDGE = 0.12
"""Clearance [in] between the outermost text (a tick label, an axis label, a legend) and the
figure's edge."""


def _lay_out(fig: Figure, timed: Sequence[bool]) -> None:
    """The panels (``fig.axes``, top to bottom; ``timed``: the one that shows the time axis)
    placed once, in inches, measured at the PNG's resolution
    (:data:`~feeder.viz.png.FIGURE_DPI`, as ``savefig`` draws it): fixed heights above and
    between the panels (:data:`TOP`, :data:`GAP`: a title takes one line) and under the one with
    the time axis (:data:`TIME_AXIS`), the panels' heights in the ratio the figure was made
    with, the right margin as wide as the widest legend beside its panel, and the left margin
    as wide as the widest tick labels and axis label of a panel. Matplotlib's constrained layout
    found the room by measuring every text of the figure twice before ``savefig`` drew it (the
    squeezer's five figures: 0.56 s of CPU to make, 0.32 s laid out here)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from .png import FIGURE_DPI

    width, height = fig.get_size_inches()
    axes = fig.axes
    ratios = np.array(axes[0].get_subplotspec().get_gridspec().get_height_ratios(), dtype=float)
    below = [TIME_AXIS if shows else 0.0 for shows in timed]
    free = height - TOP - EDGE - GAP * (len(axes) - 1) - sum(below)
    heights = free * ratios / ratios.sum()
    tops = height - TOP - np.concatenate([[0.0], np.cumsum(heights + below + GAP)[:-1]])

    def place(left: float, right: float) -> None:
        for ax, top, tall in zip(axes, tops, heights, strict=True):
            box = [left / width, (top - tall) / height, 1.0 - (left + right) / width]
            ax.set_position([*box, tall / height])

    shown, fig.dpi = fig.dpi, FIGURE_DPI
    try:
        # the canvas savefig draws on: the texts measured here are not measured again
        renderer = FigureCanvasAgg(fig).get_renderer()
        drawn = [ax for ax in axes if ax.axison]
        legends = [ax.get_legend() for ax in drawn if ax.get_legend() is not None]
        legend = max((box.get_window_extent(renderer).width for box in legends), default=0.0)
        # a legend stands 1 % of its panel's width beyond it (its anchor): 0.1 in at most
        right = legend / FIGURE_DPI + 0.1 + EDGE if legends else EDGE
        place(1.0, right)  # the panels' heights, which set their y ticks
        left = max(
            (
                (ax.get_window_extent(renderer).x0 - ax.yaxis.get_tightbbox(renderer).x0)
                / FIGURE_DPI
                for ax in drawn
            ),
            default=0.0,
        )
        place(left + EDGE, right)
    finally:
        fig.dpi = shown


def _wrapped(curve: Curve) -> Curve:
    """``curve`` with its label wrapped to lines of at most :data:`LEGEND_WRAP` characters."""
    label = textwrap.fill(curve.label, LEGEND_WRAP, break_on_hyphens=False)
    return dataclasses.replace(curve, label=label)


def _legend_height(curves: Sequence[Curve], columns: int) -> float:
    """Height [in] of a legend of ``curves`` in ``columns`` columns (split as matplotlib splits
    them): its tallest column's lines times :data:`LEGEND_LINE`, and a margin."""
    lines = np.array([curve.label.count("\n") + 1 for curve in curves], dtype=int)
    tallest = max((int(part.sum()) for part in np.array_split(lines, max(columns, 1))), default=0)
    return tallest * LEGEND_LINE + 0.4


def _curves(panel: Panel) -> list[Curve]:
    """The curves that show a panel's series (:mod:`feeder.viz.axes`)."""
    shown = log_curves if panel.log else distinct_curves
    return shown(panel.series, panel.unit, panel.scale)
