"""Studies built on one loading cycle.

* :func:`run_cycle_study` / :func:`write_cycle_study`: the standard study, Pinocchio's loads
  cross-checked by the hand-derived Lagrange equations, written as ``cycle.csv`` and the figures
  of the paper's Figs. 4, 8, 10–15 (the ``feeder cycle`` command).
* :func:`elevation_sweep`: the peak loads at each elevation of a sweep.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from tqdm import tqdm

from .cycle import CycleSpec
from .cycle_dynamics import CycleDynamics, cycle_dynamics
from .device import Feeder
from .exceptions import InputError, check_elevation, check_finite
from .lagrange import LagrangeLoads, lagrange_cycle_loads
from .plots import plot_cycle_figures, plot_mechanism, plot_position, plot_workspace
from .results import write_csv
from .workspace import workspace


@dataclass(frozen=True)
class CycleStudy:
    """One cycle's results from both computations.

    Attributes:
        dynamics: Pinocchio: kinematics, loads, reactions, drives, forward run.
        lagrange: The hand-derived equations' loads and multipliers on the same motion.
    """

    dynamics: CycleDynamics
    lagrange: LagrangeLoads

    def columns(self) -> dict[str, np.ndarray]:
        """Every column of the ``cycle.csv`` contract (REFERENCE.md), and the extras."""
        return self.dynamics.columns() | self.lagrange.columns()

    def cross_check(self) -> tuple[float, float]:
        """Largest |Lagrange − Pinocchio| of the piston force [N] and forearm moment [N·m]."""
        loads = self.dynamics.loads
        return (
            float(np.abs(self.lagrange.piston_force - loads.piston_force).max()),
            float(np.abs(self.lagrange.forearm_torque - loads.forearm_torque).max()),
        )

    def summary(self) -> str:
        """The dynamics summary and the cross-check, as text."""
        force, torque = self.cross_check()
        return (
            f"{self.dynamics.summary()}\n  Lagrange equations vs Pinocchio: piston force "
            f"within {force:.1e} N, forearm moment within {torque:.1e} N·m"
        )


def run_cycle_study(
    feeder: Feeder,
    elevation: float,
    spec: CycleSpec | None = None,
    progress: bool = False,
    forward: bool = True,
) -> CycleStudy:
    """Dynamics of one cycle at ``elevation`` [rad] by Pinocchio and by the Lagrange equations.

    ``forward=False`` skips the force-rule forward run (and its ``forward_*`` columns)."""
    dynamics = cycle_dynamics(feeder, elevation, spec, progress=progress, forward=forward)
    return CycleStudy(dynamics, lagrange_cycle_loads(feeder, dynamics.kinematics))


def write_cycle_study(study: CycleStudy, feeder: Feeder, directory: str | Path) -> list[Path]:
    """Write ``cycle.csv`` and every figure of the study into ``directory``."""
    directory = Path(directory)
    kinematics = study.dynamics.kinematics
    columns = study.columns()
    low, high = feeder.params.elevation_limits
    space = workspace(feeder, np.radians(np.arange(np.degrees(low), np.degrees(high) + 1, 10)))
    return [
        write_csv(directory / "cycle.csv", columns),
        plot_mechanism(directory / "device_side_view.png", feeder, kinematics),
        plot_workspace(directory / "fig04_workspace.png", space, feeder.params.name),
        plot_position(directory / "fig10_projectile_position.png", kinematics),
        *plot_cycle_figures(
            directory,
            columns,
            kinematics.spec.boundaries,
            float(np.degrees(kinematics.elevation)),
        ),
    ]


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
        spec: Stage durations and sample rate (default :class:`~feeder.cycle.CycleSpec`).
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
        rows.append(cycle_dynamics(feeder, float(elevation), spec, forward=False).peaks())
    names = [peak.name for peak in rows[0]]
    return ElevationSweep(
        elevations=elevations,
        peaks={n: np.array([row[i].value for row in rows]) for i, n in enumerate(names)},
        times={n: np.array([row[i].time for row in rows]) for i, n in enumerate(names)},
        units={peak.name: peak.unit for peak in rows[0]},
    )
