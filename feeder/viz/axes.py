"""The rules every figure's axes follow, for every figure module:

* a curve at round-off level is drawn as zero and its legend says so; curves equal to
  round-off are drawn once, their legend naming them all (``a = b``), and the others differ in
  line style as well as colour (:func:`distinct_curves`); on a log axis, values below round-off
  are drawn at it and the legend says so (:func:`log_curves`);
* a panel whose every curve is round-off shows a note instead of its axes (:func:`leave_out`);
* tick labels carry their whole value: no offset or ×10ⁿ text beside an axis; a log axis
  spans whole decades, at least two, labelled 10ⁿ (:func:`label_ticks`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from matplotlib import ticker
from matplotlib.axes import Axes
from matplotlib.figure import Figure

ROUND_OFF = 1e3 * np.finfo(float).eps
"""Relative round-off level (2.2e-13): a value at most this times the size of the terms it is
computed from is round-off. Measured: the reaction moments that are zero in exact arithmetic
(the four-bar's and slider-crank's passive joints, a trammel's, the released four-bar's) come
out at most 3 ε times the largest force times the mechanism's size, and the device's Lagrange
equations differ from Pinocchio by at most 8 ε of the peak load. A thousand ε leaves a margin
of a hundred over those, and stays more than three decades below the 1e-9 to which the loads'
own consistency checks hold (:data:`feeder.chain.dynamics.loads_solve.CONSISTENCY`): nothing the
computation resolves is drawn as zero."""

STYLES = ("-", "--", "-.", ":")
"""Line styles of the curves of a panel, in turn with the colours: curves that meet stay apart."""

SUPERSCRIPTS = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")

TITLE_Y = 1.0
"""Height of a panel's title, in its axes' fraction (over the top edge, raised by the title's
pad), given by :func:`panel_title` to every title: given, matplotlib does not measure the axes'
tick labels to place the title clear of any at the top (none has them here), 12 % of drawing a
time history."""

PLAIN_RANGE = (1e-3, 1e5)
"""Largest |tick| for which tick labels are plain decimals; outside, a × 10ⁿ."""

MIN_DECADES = 2
"""A log axis spans at least this many whole decades: its labelled ticks are then powers of ten,
at least three, and no minor tick needs a label (one decade gives "10⁰, 2×10⁰")."""


@dataclass(frozen=True)
class Curve:
    """One drawn curve standing for one or more series of a panel.

    Attributes:
        label: Legend text: the series' names joined by " = ", "= 0" and the largest size of
            the series when they are round-off.
        values: What is drawn, (N,): the first series' values, or zeros.
        members: Indices of the series it stands for, in the order given.
        zero: The series are zero to round-off.
        peak: Largest |value| of the series it stands for, before any is drawn as zero.
    """

    label: str
    values: np.ndarray
    members: tuple[int, ...]
    zero: bool
    peak: float


def round_off(series: Sequence[np.ndarray], scale: float = 0.0) -> float:
    """The round-off level of a quantity [its unit]: :data:`ROUND_OFF` times the largest of the
    ``series``' sizes and ``scale`` (the size of the terms they are computed from, when the
    series themselves may all be round-off)."""
    largest = max((float(np.abs(v).max(initial=0.0)) for v in series), default=0.0)
    return ROUND_OFF * max(largest, scale)


def distinct_curves(
    series: Sequence[tuple[str, np.ndarray]], unit: str, scale: float = 0.0
) -> list[Curve]:
    """The curves that show ``series`` (name, values (N,) in ``unit``) of one quantity: each
    series at round-off level (:func:`round_off` with ``scale``) becomes zero, and series equal
    to round-off share one curve."""
    floor = round_off([np.asarray(values) for _, values in series], scale)
    groups: list[tuple[list[int], np.ndarray]] = []
    for k, (_, values) in enumerate(series):
        values = np.asarray(values, dtype=float)
        drawn = np.zeros_like(values) if np.abs(values).max(initial=0.0) <= floor else values
        for members, first in groups:
            if np.abs(drawn - first).max(initial=0.0) <= floor:
                members.append(k)
                break
        else:
            groups.append(([k], drawn))
    curves = []
    for members, drawn in groups:
        names = " = ".join(series[k][0] for k in members)
        peak = max(float(np.abs(series[k][1]).max(initial=0.0)) for k in members)
        zero = not drawn.any()
        if zero:
            names += " = 0" + (f" (round-off, ≤ {peak:.1e} {unit})" if peak > 0.0 else "")
        curves.append(Curve(names, drawn, tuple(members), zero, peak))
    return curves


def log_curves(
    series: Sequence[tuple[str, np.ndarray]], unit: str, scale: float = 0.0
) -> list[Curve]:
    """The curves that show positive ``series`` (name, values (N,) in ``unit``) on a log axis:
    each raised to the round-off level (:func:`round_off` with ``scale``), its legend saying so
    where it was below; zero if it never exceeds it."""
    floor = round_off([np.asarray(values) for _, values in series], scale)
    curves = []
    for k, (label, values) in enumerate(series):
        below = np.asarray(values) <= floor
        note = f" (round-off below {floor:.1e} {unit}: drawn there)" if below.any() else ""
        peak = float(np.abs(values).max(initial=0.0))
        curves.append(
            Curve(label + note, np.maximum(values, floor), (k,), bool(below.all()), peak)
        )
    return curves


def draw_curves(
    ax: Axes, x: np.ndarray, curves: Sequence[Curve], linewidth: float = 1.2, first: int = 0
) -> None:
    """Each curve against ``x``, a colour and a line style (:data:`STYLES`) apiece, counted
    from the ``first``-th (for curves of another time grid on the same axes)."""
    for k, curve in enumerate(curves, start=first):
        ax.plot(
            x,
            curve.values,
            label=curve.label,
            color=f"C{k}",
            linestyle=STYLES[k % len(STYLES)],
            linewidth=linewidth,
        )


def zero_note(what: str, curves: Sequence[Curve], unit: str) -> str:
    """The note that replaces a panel whose curves are all zero: ``what`` and how small."""
    peak = max((curve.peak for curve in curves), default=0.0)
    size = f"round-off, ≤ {peak:.1e} {unit}" if peak > 0.0 else "exactly"
    return f"{what}:\nzero at every sample ({size}); not drawn"


def panel_title(ax: Axes, title: str, **style: object) -> None:
    """Set the title of the panel ``ax`` at :data:`TITLE_Y` (``style``: matplotlib's keywords of
    a title, such as ``fontsize`` and ``pad``). Every figure's panels are titled by it."""
    ax.set_title(title, y=TITLE_Y, **style)


def leave_out(ax: Axes, note: str) -> None:
    """Show ``note`` in place of the panel ``ax``: no frame, ticks or labels."""
    ax.set_axis_off()
    ax.text(0.5, 0.5, note, transform=ax.transAxes, ha="center", va="center", fontsize=9)


class FullTicks(ticker.Formatter):
    """Tick labels that each carry the whole value: plain decimals, as few as the ticks need,
    while the largest |tick| is within :data:`PLAIN_RANGE`; otherwise a mantissa × 10ⁿ on every
    label. Never an offset or a scale beside the axis."""

    def __call__(self, x: float, pos: int | None = None) -> str:
        return self.format_ticks([x])[0]

    def format_ticks(self, values: Sequence[float]) -> list[str]:
        values = np.asarray(values, dtype=float)
        largest = float(np.abs(values).max(initial=0.0))
        if largest == 0.0 or PLAIN_RANGE[0] <= largest < PLAIN_RANGE[1]:
            exponent, mantissas = 0, values
        else:
            exponent = math.floor(math.log10(largest))
            mantissas = values / 10.0**exponent
        decimals = _decimals(mantissas)
        power = f"×10{str(exponent).translate(SUPERSCRIPTS)}" if exponent else ""
        return [
            "0" if m == 0.0 else f"{m:.{decimals}f}{power}".replace("-", "−") for m in mantissas
        ]


class DecadeTicks(ticker.Formatter):
    """Tick labels of a log axis's decades as :class:`FullTicks` writes a power: ``10⁻¹²``, in
    plain text (matplotlib's own, ``$10^{-12}$``, goes through its math-text parser: a fifth of
    drawing a figure with a log axis). A tick that is not a whole power of ten is written as
    :class:`FullTicks` writes it."""

    def __call__(self, x: float, pos: int | None = None) -> str:
        exponent = round(math.log10(x)) if x > 0.0 else 0
        if x <= 0.0 or abs(x - 10.0**exponent) > 1e-9 * x:
            return FullTicks()(x, pos)
        return "10" + str(exponent).translate(SUPERSCRIPTS)


class InView(ticker.Locator):
    """The locations of ``locator`` within the axis's view: matplotlib makes a tick (five
    artists) for every location its locator gives and draws those within the view only; a log
    axis's minor locator gives the subdivisions of a decade beyond each end too, a third of its
    ticks. Used for those unlabelled minor ticks (a labelled tick's text may depend on the
    others: :class:`FullTicks`)."""

    def __init__(self, locator: ticker.Locator):
        self.locator = locator

    def set_axis(self, axis) -> None:
        super().set_axis(axis)
        self.locator.set_axis(axis)

    def __call__(self) -> list[float]:
        return self.tick_values(*self.axis.get_view_interval())

    def tick_values(self, vmin: float, vmax: float) -> list[float]:
        low, high = min(vmin, vmax), max(vmin, vmax)
        return [x for x in self.locator.tick_values(vmin, vmax) if low <= x <= high]


def _decimals(values: np.ndarray, most: int = 12) -> int:
    """The fewest decimals that write every value to within 1e-9 of the smallest gap between
    them (of 1 for a single value)."""
    gaps = np.diff(np.unique(values))
    gap = float(gaps.min()) if gaps.size else 1.0
    for decimals in range(most):
        if np.all(np.abs(np.round(values, decimals) - values) <= 1e-9 * gap):
            return decimals
    return most


def label_ticks(fig: Figure) -> None:
    """Every drawn axis of ``fig``: :class:`FullTicks` on a linear one; on a log one, whole
    decades around its data, at least :data:`MIN_DECADES`, powers of ten labelled only
    (:class:`DecadeTicks`)."""
    for ax in fig.axes:
        if not ax.axison:
            continue
        for axis, limits, interval in (
            (ax.xaxis, ax.set_xlim, ax.dataLim.intervalx),
            (ax.yaxis, ax.set_ylim, ax.dataLim.intervaly),
        ):
            if axis.get_scale() == "log":
                limits(*_decades(*interval))
                axis.set_major_formatter(DecadeTicks())
                axis.set_minor_formatter(ticker.NullFormatter())
                if not isinstance(axis.get_minor_locator(), InView):
                    axis.set_minor_locator(InView(axis.get_minor_locator()))
            elif isinstance(axis.get_major_formatter(), ticker.FixedFormatter):
                continue  # named categories (a bar chart's): their own labels
            else:
                axis.set_major_formatter(FullTicks())


def _decades(low: float, high: float) -> tuple[float, float]:
    """Whole decades around [low, high] (> 0), at least :data:`MIN_DECADES` of them."""
    bottom, top = math.floor(math.log10(low)), math.ceil(math.log10(high))
    spare = MIN_DECADES - (top - bottom)
    if spare > 0:
        bottom -= spare // 2
        top += spare - spare // 2
    return 10.0**bottom, 10.0**top
