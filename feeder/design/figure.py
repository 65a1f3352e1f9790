"""The figure of a sensitivity study: a heat map of elasticities, peaks × parameters, one panel
per scope (the device's one elevation and envelope; a mechanism's motion tables), after the
house conventions of :mod:`feeder.viz.figures` (fixed margins, units in the labels, words for
the quantities)."""

from __future__ import annotations

import math

import numpy as np
from matplotlib.axis import Axis
from matplotlib.colors import Normalize
from matplotlib.figure import Figure
from matplotlib.ticker import FixedFormatter, FixedLocator

from ..viz.axes import panel_title
from ..viz.catalog import words
from ..viz.figures import finish
from .differentiable import DesignParameter
from .sensitivities import Scope, Sensitivities

COLOUR_LIMIT = 2.0
"""Elasticities beyond ±2 (a peak that grows with the square of a parameter or faster) take the
end colours; every cell prints its value."""

SHOWN = 0.005
"""Elasticities below this magnitude print no number (the colour shows ≈ 0)."""

CELL = (0.46, 0.3)
"""Width and height [in] of a cell: room for ``−1.32*`` at 6.5 pt."""

MARGINS = {"left": 2.4, "right": 1.3, "bottom": 1.2, "top": 0.75, "hspace": 1.7}
"""[in] Around the panels: peak names on the left, the colour bar on the right, the parameter
names under each panel, the figure's and each panel's title above."""


def _cell(scope: Scope, peak: str, parameter: str) -> tuple[float, str]:
    """The elasticity (NaN: none) and the text of one cell."""
    entry = scope.entries[(peak, parameter)]
    if entry.status == "unavailable":
        return math.nan, "n/a"
    value = entry.elasticity
    if not math.isfinite(value):
        return math.nan, "–"
    mark = "*" if entry.status == "kink" else ""
    return value, (f"{value:.2f}".replace("-", "−") if abs(value) >= SHOWN else "") + mark


def sensitivity_figure(result: Sensitivities) -> Figure:
    """The heat map of every scope's elasticities (module docstring): of the device's
    :class:`~feeder.design.sensitivities.Sensitivities` or a mechanism's
    :class:`~feeder.design.mechanism.sensitivities.MechanismSensitivities` (each has a
    ``title``, ``parameters`` and ``scopes`` of peaks and entries)."""
    names = [p.name for p in result.parameters]
    rows = max(len(scope.peaks) for scope in result.scopes)
    panels = len(result.scopes)
    width = MARGINS["left"] + MARGINS["right"] + CELL[0] * len(names)
    height = (
        MARGINS["top"]
        + MARGINS["bottom"]
        + panels * CELL[1] * rows
        + (panels - 1) * MARGINS["hspace"]
    )
    fig = Figure(figsize=(max(width, 7.0), height))
    axes = np.atleast_1d(fig.subplots(panels, 1, squeeze=False).ravel())
    norm = Normalize(-COLOUR_LIMIT, COLOUR_LIMIT)
    image = None
    for ax, scope in zip(axes, result.scopes, strict=True):
        cells = [[_cell(scope, peak.name, n) for n in names] for peak in scope.peaks]
        values = np.array([[value for value, _ in row] for row in cells])
        image = ax.imshow(np.ma.masked_invalid(values), cmap="RdBu_r", norm=norm, aspect="auto")
        ax.set_facecolor("0.85")  # no number: unavailable, or a zero peak
        for i, row in enumerate(cells):
            for j, (value, text) in enumerate(row):
                dark = math.isfinite(value) and abs(value) > 0.6 * COLOUR_LIMIT
                ax.text(j, i, text, ha="center", va="center", fontsize=6.5,
                        color="white" if dark else "black")  # fmt: skip
        _categories(ax.xaxis, [_parameter_label(p) for p in result.parameters])
        _categories(ax.yaxis, [f"{words(p.name)} [{p.unit}]" for p in scope.peaks])
        for label in ax.get_xticklabels():
            label.set(rotation=50, ha="right", rotation_mode="anchor", fontsize=7.5)
        for label in ax.get_yticklabels():
            label.set_fontsize(7.5)
        panel_title(ax, f"{result.title}, {scope.title}", pad=6, fontsize=10)
    fig.suptitle(
        "Elasticity of each peak load: % of the peak per % of the parameter\n"
        "(* not differentiable within the step; grey: unavailable or a zero peak)",
        fontsize=9,
        y=1.0 - 0.1 / height,
        va="top",
    )
    finish(fig, **{k: MARGINS[k] for k in ("left", "right", "bottom", "top", "hspace")})
    bar = fig.add_axes((1.0 - 1.0 / fig.get_figwidth(), 0.15, 0.15 / fig.get_figwidth(), 0.7))
    fig.colorbar(image, cax=bar, extend="both", label="elasticity [% per %]")
    return fig


def _categories(axis: Axis, labels: list[str]) -> None:
    """Named categories at 0, 1, …: a fixed formatter, which the house tick labelling
    (:func:`~feeder.viz.axes.label_ticks`) leaves alone."""
    axis.set_major_locator(FixedLocator(range(len(labels))))
    axis.set_major_formatter(FixedFormatter(labels))


def _parameter_label(parameter: DesignParameter) -> str:
    return f"{parameter.name} [{parameter.unit}]"
