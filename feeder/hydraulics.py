"""Drives: the hydraulic cylinder's chamber pressures and the forearm's rack force.

Ideal drives: no seal friction, no back pressure in the idle chamber, no losses in the gear.
The sizes are assumptions, not in the paper (:mod:`feeder.parameters`: ``bore_diameter``,
``rod_diameter``, ``pinion_radius``).

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

from .exceptions import InputError, check_finite
from .parameters import FeederParameters


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
    """Cap-end (bore) and rod-end (annulus) piston areas [m²].

    Raises:
        InputError: Bore or rod diameter not positive, or rod not thinner than the bore.
    """
    bore, rod = params.bore_diameter, params.rod_diameter
    if not 0.0 < rod < bore:
        raise InputError(
            f"cylinder needs 0 < rod diameter < bore diameter, got rod {rod!r} m, bore {bore!r} m"
        )
    cap = math.pi * bore**2 / 4.0
    return cap, cap - math.pi * rod**2 / 4.0


def cylinder_pressures(params: FeederParameters, piston_force: np.ndarray) -> CylinderPressures:
    """Chamber pressures that produce ``piston_force`` [N] (positive extends the rod).

    Raises:
        InputError: NaN/inf forces or a bad cylinder size (:func:`piston_areas`).
    """
    force = check_finite("piston force", piston_force)
    cap, annulus = piston_areas(params)
    return CylinderPressures(
        cap=np.where(force > 0.0, force / cap, 0.0),
        rod=np.where(force < 0.0, -force / annulus, 0.0),
    )


def rack_force(params: FeederParameters, forearm_torque: np.ndarray) -> np.ndarray:
    """Rack force [N] on the pinion's pitch circle that drives ``forearm_torque`` [N·m].

    Raises:
        InputError: NaN/inf moments or a non-positive pinion radius.
    """
    torque = check_finite("forearm torque", forearm_torque)
    radius = params.pinion_radius
    if not radius > 0.0:
        raise InputError(f"pinion radius must be positive, got {radius!r} m")
    return torque / radius
