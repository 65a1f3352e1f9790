"""Drawings of the device: its side view at several poses, the payload's workspace (paper
Fig. 4) and the loop's stroke and transmission angle over the elevation range. Every function
returns a :class:`matplotlib.figure.Figure`; saving it is the caller's."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
from matplotlib.figure import Figure

from ..device.feeder import Feeder
from ..device.loop import TRANSMISSION_BAND_DEG, arm_travel, required_stroke, solve_loop
from ..device.urdf_writer import barrel_length
from ..motion.cycle import CycleKinematics
from ..motion.workspace import Workspace


def workspace_figure(space: Workspace, device: str) -> Figure:
    """Paper Fig. 4: the payload's path in the vertical plane and its ramming poses.

    Args:
        space: The workspace (:func:`~feeder.motion.workspace.workspace`).
        device: Device name for the title.
    """
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
    fig.tight_layout()
    return fig


def side_view_figure(feeder: Feeder, cycle: CycleKinematics, poses: int = 6) -> Figure:
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
    fig.tight_layout()
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
    left.plot(np.degrees(elevations), travel * 1e3, color="C0")
    left.set_xlabel("elevation ε [deg]")
    left.set_ylabel("piston travel to ramming [mm]")
    left.set_title(f"Piston travel (stroke needed: {required_stroke(p) * 1e3:.1f} mm)")
    right.plot(np.degrees(rotation), mu, color="C1", label="transmission angle μ")
    for limit in TRANSMISSION_BAND_DEG:
        right.axhline(limit, color="0.5", linestyle="--", linewidth=0.8)
    right.plot([], [], color="0.5", linestyle="--", linewidth=0.8, label="documented band")
    right.set_xlabel("arm rotation from loading [deg]")
    right.set_ylabel("transmission angle μ [deg]")
    right.set_title("Transmission angle at the rod-eye pin")
    right.legend(loc="best", fontsize=8)
    for ax in (left, right):
        ax.grid(True, linewidth=0.4, alpha=0.6)
    fig.tight_layout()
    return fig
