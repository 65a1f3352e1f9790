"""Figures that compare: several cycles on shared axes, sweeps of peaks against elevation, and
the hand-derived equations against Pinocchio. Every function returns a
:class:`matplotlib.figure.Figure`; saving it is the caller's."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
from matplotlib.figure import Figure

from ..paper.printed import printed_equations
from ..study.columns import COLUMNS
from ..study.cycle_study import CycleStudy
from ..study.sweep import ElevationSweep
from .figures import mark_stages

_UNITS = {column.name: column.unit for column in COLUMNS}
_DISPLAY = {"Pa": (1e-5, "bar")}  # SI unit → (factor, unit an engineer reads)
_EQUAL = 1e-18  # where a log-scale difference plot draws samples that are exactly equal


def _grid(panels: int, columns: int, width: float, height: float) -> tuple[Figure, np.ndarray]:
    rows = math.ceil(panels / columns)
    fig = Figure(figsize=(width * columns, height * rows))
    axes = np.atleast_1d(fig.subplots(rows, columns, squeeze=False).ravel())
    for ax in axes[panels:]:
        ax.set_visible(False)
    return fig, axes[:panels]


def _scaled(name: str) -> tuple[float, str]:
    """Display factor and unit of a column: pressures in bar, everything else in SI."""
    unit = _UNITS[name]
    return _DISPLAY.get(unit, (1.0, unit))


def cycles_figure(
    studies: Mapping[str, CycleStudy], panels: Sequence[tuple[str, str]], columns: int = 2
) -> Figure:
    """Several cycles on shared axes: one panel per quantity, one curve per study.

    Args:
        studies: Legend label → study (e.g. "ε = 30°" → its :class:`CycleStudy`).
        panels: (column name of ``cycle.csv``, panel title) pairs.
        columns: Panels per row.
    """
    fig, axes = _grid(len(panels), columns, 6.0, 3.0)
    tables = {label: study.columns() for label, study in studies.items()}
    boundaries = next(iter(studies.values())).dynamics.kinematics.spec.boundaries
    for ax, (name, title) in zip(axes, panels, strict=True):
        factor, unit = _scaled(name)
        for label, table in tables.items():
            ax.plot(table["t"], table[name] * factor, label=label, linewidth=1.2)
        mark_stages(ax, boundaries)
        ax.set_title(title, pad=14, fontsize=10)
        ax.set_ylabel(f"{name} [{unit}]" if unit else name, fontsize=8)
        ax.set_xlabel("time t [s]")
        ax.grid(True, linewidth=0.4, alpha=0.6)
    axes[0].legend(loc="best", fontsize=8)
    fig.tight_layout()
    return fig


def sweep_figure(
    sweeps: Mapping[str, ElevationSweep],
    panels: Sequence[tuple[str, Sequence[str]]],
    columns: int = 3,
) -> Figure:
    """Peaks against elevation: one panel per group of quantities, one curve per sweep and
    quantity (|peak|, pressures in bar).

    Args:
        sweeps: Legend label → sweep (a single sweep is labelled by quantity only).
        panels: (panel title, quantity names) pairs; the quantities of a panel share a unit.
        columns: Panels per row.
    """
    fig, axes = _grid(len(panels), columns, 5.0, 4.0)
    for ax, (title, names) in zip(axes, panels, strict=True):
        units = {_scaled(name)[1] for name in names}
        for label, sweep in sweeps.items():
            for name in names:
                factor, _ = _scaled(name)
                curve = name if len(sweeps) == 1 else f"{label}: {name}"
                ax.plot(
                    np.degrees(sweep.elevations), np.abs(sweep.peaks[name]) * factor, label=curve
                )
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("elevation ε [deg]")
        ax.set_ylabel(f"peak [{', '.join(sorted(units))}]")
        ax.grid(True, linewidth=0.4, alpha=0.6)
        ax.legend(loc="best", fontsize=7)
    fig.tight_layout()
    return fig


def cross_check_figure(study: CycleStudy) -> Figure:
    """The piston force and forearm moment by Pinocchio, by the corrected hand-derived
    equations and by the equations as printed, and the relative difference of the first two
    per quantity on a log scale."""
    k = study.dynamics.kinematics
    table = study.columns()
    printed = printed_equations(study.feeder.params, k.q, k.v, k.a)
    fig = Figure(figsize=(12, 7.5))
    axes = fig.subplots(2, 2)
    quantities = (
        ("piston_force", "lagrange_piston_force", printed.piston_force, "piston force [N]"),
        ("forearm_torque", "lagrange_forearm_torque", printed.forearm_torque, "moment [N·m]"),
    )
    for col, (name, hand, as_printed, label) in enumerate(quantities):
        top, bottom = axes[0, col], axes[1, col]
        top.plot(k.t, table[name], label="Pinocchio", linewidth=1.6)
        top.plot(k.t, table[hand], "--", label="Lagrange, corrected", linewidth=1.2)
        top.plot(k.t, as_printed, ":", label="Lagrange, as printed", linewidth=1.2)
        top.set_ylabel(label)
        top.legend(loc="best", fontsize=8)
        scale = float(np.abs(table[name]).max())
        relative = np.abs(table[name] - table[hand]) / scale
        bottom.semilogy(k.t, np.maximum(relative, _EQUAL), linewidth=0.8, label="difference")
        bottom.axhline(np.finfo(float).eps, color="C3", linestyle="--", linewidth=0.8)
        bottom.plot([], [], color="C3", linestyle="--", linewidth=0.8, label="machine ε")
        bottom.set_ylim(_EQUAL / 10.0, 1.0)
        bottom.set_ylabel(f"|Pinocchio − corrected| / max|{name}|", fontsize=8)
        bottom.legend(loc="upper right", fontsize=8, title=f"equal samples at {_EQUAL:g}")
        for ax in (top, bottom):
            mark_stages(ax, k.spec.boundaries)
            ax.set_xlabel("time t [s]")
            ax.grid(True, linewidth=0.4, alpha=0.6)
    fig.tight_layout()
    return fig
