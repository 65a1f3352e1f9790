"""Peak loads against elevation: :class:`ElevationSweep`, one device's sweep in memory
(:func:`elevation_sweep`), and a sweep table's rows as such sweeps (:func:`sweeps_of`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..device.feeder import Feeder
from ..exceptions import InputError
from ..motion.laws import CycleSpec
from ..validation import check_elevation, check_finite
from .columns import COLUMNS
from .grid import SweepCase
from .sweep import run_cases, sweep_executor
from .sweep_table import Row, row_quantities

UNITS = {column.name: column.unit for column in COLUMNS}
"""Quantity name → its SI unit (the ``cycle.csv`` column's)."""


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
    workers: int | None = None,
) -> ElevationSweep:
    """Peak loads and reactions of the cycle at each of ``elevations`` [rad], in memory.

    The forward (force-rule) run of each cycle is skipped: the peaks do not need it.

    Args:
        feeder: The device.
        elevations: ε [rad], shape (K,), K ≥ 1.
        spec: Stage durations and sample rate (default :class:`~feeder.motion.laws.CycleSpec`).
        progress: Show a progress bar over the cycles on a terminal (none when stderr is not
            one, e.g. in CI logs).
        workers: Processes (default: every core; 1 computes here).

    Raises:
        InputError: ``elevations`` empty, not one-dimensional, or not finite; bad ``workers``.
        ElevationError: An elevation outside the device's range (checked before any work).
    """
    array = check_finite("elevations", elevations)
    if array.ndim != 1 or array.size == 0:
        raise InputError(f"elevations must be a non-empty 1-D array [rad], got {elevations!r}")
    elevations = np.array([check_elevation(e, feeder.params.elevation_limits) for e in array])
    spec = spec or CycleSpec()
    params = feeder.params
    cases = [
        SweepCase(params.name, "reference", math.degrees(e), float(e), params, spec)
        for e in elevations
    ]
    with sweep_executor(workers) as (executor, slots):
        rows = {row["elevation_deg"]: row for row in run_cases(cases, executor, slots, progress)}
    ordered = [rows[case.elevation_deg] for case in cases]
    names = row_quantities(ordered[0])
    return ElevationSweep(
        elevations=elevations,
        peaks={n: np.array([row[n] for row in ordered], dtype=float) for n in names},
        times={n: np.array([row[f"{n}_time"] for row in ordered], dtype=float) for n in names},
        units={n: UNITS[n] for n in names},
    )


def sweeps_of(rows: Sequence[Row]) -> dict[tuple[str, str], ElevationSweep]:
    """A table's rows as one :class:`ElevationSweep` per (device, variant), each by increasing
    elevation."""
    groups: dict[tuple[str, str], list[Row]] = {}
    for row in rows:
        groups.setdefault((str(row["device"]), str(row["variant"])), []).append(row)
    sweeps = {}
    for key, group in groups.items():
        group.sort(key=lambda row: float(row["elevation_deg"]))
        names = row_quantities(group[0])
        sweeps[key] = ElevationSweep(
            elevations=np.radians([float(row["elevation_deg"]) for row in group]),
            peaks={n: np.array([row[n] for row in group], dtype=float) for n in names},
            times={n: np.array([row[f"{n}_time"] for row in group], dtype=float) for n in names},
            units={n: UNITS[n] for n in names},
        )
    return sweeps
