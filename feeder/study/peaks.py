"""The peak of every actuator load, drive and joint reaction over a cycle, with its time."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..dynamics.cycle import CycleDynamics
from .columns import vector_quantities


@dataclass(frozen=True)
class Peak:
    """Largest magnitude of one quantity over the cycle.

    Attributes:
        name: Column name (:data:`~feeder.study.columns.COLUMNS`).
        value: Value at the peak (signed for signed quantities) [unit].
        unit: SI unit.
        time: Time of the peak [s].
    """

    name: str
    value: float
    unit: str
    time: float


def cycle_peaks(d: CycleDynamics) -> list[Peak]:
    """Peak of each actuator load and drive (signed) and each joint reaction's magnitude."""
    t = d.kinematics.t
    signed = {
        "piston_force": (d.loads.piston_force, "N"),
        "cylinder_cap_pressure": (d.pressures.cap, "Pa"),
        "cylinder_rod_pressure": (d.pressures.rod, "Pa"),
        "forearm_torque": (d.loads.forearm_torque, "N·m"),
        "rack_force": (d.rack_force, "N"),
    }
    magnitudes = {
        name: (np.linalg.norm(vector, axis=1), unit)
        for name, (vector, unit) in vector_quantities(d).items()
    }
    peaks = []
    for name, (values, unit) in (signed | magnitudes).items():
        k = int(np.argmax(np.abs(values)))
        peaks.append(Peak(name, float(values[k]), unit, float(t[k])))
    return peaks
