"""Engineering figures of the feeding cycle, after the paper's Figs. 4 and 8–15.

Every time history marks the stage boundaries and names its quantity and unit. Figures are
built as :class:`matplotlib.figure.Figure` objects (no pyplot state, so any backend, notebooks
included, is left alone) and written as PNG.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pinocchio as pin
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from .cycle import CycleKinematics
from .device import Feeder
from .urdf import barrel_length
from .workspace import Workspace

_STAGE_NAMES = ("1: swing to conveyor", "2: swing back, loaded", "3: arm to elevation")


def _finish(fig: Figure, path: str | Path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    return path


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
    path: str | Path,
    t: np.ndarray,
    boundaries: Sequence[float],
    series: Sequence[tuple[str, np.ndarray]],
    title: str,
    ylabel: str,
) -> Path:
    """One figure: ``series`` (label, values (N,)) against time, stages marked.

    Args:
        path: PNG file to write.
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
    return _finish(fig, path)


def plot_workspace(path: str | Path, space: Workspace, device: str) -> Path:
    """Paper Fig. 4: the payload's path in the vertical plane and its ramming poses."""
    fig = Figure(figsize=(6.5, 6.0))
    ax = fig.subplots()
    ax.plot(
        space.position[:, 0],
        space.position[:, 1],
        color="C0",
        linewidth=1.5,
        label="payload CG path (−4°: largest travel)",
    )
    half = 0.35
    for eps, centre, axis in zip(
        space.elevations, space.ram_position, space.ram_axis, strict=True
    ):
        ends = np.array([centre - half * axis, centre + half * axis])
        ax.plot(ends[:, 0], ends[:, 1], color="C1", linewidth=1.0)
        ax.annotate(f"{np.degrees(eps):.0f}°", ends[1, :2], fontsize=8, color="C1")
    start = space.position[0]
    ax.plot(
        [start[0], start[0]],
        [start[1] - half, start[1] + half],
        color="C2",
        linewidth=1.0,
        label="payload axis at loading",
    )
    ax.plot([], [], color="C1", label="payload axis at ramming (ε)")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m] (muzzle towards −x)")
    ax.set_ylabel("y [m] (up)")
    ax.set_title(f"Workspace of the {device} feeder (cf. paper Fig. 4)")
    ax.grid(True, linewidth=0.4, alpha=0.6)
    ax.legend(loc="lower left", fontsize=8)
    return _finish(fig, path)


def plot_mechanism(
    path: str | Path, feeder: Feeder, cycle: CycleKinematics, poses: int = 6
) -> Path:
    """Side view (x-y plane) of the device at ``poses`` instants of stage 3, to scale.

    Drawn from Pinocchio's forward kinematics of the URDF: the frame pivots B and A, the
    cylinder and piston to the rod-eye pin, the arm to the forearm hinge, and the payload as a
    rectangle of its length and calibre along its axis. The loading and ramming poses are
    solid, the poses between them faded.
    """
    p, model, data = feeder.params, feeder.model, feeder.chain.data
    names = ("cylinder", "piston_pin", "arm", "arm_pin", "forearm", "projectile")
    ids = [feeder.frame_id(name) for name in names]
    start = int(np.searchsorted(cycle.t, cycle.spec.boundaries[2]))
    samples = np.linspace(start, len(cycle.t) - 1, poses).round().astype(int)
    fig = Figure(figsize=(7.5, 6.5))
    ax = fig.subplots()
    for n, i in enumerate(samples):
        pin.framesForwardKinematics(model, data, feeder.to_pinocchio(cycle.q[i]))
        at = {name: data.oMf[k] for name, k in zip(names, ids, strict=True)}
        solid = n in (0, len(samples) - 1)
        alpha, width = (1.0, 1.0) if solid else (0.25, 0.7)
        pin_xy = at["piston_pin"].translation[:2]
        cylinder_end = barrel_length(p) * at["cylinder"].rotation[:2, 0]
        ax.plot(
            *np.array([[0.0, 0.0], cylinder_end]).T,
            color="C0",
            lw=7 * width,
            alpha=alpha,
            solid_capstyle="butt",
            label="cylinder" if n == 0 else None,
        )
        ax.plot(
            *np.array([cylinder_end, pin_xy]).T,
            color="0.55",
            lw=3 * width,
            alpha=alpha,
            label="piston rod" if n == 0 else None,
        )
        hinge = at["forearm"].translation[:2]
        ax.plot(
            *np.array([at["arm"].translation[:2], hinge]).T,
            color="C1",
            lw=5 * width,
            alpha=alpha,
            label="arm" if n == 0 else None,
        )
        centre, axis = at["projectile"].translation[:2], at["projectile"].rotation[:2, 1]
        normal = np.array([-axis[1], axis[0]]) * p.payload_diameter / 2.0
        base, tip = centre - 0.4 * p.payload_length * axis, centre + 0.6 * p.payload_length * axis
        outline = np.array(
            [base + normal, tip + normal, tip - normal, base - normal, base + normal]
        )
        ax.plot(
            *outline.T,
            color="C2",
            lw=1.2 * width,
            alpha=alpha,
            label=f"{p.payload_name} (nose →)" if n == 0 else None,
        )
        ax.plot(*np.array([hinge, centre]).T, color="C2", lw=2 * width, alpha=alpha)
        ax.plot(*pin_xy, "o", color="k", ms=4, alpha=alpha)
    for xy, label in (((0.0, 0.0), "B"), ((p.L1, p.L2), "A")):
        ax.plot(*xy, marker="^", color="k", ms=10)
        ax.annotate(label, xy, xytext=(6, -14), textcoords="offset points")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m] (muzzle towards −x)")
    ax.set_ylabel("y [m] (up)")
    ax.set_title(
        f"{p.name.capitalize()} feeder, side view: loading to ramming at "
        f"ε = {np.degrees(cycle.elevation):g}°"
    )
    ax.grid(True, linewidth=0.4, alpha=0.6)
    ax.legend(loc="lower left", fontsize=8)
    return _finish(fig, path)


def plot_position(path: str | Path, cycle: CycleKinematics) -> Path:
    """Paper Fig. 10: payload CG coordinates x, y, z against time."""
    series = [(f"{axis}", cycle.projectile_position[:, k]) for k, axis in enumerate("xyz")]
    return time_history(
        path,
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
    (
        "lagrange_cross_check.png",
        "Actuator loads: Pinocchio − hand-derived Lagrange equations",
        "difference [N] / [N·m]",
        (
            ("piston force", "piston_force_difference"),
            ("forearm moment", "forearm_torque_difference"),
        ),
    ),
)
"""Figures of a full cycle: file name, title, y label and (legend, column) curves."""


def plot_cycle_figures(
    directory: str | Path,
    columns: dict[str, np.ndarray],
    boundaries: Sequence[float],
    elevation_deg: float,
) -> list[Path]:
    """Draw :data:`CYCLE_FIGURES` from a full cycle table's columns into ``directory``."""
    columns = columns | {
        "piston_force_difference": columns["piston_force"] - columns["lagrange_piston_force"],
        "forearm_torque_difference": columns["forearm_torque"]
        - columns["lagrange_forearm_torque"],
    }
    return [
        time_history(
            Path(directory) / name,
            columns["t"],
            boundaries,
            [(label, columns[column]) for label, column in curves],
            f"{title}, ε = {elevation_deg:g}°",
            ylabel,
        )
        for name, title, ylabel, curves in CYCLE_FIGURES
    ]
