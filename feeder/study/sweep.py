"""Elevation sweep: the peak loads and reactions of the cycle at each elevation."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from tqdm import tqdm

from ..device.feeder import Feeder
from ..dynamics.cycle import cycle_dynamics
from ..exceptions import InputError
from ..motion.laws import CycleSpec
from ..validation import check_elevation, check_finite
from .peaks import cycle_peaks


@dataclass(frozen=True)
class ElevationSweep:
    """Peak loads of a cycle at each elevation of a sweep.

    Attributes:
        elevations: ε [rad], (K,).
        peaks: Quantity name → peak value at each elevation (signed where the quantity is
            signed, else the magnitude) [SI unit], (K,).
        times: Quantity name → time of that peak in its cycle [s], (K,).
        units: Quantity name → SI unit.
    """

    elevations: np.ndarray
    peaks: dict[str, np.ndarray]
    times: dict[str, np.ndarray]
    units: dict[str, str]

    def worst(self, name: str) -> tuple[float, float]:
        """Elevation [rad] and value of the largest |peak| of ``name`` over the sweep."""
        k = int(np.argmax(np.abs(self.peaks[name])))
        return float(self.elevations[k]), float(self.peaks[name][k])


def elevation_sweep(
    feeder: Feeder,
    elevations: np.ndarray,
    spec: CycleSpec | None = None,
    progress: bool = True,
) -> ElevationSweep:
    """Peak loads and reactions of the cycle at each of ``elevations`` [rad].

    The forward (force-rule) run of each cycle is skipped: the peaks do not need it.

    Args:
        feeder: The device.
        elevations: ε [rad], shape (K,), K ≥ 1.
        spec: Stage durations and sample rate (default :class:`~feeder.motion.laws.CycleSpec`).
        progress: Show a progress bar over the cycles on a terminal (none when stderr is not
            one, e.g. in CI logs).

    Raises:
        InputError: ``elevations`` empty, not one-dimensional, or not finite.
        ElevationError: An elevation outside the device's range (checked before any work).
    """
    array = check_finite("elevations", elevations)
    if array.ndim != 1 or array.size == 0:
        raise InputError(f"elevations must be a non-empty 1-D array [rad], got {elevations!r}")
    elevations = np.array([check_elevation(e, feeder.params.elevation_limits) for e in array])
    rows = []
    quiet = None if progress else True  # None: tqdm shows the bar only on a terminal
    for elevation in tqdm(elevations, desc="elevation sweep", unit="cycle", disable=quiet):
        rows.append(cycle_peaks(cycle_dynamics(feeder, float(elevation), spec, forward=False)))
    names = [peak.name for peak in rows[0]]
    return ElevationSweep(
        elevations=elevations,
        peaks={n: np.array([row[i].value for row in rows]) for i, n in enumerate(names)},
        times={n: np.array([row[i].time for row in rows]) for i, n in enumerate(names)},
        units={peak.name: peak.unit for peak in rows[0]},
    )
