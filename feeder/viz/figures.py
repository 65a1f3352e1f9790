"""Time histories of the feeding cycle, after the paper's Figs. 8 and 10–15.

Every time history marks the stage boundaries and names its quantity and unit. Every function
returns a :class:`matplotlib.figure.Figure` (no pyplot state, so any backend, notebooks
included, is left alone); saving it is the caller's (:func:`feeder.outputs.save_figure`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from ..motion.cycle import CycleKinematics
from ..study.cycle_study import CycleStudy

_STAGE_NAMES = ("1: swing to conveyor", "2: swing back, loaded", "3: arm to elevation")


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


def time_history(
    t: np.ndarray,
    boundaries: Sequence[float],
    series: Sequence[tuple[str, np.ndarray]],
    title: str,
    ylabel: str,
) -> Figure:
    """One figure: ``series`` (label, values (N,)) against time, stages marked.

    Args:
        t: Times [s], (N,).
        boundaries: Stage boundaries [s], (4,).
        series: Curves to draw.
        title: Figure title (name the paper's figure it mirrors).
        ylabel: Quantity and unit.
    """
    fig = Figure(figsize=(8, 4.2))
    ax = fig.subplots()
    peak = max(float(np.abs(values).max()) for _, values in series)
    exponent = 3 * math.floor(math.log10(peak) / 3) if peak > 0 else 0
    if -3 < exponent < 6:  # plain numbers read best; otherwise scale in the label, not an offset
        exponent = 0
    for label, values in series:
        ax.plot(t, np.asarray(values) / 10.0**exponent, label=label, linewidth=1.3)
    ax.ticklabel_format(axis="y", useOffset=False, style="plain")
    mark_stages(ax, boundaries)
    ax.set_xlabel("time t [s]")
    ax.set_ylabel(ylabel if exponent == 0 else f"{ylabel} × 1e{exponent}")
    ax.set_title(title, pad=16)
    ax.grid(True, linewidth=0.4, alpha=0.6)
    if len(series) > 1:
        ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    return fig


def position_figure(cycle: CycleKinematics) -> Figure:
    """Paper Fig. 10: payload CG coordinates x, y, z against time."""
    series = [(f"{axis}", cycle.payload_position[:, k]) for k, axis in enumerate("xyz")]
    return time_history(
        cycle.t,
        cycle.spec.boundaries,
        series,
        f"Payload CG position, ε = {np.degrees(cycle.elevation):.1f}° (cf. paper Fig. 10)",
        "position [m]",
    )


CYCLE_FIGURES: tuple[tuple[str, str, str, tuple[tuple[str, str], ...]], ...] = (
    (
        "fig08_projectile_speed.png",
        "Payload CG speed (cf. paper Fig. 8)",
        "speed [m/s]",
        (("|v_G|", "projectile_speed"),),
    ),
    (
        "fig11_forearm_joint_force.png",
        "Reaction force in the forearm–arm joint (cf. Fig. 11)",
        "force [N]",
        (
            ("magnitude", "forearm_joint_force"),
            ("x", "forearm_joint_force_x"),
            ("y", "forearm_joint_force_y"),
            ("z", "forearm_joint_force_z"),
        ),
    ),
    (
        "fig12_cylinder_frame_force.png",
        "Reaction force in the cylinder–frame joint (cf. Fig. 12)",
        "force [N]",
        (
            ("magnitude", "cylinder_frame_force"),
            ("x", "cylinder_frame_force_x"),
            ("y", "cylinder_frame_force_y"),
            ("z", "cylinder_frame_force_z"),
        ),
    ),
    (
        "fig13_piston_arm_force.png",
        "Pin force between piston and arm (cf. Fig. 13)",
        "force [N]",
        (
            ("magnitude", "piston_arm_force"),
            ("x", "piston_arm_force_x"),
            ("y", "piston_arm_force_y"),
            ("z", "piston_arm_force_z"),
        ),
    ),
    (
        "fig14_piston_force.png",
        "Actuator force along the piston axis (cf. Fig. 14)",
        "force [N]",
        (("piston force", "piston_force"),),
    ),
    (
        "fig15_forearm_torque.png",
        "Actuator moment about the forearm axis (cf. Fig. 15)",
        "moment [N·m]",
        (("forearm moment", "forearm_torque"),),
    ),
    (
        "arm_frame_force.png",
        "Reaction force in the arm–frame joint",
        "force [N]",
        (
            ("magnitude", "arm_frame_force"),
            ("x", "arm_frame_force_x"),
            ("y", "arm_frame_force_y"),
            ("z", "arm_frame_force_z"),
        ),
    ),
    (
        "cylinder_pressure.png",
        "Lift-cylinder chamber pressure (ideal, push on the cap side)",
        "pressure [Pa]",
        (("cap side", "cylinder_cap_pressure"), ("rod side", "cylinder_rod_pressure")),
    ),
    ("rack_force.png", "Forearm rack force", "force [N]", (("rack force", "rack_force"),)),
)
"""Figures of a full cycle: file name, title, y label and (legend, column) curves."""


def cycle_figures(study: CycleStudy) -> dict[str, Figure]:
    """The time histories of :data:`CYCLE_FIGURES` of a study, by file name."""
    kinematics = study.dynamics.kinematics
    boundaries = kinematics.spec.boundaries
    elevation_deg = float(np.degrees(kinematics.elevation))
    columns = study.columns()
    figures = {}
    for name, title, ylabel, curves in CYCLE_FIGURES:
        figures[name] = time_history(
            columns["t"],
            boundaries,
            [(label, columns[column]) for label, column in curves],
            f"{title}, ε = {elevation_deg:g}°",
            ylabel,
        )
    return figures
