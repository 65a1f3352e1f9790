"""Drives: the hydraulic cylinder's chamber pressures and the forearm's rack force.

Ideal drives: no seal friction, no back pressure in the idle chamber, no losses in the gear.
The sizes are assumptions, not in the paper (:mod:`feeder.device.parameters`: ``bore_diameter``,
``rod_diameter``, ``pinion_radius``, checked there: 0 < rod < bore, pinion radius > 0).

* Cylinder (arm lift). A positive piston force (along ``piston_joint``'s axis, extending the
  rod) is made by the cap-end chamber acting on the full bore area A = π D²/4; a negative one
  (pulling the rod in) by the rod-end chamber acting on the annulus A = π (D² − d²)/4. The other
  chamber is at zero gauge pressure.
* Rack and pinion (forearm swing; paper, section I). The rack force on the pinion's pitch circle
  is F = M / r, signed like the forearm moment M.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..device.parameters import FeederParameters


@dataclass(frozen=True)
class CylinderPressures:
    """Gauge pressures [Pa] in the two chambers of the lift cylinder, shape (N,) each.

    Attributes:
        cap: Cap-end (full bore) chamber: pushes the rod out.
        rod: Rod-end (annulus) chamber: pulls the rod in.
    """

    cap: np.ndarray
    rod: np.ndarray

    def peak(self) -> np.ndarray:
        """Pressure of the working chamber, max(cap, rod) [Pa], shape (N,)."""
        return np.maximum(self.cap, self.rod)


def piston_areas(params: FeederParameters) -> tuple[float, float]:
    """Cap-end (bore) and rod-end (annulus) piston areas [m²]."""
    bore, rod = params.bore_diameter, params.rod_diameter
    cap = math.pi * bore**2 / 4.0
    return cap, cap - math.pi * rod**2 / 4.0


def cylinder_pressures(params: FeederParameters, piston_force: np.ndarray) -> CylinderPressures:
    """Chamber pressures that produce ``piston_force`` [N], shape (N,), positive extending."""
    force = np.asarray(piston_force, dtype=float)
    cap, annulus = piston_areas(params)
    return CylinderPressures(
        cap=np.where(force > 0.0, force / cap, 0.0),
        rod=np.where(force < 0.0, -force / annulus, 0.0),
    )


def rack_force(params: FeederParameters, forearm_torque: np.ndarray) -> np.ndarray:
    """Rack force [N] on the pinion's pitch circle that drives ``forearm_torque`` [N·m], (N,)."""
    return np.asarray(forearm_torque, dtype=float) / params.pinion_radius
