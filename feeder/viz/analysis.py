"""Figures of a user mechanism's analysis (``feeder analyze``) and forward run (``feeder
simulate``): the drive loads, every joint's reaction, the cut forces, the distance to a singular
pose, the motion, the force elements, and the run's energy balance and drift. Each function
returns a :class:`matplotlib.figure.Figure`; saving it is the caller's."""

from __future__ import annotations

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from ..chain.dynamics.inverse import ChainLoads
from ..study.analyze import Analysis
from ..study.simulate import Simulation


def _finish(ax: Axes, ylabel: str, title: str) -> None:
    ax.set_xlabel("time t [s]")
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.grid(True, linewidth=0.4, alpha=0.6)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="best", fontsize=8)
    ax.label_outer()  # panels sharing the time axis: its label and ticks on the bottom one only


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


def reactions_figure(t: np.ndarray, loads: ChainLoads) -> Figure:
    """Magnitude of every joint's reaction force and moment against time (two panels)."""
    return _wrench_figure(
        t,
        loads.joints,
        "Joint reaction forces (parent on child)",
        "Joint reaction moments about each joint's origin",
    )


def closures_figure(t: np.ndarray, loads: ChainLoads) -> Figure:
    """Magnitude of each cut's force and moment (on the body of its first frame) against time;
    statically indeterminate components are the minimum-norm choice (the summary says which)."""
    return _wrench_figure(t, loads.closures, "Closure (cut) forces", "Closure (cut) moments")


def _wrench_figure(t: np.ndarray, wrenches: dict, force_title: str, moment_title: str) -> Figure:
    """|force| and |moment| of each named wrench against time, two panels."""
    fig = Figure(figsize=(8.0, 6.0))
    forces, moments = fig.subplots(2, 1, sharex=True)
    for name, wrench in wrenches.items():
        forces.plot(t, np.linalg.norm(wrench.force, axis=1), label=name, linewidth=1.2)
        moments.plot(t, np.linalg.norm(wrench.moment, axis=1), label=name, linewidth=1.2)
    _finish(forces, "|force| [N]", force_title)
    _finish(moments, "|moment| [N·m]", moment_title)
    fig.tight_layout()
    return fig


def analysis_figures(analysis: Analysis) -> dict[str, Figure]:
    """Every figure of an analysis, by file name."""
    t = analysis.motion.t
    return {
        "actuator_loads.png": loads_figure(analysis),
        "joint_reactions.png": reactions_figure(t, analysis.loads),
        "closure_forces.png": closures_figure(t, analysis.loads),
    }


def motion_figure(simulation: Simulation) -> Figure:
    """The one-coordinate joints' values and rates against time (two panels)."""
    run, model = simulation.run, simulation.chain.model
    fig = Figure(figsize=(8.0, 6.0))
    values, rates = fig.subplots(2, 1, sharex=True)
    for j in range(1, model.njoints):
        joint = model.joints[j]
        if joint.nv != 1:
            continue
        q = run.q[:, joint.idx_q]
        if joint.nq == 2:
            q = np.unwrap(np.arctan2(run.q[:, joint.idx_q + 1], q))
        values.plot(run.t, q, label=model.names[j], linewidth=1.2)
        rates.plot(run.t, run.v[:, joint.idx_v], label=model.names[j], linewidth=1.2)
    _finish(values, "joint value [rad or m]", "Joint coordinates (forward run from rest)")
    _finish(rates, "joint rate [rad/s or m/s]", "Joint rates")
    fig.tight_layout()
    return fig


def balance_figure(simulation: Simulation) -> Figure:
    """The energy, the work of the non-conservative forces, their balance and the drift."""
    run = simulation.run
    fig = Figure(figsize=(8.0, 7.5))
    energy, balance, drift = fig.subplots(3, 1, sharex=True)
    energy.plot(run.t, run.energy - run.energy[0], label="E − E(0)", linewidth=1.3)
    energy.plot(run.t, run.work, label="W (non-conservative work)", linewidth=1.0, linestyle="--")
    _finish(energy, "energy [J]", "Energy (kinetic, gravitational, elastic) and work")
    balance.plot(run.t, run.energy - run.energy[0] - run.work, color="C3", linewidth=1.0)
    _finish(balance, "E − E(0) − W [J]", "Energy balance (zero for an exact run)")
    drift.semilogy(run.t, np.maximum(run.residual, 1e-18), color="C2", linewidth=1.0)
    _finish(drift, "residual [m, rad]", "Closure drift before projection (floor 1e-18)")
    fig.tight_layout()
    return fig


def elements_figure(simulation: Simulation) -> Figure:
    """Each force element's force against time."""
    run = simulation.run
    fig = Figure(figsize=(8.0, 4.0))
    ax = fig.subplots()
    for name, values in run.loads.elements.items():
        ax.plot(run.t, values, label=name, linewidth=1.2)
    _finish(ax, "force [N] (tension +) or resistance [N·m, N]", "Force elements")
    fig.tight_layout()
    return fig


def simulation_figures(simulation: Simulation) -> dict[str, Figure]:
    """Every figure of a forward run, by file name."""
    run = simulation.run
    figures = {
        "motion.png": motion_figure(simulation),
        "energy_balance.png": balance_figure(simulation),
        "joint_reactions.png": reactions_figure(run.t, run.loads),
    }
    if run.loads.closures:
        figures["closure_forces.png"] = closures_figure(run.t, run.loads)
    if run.loads.elements:
        figures["force_elements.png"] = elements_figure(simulation)
    return figures
