"""Cycle dynamics shared by the dynamics tests, computed once per session (cached).

The elevations are conftest's. These are cached functions, so that the dynamics test modules
(through conftest's ``result`` and ``dyn`` fixtures, or directly for other devices) share one
result per device and elevation.
"""

from __future__ import annotations

import math
from dataclasses import replace
from functools import cache

from feeder.device import PROJECTILE_FEEDER, Feeder, load_feeder
from feeder.dynamics import CycleDynamics, FeederDynamics, cycle_dynamics

from ..conftest import ELEVATIONS_DEG

__all__ = ["ELEVATIONS_DEG", "cycle_result", "device", "device_dynamics", "toggle_device"]


@cache
def device(name: str = "projectile") -> Feeder:
    """The built-in device."""
    return load_feeder(name)


@cache
def device_dynamics(name: str = "projectile") -> FeederDynamics:
    """Its dynamics models."""
    return FeederDynamics(device(name))


@cache
def cycle_result(elevation_deg: float, name: str = "projectile") -> CycleDynamics:
    """The full cycle dynamics at ``elevation_deg``."""
    return cycle_dynamics(device(name), math.radians(elevation_deg))


@cache
def toggle_device() -> Feeder:
    """The reference device with its end stops opened so that the toggle is reachable.

    The toggle is where the cylinder pivot B, the arm pivot and the pin line up: φ3 =
    atan2(L2, L1) − π ≈ −29.7°, r2 ≈ 0.204 m, both outside the reference stops.
    """
    params = replace(PROJECTILE_FEEDER, name="toggle", phi3_min=math.radians(-45.0), r2_min=0.15)
    return load_feeder(params)
