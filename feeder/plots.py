"""Engineering figures of the feeding cycle, after the paper's Figs. 4 and 8–15.

Every time history marks the stage boundaries and names its quantity and unit; figures are
written as PNG with the non-interactive Agg backend.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .cycle import CycleKinematics  # noqa: E402
from .workspace import Workspace  # noqa: E402

_STAGE_NAMES = ("1: swing to conveyor", "2: swing back, loaded", "3: arm to elevation")


def _finish(fig: plt.Figure, path: str | Path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def mark_stages(ax: plt.Axes, boundaries: Sequence[float]) -> None:
    """Dashed lines at the stage boundaries [s] and the stage names along the top."""
    for t in boundaries[1:-1]:
        ax.axvline(t, color="0.4", linestyle="--", linewidth=0.8)
    for k in range(3):
        middle = 0.5 * (boundaries[k] + boundaries[k + 1])
        ax.text(middle, 1.01, _STAGE_NAMES[k], transform=ax.get_xaxis_transform(),
                ha="center", va="bottom", fontsize=7, color="0.3")
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
    fig, ax = plt.subplots(figsize=(8, 4.2))
    for label, values in series:
        ax.plot(t, values, label=label, linewidth=1.3)
    mark_stages(ax, boundaries)
    ax.set_xlabel("time t [s]")
    ax.set_ylabel(ylabel)
    ax.set_title(title, pad=16)
    ax.grid(True, linewidth=0.4, alpha=0.6)
    if len(series) > 1:
        ax.legend(loc="best", fontsize=8)
    return _finish(fig, path)


def plot_workspace(path: str | Path, space: Workspace, device: str) -> Path:
    """Paper Fig. 4: the payload's path in the vertical plane and its ramming poses."""
    fig, ax = plt.subplots(figsize=(6.5, 6.0))
    ax.plot(space.position[:, 0], space.position[:, 1], color="C0", linewidth=1.5,
            label="payload CG path (−4°: largest travel)")
    half = 0.35
    for eps, centre, axis in zip(space.elevations, space.ram_position, space.ram_axis,
                                 strict=True):
        ends = np.array([centre - half * axis, centre + half * axis])
        ax.plot(ends[:, 0], ends[:, 1], color="C1", linewidth=1.0)
        ax.annotate(f"{np.degrees(eps):.0f}°", ends[1, :2], fontsize=8, color="C1")
    start = space.position[0]
    ax.plot([start[0], start[0]], [start[1] - half, start[1] + half], color="C2",
            linewidth=1.0, label="payload axis at loading")
    ax.plot([], [], color="C1", label="payload axis at ramming (ε)")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m] (muzzle towards −x)")
    ax.set_ylabel("y [m] (up)")
    ax.set_title(f"Workspace of the {device} feeder (cf. paper Fig. 4)")
    ax.grid(True, linewidth=0.4, alpha=0.6)
    ax.legend(loc="lower left", fontsize=8)
    return _finish(fig, path)


def plot_position(path: str | Path, cycle: CycleKinematics) -> Path:
    """Paper Fig. 10: payload CG coordinates x, y, z against time."""
    series = [(f"{axis}", cycle.projectile_position[:, k]) for k, axis in enumerate("xyz")]
    return time_history(path, cycle.t, cycle.spec.boundaries, series,
                        f"Payload CG position, ε = {np.degrees(cycle.elevation):.1f}° "
                        "(cf. paper Fig. 10)", "position [m]")
