"""Figures that compare: several cycles on shared axes, sweeps of peaks against elevation, and
the hand-derived equations against Pinocchio. Units, margins and the elevation's format follow
:mod:`feeder.viz.figures`, the axes :mod:`feeder.viz.axes` (round-off drawn as zero, equal
curves drawn once, legends in words); every function returns a
:class:`matplotlib.figure.Figure`."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.ticker import FixedFormatter

from ..exceptions import InputError
from ..paper.printed import printed_equations
from ..study.cycle_study import CycleStudy
from ..study.elevation_sweeps import ElevationSweep
from .axes import (
    STYLES,
    distinct_curves,
    draw_curves,
    leave_out,
    log_curves,
    panel_title,
    zero_note,
)
from .catalog import UNITS, display_unit, words
from .figures import finish, mark_stages


def _grid(panels: int, columns: int, width: float, height: float) -> tuple[Figure, np.ndarray]:
    rows = math.ceil(panels / columns)
    fig = Figure(figsize=(width * columns, height * rows))
    axes = np.atleast_1d(fig.subplots(rows, columns, squeeze=False).ravel())
    for ax in axes[panels:]:
        ax.set_visible(False)
    return fig, axes[:panels]


def _one_unit(title: str, names: Sequence[str]) -> tuple[float, str]:
    """The display factor and unit shared by the columns ``names``, or :class:`InputError`:
    quantities of different units (N and N·m) never share an axis."""
    unknown = [name for name in names if name not in UNITS]
    if unknown:
        raise InputError(f"panel {title!r}: no cycle.csv column {unknown}")
    units = {UNITS[name] for name in names}
    if len(units) != 1:
        raise InputError(
            f"panel {title!r} mixes units {sorted(units)}: put quantities of one unit on an axis"
        )
    return display_unit(units.pop())


def cycles_figure(
    studies: Mapping[str, CycleStudy], panels: Sequence[tuple[str, str]], columns: int = 2
) -> Figure:
    """Several cycles on shared axes: one panel per quantity, one curve per study.

    Args:
        studies: Legend label → study (e.g. "ε = 30°" → its :class:`CycleStudy`).
        panels: (column name of ``cycle.csv``, panel title) pairs.
        columns: Panels per row.

    Raises:
        InputError: A panel names no ``cycle.csv`` column.
    """
    fig, axes = _grid(len(panels), columns, 6.0, 3.0)
    tables = {label: study.columns() for label, study in studies.items()}
    boundaries = next(iter(studies.values())).dynamics.kinematics.spec.boundaries
    grids = _time_grids(tables)
    for ax, (name, title) in zip(axes, panels, strict=True):
        factor, unit = _one_unit(title, [name])
        groups = [
            (t, distinct_curves([(label, tables[label][name] * factor) for label in labels], unit))
            for t, labels in grids
        ]  # studies are compared sample by sample only on the same time grid
        curves = [curve for _, group in groups for curve in group]
        if all(curve.zero for curve in curves):
            leave_out(ax, zero_note(title, curves, unit))
            continue
        drawn = 0
        for t, group in groups:
            draw_curves(ax, t, group, first=drawn)
            drawn += len(group)
        mark_stages(ax, boundaries)
        panel_title(ax, title, pad=14, fontsize=10)
        ax.set_ylabel(f"{words(name)} [{unit}]" if unit else words(name), fontsize=8)
        ax.set_xlabel("time t [s]")
        ax.grid(True, linewidth=0.4, alpha=0.6)
        ax.legend(loc="upper left", fontsize=7)
    finish(fig, left=0.75, top=0.55, bottom=0.5, wspace=0.85, hspace=0.95)
    return fig


def _time_grids(tables: Mapping[str, Mapping[str, np.ndarray]]) -> list[tuple[np.ndarray, list]]:
    """The tables' time grids, each with the labels of the tables sampled on it, in order."""
    grids: list[tuple[np.ndarray, list]] = []
    for label, table in tables.items():
        for t, labels in grids:
            if np.array_equal(t, table["t"]):
                labels.append(label)
                break
        else:
            grids.append((table["t"], [label]))
    return grids


SWEEP_PANELS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("Piston force", ("piston_force",)),
    ("Cylinder pressure", ("cylinder_cap_pressure", "cylinder_rod_pressure")),
    ("Pin and pivot forces", ("piston_arm_force", "cylinder_frame_force", "arm_frame_force")),
    ("Forearm moment", ("forearm_torque",)),
    ("Forearm, grip and rack forces", ("forearm_joint_force", "grip_force", "rack_force")),
    (
        "Bearing and grip moments",
        ("arm_frame_moment", "forearm_joint_moment", "grip_moment", "piston_cylinder_moment"),
    ),
)
"""The panels of a sweep's figure (``feeder sweep``): title, quantities of one unit."""


def sweep_figure(
    sweeps: Mapping[str, ElevationSweep],
    panels: Sequence[tuple[str, Sequence[str]]] = SWEEP_PANELS,
    columns: int = 3,
    title: str | None = None,
) -> Figure:
    """Peaks against elevation: one panel per group of quantities of one unit, |peak| in the
    display unit; a colour per quantity (each panel's legend), a line style per sweep (the
    figure's legend, when there are several).

    Args:
        sweeps: Legend label → sweep.
        panels: (panel title, quantity names) pairs; the quantities of a panel share a unit.
        columns: Panels per row.
        title: Figure title, or None.

    Raises:
        InputError: A panel whose quantities have different units, or names no column, or a
            quantity that a sweep lacks.
    """
    fig, axes = _grid(len(panels), columns, 5.0, 4.0)
    for ax, (panel, names) in zip(axes, panels, strict=True):
        factor, unit = _one_unit(panel, names)
        for label, sweep in sweeps.items():
            missing = [name for name in names if name not in sweep.peaks]
            if missing:
                raise InputError(f"panel {panel!r}: sweep {label!r} has no peaks of {missing}")
        runs = [
            (
                sweep,
                distinct_curves(
                    [(f"{words(n)} [{unit}]", np.abs(sweep.peaks[n]) * factor) for n in names],
                    unit,
                ),
            )
            for sweep in sweeps.values()
        ]
        every = [curve for _, curves in runs for curve in curves]
        if all(curve.zero for curve in every):
            leave_out(ax, zero_note(panel, every, unit))
            continue
        for k, (sweep, curves) in enumerate(runs):
            for curve in curves:
                ax.plot(
                    np.degrees(sweep.elevations),
                    curve.values,
                    label=curve.label if k == 0 else None,
                    color=f"C{curve.members[0]}",
                    linestyle=STYLES[k % len(STYLES)],
                )
        panel_title(ax, panel, fontsize=10)
        ax.set_xlabel("elevation ε [deg]")
        ax.set_ylabel(f"peak [{unit}]")
        ax.grid(True, linewidth=0.4, alpha=0.6)
        ax.legend(loc="best", fontsize=7)
    top = 0.75 if title else 0.4
    if len(sweeps) > 1:
        handles = [
            Line2D([], [], color="0.2", linestyle=STYLES[k % len(STYLES)], label=label)
            for k, label in enumerate(sweeps)
        ]
        fig.legend(handles=handles, loc="upper right", ncols=len(handles), fontsize=8)
        top = 0.75
    if title:
        fig.suptitle(title)
    finish(fig, left=0.75, top=top, bottom=0.55, wspace=0.85)
    return fig


def base_peaks_figure(
    rows: Sequence[tuple[str, float, float, str]], base: str, elevation: float
) -> Figure:
    """Every peak on a moving or tilted base against the same cycle standing level: one bar per
    quantity, the ratio of the two peaks (dimensionless, so loads of any unit share the axis),
    each labelled with both values in their unit; quantities zero in both cycles are left out
    with a note.

    Args:
        rows: (column name, peak on the base, peak standing, SI unit), magnitudes.
        base: The base's description.
        elevation: ε [rad].
    """
    drawn = [row for row in rows if row[1] > 0.0 or row[2] > 0.0]
    drawn.sort(key=lambda row: row[1] / row[2] if row[2] > 0.0 else math.inf)
    fig = Figure(figsize=(10.0, 1.6 + 0.32 * len(drawn)))
    ax = fig.subplots()
    y = np.arange(len(drawn))
    ratios = np.array([moving / still if still > 0.0 else np.nan for _, moving, still, _ in drawn])
    finite = np.nan_to_num(ratios, nan=0.0)
    ax.barh(y, finite, color=["tab:red" if r > 1.0 else "tab:blue" for r in finite], height=0.6)
    ax.axvline(1.0, color="black", linewidth=0.8)
    labels = []
    for (name, moving, still, unit), ratio in zip(drawn, ratios, strict=True):
        factor, shown = display_unit(unit)
        labels.append(words(name))
        text = f"{moving * factor:.3g} / {still * factor:.3g} {shown}"
        if not np.isfinite(ratio):
            text += " (zero standing)"
        ax.annotate(
            text,
            (max(ratio if np.isfinite(ratio) else 0.0, 0.0), y[len(labels) - 1]),
            xytext=(4, 0),
            textcoords="offset points",
            va="center",
            fontsize=8,
        )
    ax.set_yticks(y)
    ax.yaxis.set_major_formatter(FixedFormatter(labels))
    ax.set_xlabel("peak on this base / peak standing level [–]")
    ax.set_xlim(0.0, max(1.2, float(np.nanmax(ratios, initial=1.0)) * 1.35))
    ax.grid(True, axis="x", linewidth=0.4, alpha=0.6)
    left_out = [words(name) for name, moving, still, _ in rows if moving == 0.0 == still]
    title = f"Peak loads on this base against standing level, ε = {math.degrees(elevation):g}°"
    fig.suptitle(title, fontsize=11)
    panel_title(ax, base, fontsize=8)
    if left_out:
        fig.text(0.01, 0.01, "zero in both: " + ", ".join(left_out), fontsize=7)
    finish(fig, left=2.6, right=0.3, top=0.7, bottom=0.65)
    return fig


def cross_check_figure(study: CycleStudy) -> Figure:
    """The piston force and forearm moment by Pinocchio, by the corrected hand-derived
    equations and by the equations as printed (:func:`cross_check`)."""
    k = study.dynamics.kinematics
    return cross_check(study.feeder.params, study.columns(), k.spec.boundaries)


def cross_check(params, table: Mapping[str, np.ndarray], boundaries: Sequence[float]) -> Figure:
    """The cross-check figure from a cycle's columns: top, each load by the three
    computations (curves equal to round-off drawn once, :mod:`feeder.viz.axes`); below, the
    size of the difference between Pinocchio and the corrected equations on a log scale, or a
    note where it is round-off at every sample.

    Args:
        params: The device's parameters (for the equations as printed).
        table: The cycle's columns (``cycle.csv``).
        boundaries: Stage boundaries [s].
    """
    t = table["t"]
    q, v, a = (
        np.column_stack([table[f"{prefix}_{c}"] for c in ("phi1", "r2", "phi3", "phi4")])
        for prefix in "qva"
    )
    printed = printed_equations(params, q, v, a)
    panels = []
    for name, hand, as_printed, label in (
        ("piston_force", "lagrange_piston_force", printed.piston_force, "piston force"),
        ("forearm_torque", "lagrange_forearm_torque", printed.forearm_torque, "forearm moment"),
    ):
        factor, unit = display_unit(UNITS[name])
        loads = distinct_curves(
            [
                ("Pinocchio", table[name] * factor),
                ("Lagrange, corrected", table[hand] * factor),
                ("Lagrange, as printed", as_printed * factor),
            ],
            unit,
        )
        # the difference's terms are the load itself: its round-off scale
        difference = log_curves(
            [("|Pinocchio − Lagrange, corrected|", np.abs(table[name] - table[hand]) * factor)],
            unit,
            scale=float(np.abs(table[name]).max()) * factor,
        )
        panels.append((label, unit, loads, difference))
    drawn = any(not diff[0].zero for *_, diff in panels)
    fig = Figure(figsize=(12, 4.0 + (3.75 if drawn else 1.25)))
    axes = fig.subplots(2, 2, gridspec_kw={"height_ratios": (1.0, 1.0 if drawn else 0.15)})
    for col, (label, unit, loads, difference) in enumerate(panels):
        top, bottom = axes[0, col], axes[1, col]
        draw_curves(top, t, loads)
        top.set_ylabel(f"{label} [{unit}]")
        top.legend(loc="best", fontsize=8)
        shown = [top]
        if difference[0].zero:
            what = f"Pinocchio − Lagrange, corrected ({label})"
            leave_out(bottom, zero_note(what, difference, unit))
        else:
            draw_curves(bottom, t, difference, linewidth=0.8)
            bottom.set_yscale("log")
            bottom.set_ylabel(f"|difference| [{unit}]")
            bottom.legend(loc="upper right", fontsize=8)
            shown.append(bottom)
        for ax in shown:
            mark_stages(ax, boundaries)
            ax.set_xlabel("time t [s]")
            ax.grid(True, linewidth=0.4, alpha=0.6)
    finish(fig, left=0.85, top=0.35, bottom=0.55, wspace=0.95, hspace=0.85)
    return fig
