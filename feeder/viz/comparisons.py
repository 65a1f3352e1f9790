"""Figures that compare: several cycles on shared axes, sweeps of peaks against elevation, and
the hand-derived equations against Pinocchio. Units, margins and the elevation's format follow
:mod:`feeder.viz.figures`; every function returns a :class:`matplotlib.figure.Figure`."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from ..exceptions import InputError
from ..paper.printed import printed_equations
from ..study.cycle_study import CycleStudy
from ..study.sweep import ElevationSweep
from .catalog import UNITS, display_unit
from .figures import mark_stages, set_margins

_EQUAL = 1e-18  # where a log-scale difference plot draws samples that are exactly equal


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
    for ax, (name, title) in zip(axes, panels, strict=True):
        factor, unit = _one_unit(title, [name])
        for label, table in tables.items():
            ax.plot(table["t"], table[name] * factor, label=label, linewidth=1.2)
        mark_stages(ax, boundaries)
        ax.set_title(title, pad=14, fontsize=10)
        ax.set_ylabel(f"{name} [{unit}]" if unit else name, fontsize=8)
        ax.set_xlabel("time t [s]")
        ax.grid(True, linewidth=0.4, alpha=0.6)
    axes[0].legend(loc="upper left", fontsize=8)
    set_margins(fig, left=0.75, top=0.55, bottom=0.5, wspace=0.85, hspace=0.95)
    return fig


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
        InputError: A panel whose quantities have different units, or names no column.
    """
    fig, axes = _grid(len(panels), columns, 5.0, 4.0)
    styles = ("-", "--", ":", "-.")
    for ax, (panel, names) in zip(axes, panels, strict=True):
        factor, unit = _one_unit(panel, names)
        for k, sweep in enumerate(sweeps.values()):
            for colour, name in enumerate(names):
                ax.plot(
                    np.degrees(sweep.elevations),
                    np.abs(sweep.peaks[name]) * factor,
                    label=name if k == 0 else None,
                    color=f"C{colour}",
                    linestyle=styles[k % len(styles)],
                )
        ax.set_title(panel, fontsize=10)
        ax.set_xlabel("elevation ε [deg]")
        ax.set_ylabel(f"peak [{unit}]")
        ax.grid(True, linewidth=0.4, alpha=0.6)
        ax.legend(loc="best", fontsize=7)
    top = 0.75 if title else 0.4
    if len(sweeps) > 1:
        handles = [
            Line2D([], [], color="0.2", linestyle=styles[k % len(styles)], label=label)
            for k, label in enumerate(sweeps)
        ]
        fig.legend(handles=handles, loc="upper right", ncols=len(handles), fontsize=8)
        top = 0.75
    if title:
        fig.suptitle(title)
    set_margins(fig, left=0.75, top=top, bottom=0.55, wspace=0.85)
    return fig


def cross_check_figure(study: CycleStudy) -> Figure:
    """The piston force and forearm moment by Pinocchio, by the corrected hand-derived
    equations and by the equations as printed (:func:`cross_check`)."""
    k = study.dynamics.kinematics
    return cross_check(study.feeder.params, study.columns(), k.spec.boundaries)


def cross_check(params, table: Mapping[str, np.ndarray], boundaries: Sequence[float]) -> Figure:
    """The cross-check figure from a cycle's columns: top, each load by the three
    computations; below, the relative difference of Pinocchio and the corrected equations per
    quantity, on a log scale.

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
    fig = Figure(figsize=(12, 7.5))
    axes = fig.subplots(2, 2)
    quantities = (
        ("piston_force", "lagrange_piston_force", printed.piston_force, "piston force"),
        ("forearm_torque", "lagrange_forearm_torque", printed.forearm_torque, "forearm moment"),
    )
    for col, (name, hand, as_printed, label) in enumerate(quantities):
        factor, unit = display_unit(UNITS[name])
        top, bottom = axes[0, col], axes[1, col]
        top.plot(t, table[name] * factor, label="Pinocchio", linewidth=1.6)
        top.plot(t, table[hand] * factor, "--", label="Lagrange, corrected", linewidth=1.2)
        top.plot(t, as_printed * factor, ":", label="Lagrange, as printed", linewidth=1.2)
        top.set_ylabel(f"{label} [{unit}]")
        top.legend(loc="upper left", fontsize=8)
        scale = float(np.abs(table[name]).max())
        relative = np.abs(table[name] - table[hand]) / scale
        bottom.semilogy(t, np.maximum(relative, _EQUAL), linewidth=0.8, label="difference")
        bottom.axhline(np.finfo(float).eps, color="C3", linestyle="--", linewidth=0.8)
        bottom.plot([], [], color="C3", linestyle="--", linewidth=0.8, label="machine ε")
        bottom.set_ylim(_EQUAL / 10.0, 1.0)
        bottom.set_ylabel(f"|Pinocchio − corrected| / max|{name}|", fontsize=8)
        bottom.legend(loc="upper right", fontsize=8, title=f"equal samples at {_EQUAL:g}")
        for ax in (top, bottom):
            mark_stages(ax, boundaries)
            ax.set_xlabel("time t [s]")
            ax.grid(True, linewidth=0.4, alpha=0.6)
    set_margins(fig, left=0.85, top=0.35, bottom=0.55, wspace=0.95, hspace=0.85)
    return fig
