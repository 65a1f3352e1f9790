"""Workspace of the payload (paper Fig. 4): its path while the arm turns, and the ramming poses.

The largest path belongs to the lowest elevation (−4°: 94° of arm travel); every other elevation's
path is the first part of it, ending where the payload axis is parallel to the barrel.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..device.feeder import Feeder
from ..device.loop import arm_travel, solve_loop
from ..validation import check_elevation, check_finite
from .cycle import payload_kinematics


@dataclass(frozen=True)
class Workspace:
    """Payload path over the elevation range.

    Attributes:
        phi3: Arm angles along the path [rad], (M,).
        position: Payload CG along the path [m], (M, 3), world frame.
        elevations: Elevations of the ramming poses [rad], (K,).
        ram_position: Payload CG at ramming for each elevation [m], (K, 3).
        ram_axis: Payload axis (unit, nose first) at ramming, (K, 3).
    """

    phi3: np.ndarray
    position: np.ndarray
    elevations: np.ndarray
    ram_position: np.ndarray
    ram_axis: np.ndarray


def _poses(feeder: Feeder, phi3: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    loop = solve_loop(feeder.params, phi3)
    position, _, axis, _ = payload_kinematics(feeder, loop.q, loop.v)
    return position, axis


def workspace(feeder: Feeder, elevations: np.ndarray, samples: int = 200) -> Workspace:
    """Payload path from loading to the lowest elevation, and the ramming poses at ``elevations``.

    Args:
        feeder: The device.
        elevations: Elevations [rad], (K,), each inside the device's range.
        samples: Points along the path.
    """
    p = feeder.params
    elevations = np.array(
        [
            check_elevation(e, p.elevation_limits)
            for e in np.ravel(check_finite("elevations", elevations))
        ]
    )
    phi3 = p.phi3_load + np.linspace(0.0, arm_travel(p.elevation_min), samples)
    position, _ = _poses(feeder, phi3)
    ram_position, ram_axis = _poses(feeder, p.phi3_load + arm_travel(elevations))
    return Workspace(phi3, position, elevations, ram_position, ram_axis)
