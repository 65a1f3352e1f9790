"""Text summaries for the command line."""

from __future__ import annotations

import numpy as np

from ..device.feeder import Feeder
from ..device.loop import arm_travel, required_stroke
from ..motion.cycle import CycleKinematics


def kinematics_summary(feeder: Feeder, cycle: CycleKinematics) -> str:
    """Stroke, travel, peak payload speed, transmission band and closure of a sampled cycle."""
    speed = np.linalg.norm(cycle.payload_velocity, axis=1)
    k = int(np.argmax(speed))
    mu = np.degrees(cycle.transmission_angle)
    return "\n".join(
        [
            f"{feeder.params.name} feeder, elevation {np.degrees(cycle.elevation):g}°",
            "  piston stroke needed over the range: "
            f"{required_stroke(feeder.params) * 1e3:.1f} mm",
            f"  piston travel this cycle: {(cycle.q[-1, 1] - cycle.q[0, 1]) * 1e3:.1f} mm",
            f"  arm travel: {np.degrees(arm_travel(cycle.elevation)):.1f}°",
            f"  peak payload speed: {speed[k]:.3f} m/s at t = {cycle.t[k]:.3f} s",
            f"  transmission angle: {mu.min():.1f}° … {mu.max():.1f}°",
            f"  max closure residual: {cycle.closure_residual.max():.2e} m",
        ]
    )
