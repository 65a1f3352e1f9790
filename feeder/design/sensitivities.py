"""Sensitivities of the device's peak loads to its geometry and masses: the derivative of every
peak of the cycle (the peaks ``feeder sweep`` reports: piston force, chamber pressures, forearm
moment, rack force, every pin's reaction, the mount) with respect to every differentiable
parameter (:mod:`feeder.design.differentiable`), at one elevation and as the envelope over an
elevation range, in SI units per unit of the parameter and as an elasticity (percent of the
peak per percent of the parameter).

**Why finite differences.** A peak is a maximum over the samples of a cycle, and the envelope a
maximum over elevations too: it is differentiable only where its argmax stays put, and a
derivative must say where it is not, which differences of full runs show directly (a kink
between the one-sided differences) and an analytic derivative at a fixed argmax would hide. The
loop closure and the arm travel are solved numerically for every parameter set, and a length
changes the URDF the model is built from (joint placements, inertia placements): derivatives
through all of that would be a second implementation of the pipeline, to be kept in step with
it. Central differences of the whole pipeline differentiate exactly what ``feeder cycle`` and
``feeder sweep`` compute, with the step and its check of :mod:`feeder.design.differences`
(error estimate: the difference between the estimates over h and h/2).

**The envelope.** Its value is the peak at the elevation where |peak| is largest; its
derivative is the central difference of that maximum, which equals the derivative at that
elevation unless the argmax moves within the step. Where the argmax elevation or time moves
between the five runs, the entry says so (``moved``), and where the one-sided differences then
disagree beyond the round-off, it is flagged a kink (not differentiable within the step).

The cycles (parameters × 4 steps × elevations, and the device as given) run on every core or a
Dask cluster (:mod:`feeder.design.evaluations`); a stepped set that does not assemble, or whose
cycle fails, makes that parameter's derivatives unavailable, with the reason.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..device.loop import check_device
from ..device.parameters import FeederParameters
from ..exceptions import FeederError, InputError
from ..motion.laws import CycleSpec
from ..study.elevation_sweeps import UNITS
from ..study.sweep import sweep_executor
from ..study.sweep_table import row_quantities
from ..validation import check_elevation, check_elevations_deg, check_number
from ..viz.catalog import elevations_text
from .differences import STEP_FACTOR, Estimate, check_step_factor, estimate
from .differentiable import DesignParameter, chosen_parameters
from .evaluations import NOMINAL, Outcome, Stepped, cases_of, run_evaluations, stepped

LEVEL_DUPLICATES = ("mount_force_vehicle", "mount_moment_vehicle")
"""Peaks left out: standing level, the mount's wrench in the vehicle's axes is the level one."""


@dataclass(frozen=True)
class Peak:
    """A peak of the device as given, in one scope.

    Attributes:
        name: The ``cycle.csv`` column (:data:`~feeder.study.columns.COLUMNS`).
        unit: Its SI unit.
        value: The peak (signed where the quantity is) [unit].
        elevation_deg: The elevation of the peak [deg].
        time: Its time in the cycle [s].
    """

    name: str
    unit: str
    value: float
    elevation_deg: float
    time: float


@dataclass(frozen=True)
class Sensitivity:
    """The derivative of one peak with respect to one parameter.

    Attributes:
        peak: The peak of the device as given.
        parameter: The parameter.
        value: The parameter's value [its unit].
        h: Its step [its unit].
        estimate: The differences (:class:`~feeder.design.differences.Estimate`), None when
            unavailable.
        reason: Why it is unavailable ("" when available).
        moved: Where the argmax moved within the step: "", "time", "elevation" or
            "elevation, time".
    """

    peak: Peak
    parameter: DesignParameter
    value: float
    h: float
    estimate: Estimate | None
    reason: str
    moved: str

    @property
    def derivative(self) -> float:
        """d peak / d parameter [peak unit per parameter unit]; NaN when unavailable."""
        return self.estimate.derivative if self.estimate else math.nan

    @property
    def elasticity(self) -> float:
        """(p / peak) · d peak / dp [-]: percent of the peak per percent of the parameter; NaN
        when unavailable or the peak is zero."""
        if self.estimate is None or self.peak.value == 0.0:
            return math.nan
        return self.derivative * self.value / self.peak.value

    @property
    def status(self) -> str:
        """``ok``, ``kink`` (read the one-sided differences) or ``unavailable``."""
        if self.estimate is None:
            return "unavailable"
        return "kink" if self.estimate.kink else "ok"


@dataclass(frozen=True)
class Scope:
    """The sensitivities of every peak over one set of elevations.

    Attributes:
        name: ``elevation`` (one elevation) or ``envelope`` (the largest over a range).
        elevations_deg: The elevations [deg], (K,).
        peaks: The peaks of the device as given, in the sweep's column order.
        entries: (peak name, parameter name) → its :class:`Sensitivity`.
    """

    name: str
    elevations_deg: tuple[float, ...]
    peaks: tuple[Peak, ...]
    entries: dict[tuple[str, str], Sensitivity]

    @property
    def title(self) -> str:
        """``ε = 30°`` or ``envelope over ε = −4° … 70° (every 2°)``
        (:func:`~feeder.viz.catalog.elevations_text`)."""
        text = elevations_text(self.elevations_deg)
        return text if self.name == "elevation" else f"envelope over {text}"


@dataclass(frozen=True)
class Sensitivities:
    """What :func:`design_sensitivities` computed.

    Attributes:
        device: The parameter set's name.
        parameters: The parameters, in table order.
        steps: Each parameter's stepped sets (value, step, reason if a set fails).
        scopes: The one elevation's scope and/or the envelope's.
        spec: The cycles' timing.
        factor: The relative step.
        cycles: Cycles run.
        seconds: Wall time of the runs [s].
    """

    device: str
    parameters: tuple[DesignParameter, ...]
    steps: tuple[Stepped, ...]
    scopes: tuple[Scope, ...]
    spec: CycleSpec
    factor: float
    cycles: int
    seconds: float

    @property
    def title(self) -> str:
        """What the figure's panels are titled with: ``projectile feeder``."""
        return f"{self.device} feeder"


def check_inputs(
    params: FeederParameters,
    elevations_deg: Sequence[float] | None,
    elevation_deg: float | None,
    parameters: Sequence[str] | None,
    factor: float,
) -> tuple[list[float], float | None, tuple[DesignParameter, ...], float]:
    """The arguments of :func:`design_sensitivities` checked, before any work: (the envelope's
    elevations [deg], the one elevation [deg] or None, the parameters, the relative step).

    Raises:
        InputError: As :func:`design_sensitivities` says.
    """
    every, one = _elevations(params, elevations_deg, elevation_deg)
    chosen = chosen_parameters(None if parameters is None else list(parameters))
    return every, one, chosen, check_step_factor(factor)


def _elevations(
    params: FeederParameters, elevations_deg: Sequence[float] | None, elevation_deg: float | None
) -> tuple[list[float], float | None]:
    if elevations_deg is None and elevation_deg is None:
        raise InputError("give an elevation range (--elevations), an elevation, or both")
    limits = params.elevation_limits
    every = [] if elevations_deg is None else check_elevations_deg(elevations_deg, limits)
    one = None if elevation_deg is None else check_number("elevation [deg]", elevation_deg)
    if one is not None:
        check_elevation(math.radians(one), limits)
    return every, one


def envelope_estimate(
    values: np.ndarray, times: np.ndarray, steps: np.ndarray, factor: float = STEP_FACTOR
) -> tuple[Estimate, str]:
    """The derivative of the largest |peak| over elevations, and where its argmax moved.

    Args:
        values: The peak at each offset (rows: the five
            :data:`~feeder.design.differences.OFFSETS`) and elevation (columns) [unit], (5, K).
        times: The time of each of those peaks [s], (5, K).
        steps: The exact steps of the parameter [its unit], (5,).
        factor: The relative step.

    Returns:
        The :class:`~feeder.design.differences.Estimate` of the envelope (the signed value at
        the largest |peak| of each row), and "", "elevation", "time" or "elevation, time": what
        moved between the five rows.
    """
    values = np.asarray(values, dtype=float)
    columns = np.argmax(np.abs(values), axis=1)
    rows = np.arange(values.shape[0])
    found = estimate(values[rows, columns], steps, factor)
    picked = np.asarray(times, dtype=float)[rows, columns]
    where = [("elevation", np.unique(columns).size), ("time", np.unique(picked).size)]
    return found, ", ".join(label for label, count in where if count > 1)


def _scope(
    name: str,
    elevations: list[float],
    outcomes: dict[tuple[str, str, float], Outcome],
    device: str,
    steps: Sequence[Stepped],
    factor: float,
) -> Scope:
    nominal = [outcomes[(device, NOMINAL, e)] for e in elevations]
    names = [n for n in row_quantities(nominal[0]) if n not in LEVEL_DUPLICATES]
    peaks = []
    for peak in names:
        values = np.array([row[peak] for row in nominal], dtype=float)
        k = int(np.argmax(np.abs(values)))
        peaks.append(
            Peak(peak, UNITS[peak], float(values[k]), elevations[k], nominal[k][f"{peak}_time"])
        )
    entries = {}
    for item in steps:
        runs = [
            [outcomes.get((device, item.variant(k), e), "") for e in elevations] for k in range(5)
        ]
        failed = item.reason or next((o for rs in runs for o in rs if isinstance(o, str)), "")
        for peak in peaks:
            found, moved = None, ""
            if not failed:
                values = [[row[peak.name] for row in rs] for rs in runs]
                times = [[row[f"{peak.name}_time"] for row in rs] for rs in runs]
                found, moved = envelope_estimate(values, times, item.steps, factor)
            entries[(peak.name, item.parameter.name)] = Sensitivity(
                peak, item.parameter, item.value, item.h, found, failed, moved
            )
    return Scope(name, tuple(elevations), tuple(peaks), entries)


def design_sensitivities(
    params: FeederParameters,
    *,
    elevations_deg: Sequence[float] | None = None,
    elevation_deg: float | None = None,
    parameters: Sequence[str] | None = None,
    spec: CycleSpec | None = None,
    factor: float = STEP_FACTOR,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = True,
) -> Sensitivities:
    """The sensitivities of every peak to each parameter (module docstring).

    Args:
        params: The device.
        elevations_deg: The envelope's elevations [deg], (K,)
            (:func:`~feeder.study.grid.elevation_range`); None: no envelope.
        elevation_deg: The one elevation [deg]; None: the envelope only.
        parameters: Parameter names (:func:`~feeder.design.differentiable.design_parameters`);
            None: all of them.
        spec: The cycles' timing (default :class:`~feeder.motion.laws.CycleSpec`, 1 kHz).
        factor: The relative step (default ε^(1/3), :mod:`feeder.design.differences`).
        workers: Local processes (default: every core; 1: here). Ignored with a scheduler.
        scheduler: A Dask scheduler ``tcp://HOST:PORT`` to run the cycles on.
        progress: A progress bar on a terminal.

    Raises:
        InputError: Neither elevations nor an elevation; an elevation outside the device's
            range (ElevationError); an unknown parameter; a step not in (0, 0.1]; bad workers
            or scheduler.
        FeederError: The device as given does not assemble, or its cycle fails.
    """
    every, one, chosen, factor = check_inputs(
        params, elevations_deg, elevation_deg, parameters, factor
    )
    spec = spec or CycleSpec()
    check_device(params)
    steps = tuple(stepped(params, parameter, factor) for parameter in chosen)
    elevations = list(dict.fromkeys([*every, *([] if one is None else [one])]))
    cases = cases_of(params, steps, elevations, spec)
    start = time.monotonic()
    with sweep_executor(workers, scheduler) as (executor, slots):
        outcomes = dict(run_evaluations(cases, executor, slots, progress))
    seconds = time.monotonic() - start
    for e in elevations:
        failure = outcomes[(params.name, NOMINAL, e)]
        if isinstance(failure, str):
            raise FeederError(f"the device as given fails: {failure}")
    scopes = []
    if one is not None:
        scopes.append(_scope("elevation", [one], outcomes, params.name, steps, factor))
    if every:
        scopes.append(_scope("envelope", every, outcomes, params.name, steps, factor))
    return Sensitivities(
        params.name, chosen, steps, tuple(scopes), spec, factor, len(cases), seconds
    )
