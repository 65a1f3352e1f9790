"""Figures of a user mechanism's analysis (``feeder analyze``): the drive loads, every joint's
reaction, the cut forces and the distance to a singular pose. Each function returns a
:class:`matplotlib.figure.Figure`; saving it is the caller's."""

from __future__ import annotations

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from ..study.analyze import Analysis


def _finish(ax: Axes, ylabel: str, title: str) -> None:
    ax.set_xlabel("time t [s]")
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.grid(True, linewidth=0.4, alpha=0.6)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="best", fontsize=8)


def _unit(analysis: Analysis, joint: str) -> str:
    return "N" if analysis._prismatic(joint) else "N·m"


def loads_figure(analysis: Analysis) -> Figure:
    """The actuated joints' generalized forces and the velocity gain against time."""
    t = analysis.motion.t
    fig = Figure(figsize=(8.0, 6.0))
    top, bottom = fig.subplots(2, 1, sharex=True)
    units = {_unit(analysis, name) for name in analysis.loads.actuators}
    for name, values in analysis.loads.actuators.items():
        top.plot(t, values, label=f"{name} [{_unit(analysis, name)}]", linewidth=1.3)
    _finish(top, f"drive load [{', '.join(sorted(units))}]", "Actuator loads (inverse dynamics)")
    bottom.semilogy(t, analysis.gain, color="C3", linewidth=1.2)
    bottom.axhline(1.0, color="0.5", linestyle="--", linewidth=0.8)
    _finish(bottom, "velocity gain [–]", "Distance to a singular pose (gain → ∞ at a toggle)")
    fig.tight_layout()
    return fig


def reactions_figure(analysis: Analysis) -> Figure:
    """Magnitude of every joint's reaction force and moment against time (two panels)."""
    t = analysis.motion.t
    fig = Figure(figsize=(8.0, 6.0))
    forces, moments = fig.subplots(2, 1, sharex=True)
    for name, wrench in analysis.loads.joints.items():
        forces.plot(t, np.linalg.norm(wrench.force, axis=1), label=name, linewidth=1.2)
        moments.plot(t, np.linalg.norm(wrench.moment, axis=1), label=name, linewidth=1.2)
    _finish(forces, "|force| [N]", "Joint reaction forces (parent on child)")
    _finish(moments, "|moment| [N·m]", "Joint reaction moments about each joint's origin")
    fig.tight_layout()
    return fig


def closures_figure(analysis: Analysis) -> Figure:
    """Magnitude of each cut's force and moment (on the body of its first frame) against time;
    statically indeterminate components are the minimum-norm choice (the summary says which)."""
    t = analysis.motion.t
    fig = Figure(figsize=(8.0, 6.0))
    forces, moments = fig.subplots(2, 1, sharex=True)
    for label, wrench in analysis.loads.closures.items():
        forces.plot(t, np.linalg.norm(wrench.force, axis=1), label=label, linewidth=1.2)
        moments.plot(t, np.linalg.norm(wrench.moment, axis=1), label=label, linewidth=1.2)
    _finish(forces, "|force| [N]", "Closure (cut) forces")
    _finish(moments, "|moment| [N·m]", "Closure (cut) moments")
    fig.tight_layout()
    return fig


def analysis_figures(analysis: Analysis) -> dict[str, Figure]:
    """Every figure of an analysis, by file name."""
    return {
        "actuator_loads.png": loads_figure(analysis),
        "joint_reactions.png": reactions_figure(analysis),
        "closure_forces.png": closures_figure(analysis),
    }
