"""Drawings of the device: its side view at several poses, the payload's workspace (paper
Fig. 4) and the loop's stroke and transmission angle over the elevation range, lengths in mm
and angles in degrees. Every function returns a :class:`matplotlib.figure.Figure`; writing it
is :mod:`feeder.viz.report`'s."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.figure import Figure

from ..chain.kinematics.tree import frame_placements, tree_motion
from ..device.feeder import Feeder
from ..device.loop import TRANSMISSION_BAND_DEG, arm_travel, required_stroke, solve_loop
from ..device.urdf_writer import barrel_length
from ..motion.cycle import CycleKinematics
from ..motion.workspace import Workspace
from .axes import panel_title
from .catalog import elevation_text
from .figures import finish

MM = 1e3
"""Metres → millimetres: drawings are dimensioned in mm."""

NOSE_LENGTH = 1.5
"""Length of the payload outline's pointed front, in calibres: it marks the nose (the end the
payload axis points to) in the side view."""


def workspace_figure(space: Workspace, device: str) -> Figure:
    """Paper Fig. 4: the payload's path in the vertical plane and its ramming poses.

    Args:
        space: The workspace (:func:`~feeder.motion.workspace.workspace`).
        device: Device name for the title.
    """
    fig = Figure(figsize=(6.5, 6.0))
    ax = fig.subplots()
    ax.plot(
        space.position[:, 0] * MM,
        space.position[:, 1] * MM,
        color="C0",
        linewidth=1.5,
        label="payload CG path (−4°: largest travel)",
    )
    half = 0.35
    for eps, centre, axis in zip(
        space.elevations, space.ram_position, space.ram_axis, strict=True
    ):
        ends = np.array([centre - half * axis, centre + half * axis]) * MM
        ax.plot(ends[:, 0], ends[:, 1], color="C1", linewidth=1.0)
        ax.annotate(
            f"{np.degrees(eps):.0f}°".replace("-", "−"), ends[1, :2], fontsize=8, color="C1"
        )
    start = space.position[0] * MM
    ax.plot(
        [start[0], start[0]],
        [start[1] - half * MM, start[1] + half * MM],
        color="C2",
        linewidth=1.0,
        label="payload axis at loading",
    )
    ax.plot([], [], color="C1", label="payload axis at ramming (ε)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [mm] (muzzle towards −x)")
    ax.set_ylabel("y [mm] (up)")
    panel_title(ax, f"Workspace of the {device} feeder (cf. paper Fig. 4)")
    ax.grid(True, linewidth=0.4, alpha=0.6)
    ax.legend(loc="lower left", fontsize=8)
    finish(fig, left=0.85, top=0.45)
    return fig


def side_view_figure(feeder: Feeder, cycle: CycleKinematics, poses: int = 6) -> Figure:
    """Side view (x-y plane) of the device at ``poses`` instants of stage 3, to scale
    (:func:`device_side_view` of a sampled cycle)."""
    return device_side_view(
        feeder, cycle.t, cycle.q, cycle.spec.boundaries, cycle.elevation, poses
    )


def device_side_view(
    feeder: Feeder,
    t: np.ndarray,
    q: np.ndarray,
    boundaries: Sequence[float],
    elevation: float,
    poses: int = 6,
) -> Figure:
    """Side view (x-y plane, mm) of the device at ``poses`` instants of stage 3, to scale.

    Drawn from the URDF model's forward kinematics: the frame pivots B and A, the cylinder and
    piston to the rod-eye pin, the arm to the forearm hinge, and the payload as an outline of
    its length and calibre along its axis, pointed at the nose. The loading and ramming poses
    are solid, the poses between them faded.

    Args:
        feeder: The device.
        t: Sample times [s], (N,).
        q: Paper-order coordinates, (N, 4).
        boundaries: Stage boundaries [s], (4,).
        elevation: ε [rad], for the title.
        poses: Poses drawn.
    """
    p = feeder.params
    names = ("cylinder", "piston_pin", "arm", "forearm", "projectile")
    start = int(np.searchsorted(t, boundaries[2]))
    samples = np.linspace(start, len(t) - 1, poses).round().astype(int)
    motion = tree_motion(feeder.model, feeder.to_pinocchio(q[samples]))
    placed = [frame_placements(feeder.model, motion, feeder.frame_id(n)) for n in names]
    position = np.stack([origin[:, :2] for _, origin in placed], axis=1) * MM
    rotation = np.stack([turn[:, :2, :] for turn, _ in placed], axis=1)
    radius = p.payload_diameter / 2.0 * MM
    fig = Figure(figsize=(7.5, 6.5))
    ax = fig.subplots()
    for n in range(len(samples)):
        cylinder, pin_xy, arm, hinge, centre = position[n]
        solid = n in (0, len(samples) - 1)
        alpha, width = (1.0, 1.0) if solid else (0.25, 0.7)
        cylinder_end = cylinder + barrel_length(p) * MM * rotation[n, 0, :, 0]
        ax.plot(
            *np.array([cylinder, cylinder_end]).T,
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
        ax.plot(
            *np.array([arm, hinge]).T,
            color="C1",
            lw=5 * width,
            alpha=alpha,
            label="arm" if n == 0 else None,
        )
        axis = rotation[n, 4, :, 1]
        normal = np.array([-axis[1], axis[0]]) * radius
        base = centre - 0.4 * p.payload_length * MM * axis
        nose = centre + 0.6 * p.payload_length * MM * axis
        shoulder = nose - NOSE_LENGTH * 2.0 * radius * axis
        outline = np.array(
            [
                base + normal,
                shoulder + normal,
                nose,
                shoulder - normal,
                base - normal,
                base + normal,
            ]
        )
        ax.plot(
            *outline.T,
            color="C2",
            lw=1.2 * width,
            alpha=alpha,
            label=f"{p.payload_name}, nose at the pointed end" if n == 0 else None,
        )
        ax.plot(*np.array([hinge, centre]).T, color="C2", lw=2 * width, alpha=alpha)
        ax.plot(*pin_xy, "o", color="k", ms=4, alpha=alpha)
    for xy, label in (((0.0, 0.0), "B"), ((p.L1 * MM, p.L2 * MM), "A")):
        ax.plot(*xy, marker="^", color="k", ms=10)
        ax.annotate(label, xy, xytext=(6, -14), textcoords="offset points")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [mm] (muzzle towards −x)")
    ax.set_ylabel("y [mm] (up)")
    panel_title(
        ax,
        f"{p.name.capitalize()} feeder, side view: loading to ramming at "
        + elevation_text(elevation),
    )
    ax.grid(True, linewidth=0.4, alpha=0.6)
    ax.legend(loc="lower left", fontsize=8)
    finish(fig, left=0.85, top=0.45)
    return fig


def loop_figure(feeder: Feeder, samples: int = 400) -> Figure:
    """The loop over the elevation range: the piston travel from loading to ramming against
    the elevation, and the transmission angle at the pin against the arm's rotation, with the
    documented band (:data:`~feeder.device.loop.TRANSMISSION_BAND_DEG`).

    Args:
        feeder: The device.
        samples: Points along each curve.
    """
    p = feeder.params
    elevations = np.linspace(p.elevation_min, p.elevation_max, samples)
    ends = solve_loop(p, p.phi3_load + np.append(0.0, arm_travel(elevations)))
    travel = ends.q[1:, 1] - ends.q[0, 1]
    rotation = np.linspace(0.0, arm_travel(p.elevation_min), samples)
    loop = solve_loop(p, p.phi3_load + rotation)
    delta = loop.q[:, 0] - loop.q[:, 2]
    mu = np.degrees(np.abs(np.arctan2(np.sin(delta), np.cos(delta))))
    fig = Figure(figsize=(11, 4))
    left, right = fig.subplots(1, 2)
    left.plot(np.degrees(elevations), travel * MM, color="C0")
    left.set_xlabel("elevation ε [deg]")
    left.set_ylabel("piston travel to ramming [mm]")
    panel_title(left, f"Piston travel (stroke needed: {required_stroke(p) * MM:.1f} mm)")
    right.plot(np.degrees(rotation), mu, color="C1", label="transmission angle μ")
    for limit in TRANSMISSION_BAND_DEG:
        right.axhline(limit, color="0.5", linestyle="--", linewidth=0.8)
    right.plot([], [], color="0.5", linestyle="--", linewidth=0.8, label="documented band")
    right.set_xlabel("arm rotation from loading [deg]")
    right.set_ylabel("transmission angle μ [deg]")
    panel_title(right, "Transmission angle at the rod-eye pin")
    right.legend(loc="lower left", fontsize=8)
    for ax in (left, right):
        ax.grid(True, linewidth=0.4, alpha=0.6)
    finish(fig, top=0.45, wspace=0.9)
    return fig
