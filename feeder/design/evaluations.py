"""The cycles a sensitivity study runs: the device as given and each parameter stepped to the
five :data:`~feeder.design.differences.OFFSETS`, at every elevation, on the sweep's executor.

Each cycle is a sweep case (:class:`~feeder.study.grid.SweepCase` holding the stepped
parameters, reduced to its peaks by :func:`~feeder.study.sweep.case_peaks`), run in batches on
the executor of :func:`~feeder.study.sweep.sweep_executor`: every local core, or a Dask
cluster. A stepped parameter set that fails its checks (its loop does not assemble over the
arm's travel, a pose near the toggle) is not a crash: its cases return the reason, and the
parameter's derivatives are reported unavailable with it.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass

import numpy as np

from ..device.loop import check_device
from ..device.parameters import FeederParameters
from ..exceptions import FeederError
from ..motion.laws import CycleSpec
from ..study.grid import SweepCase
from ..study.sweep import case_peaks, run_cases
from ..study.sweep_table import Row
from .differences import OFFSETS, offsets, step
from .differentiable import DesignParameter

NOMINAL = "nominal"
"""The variant name of the cases of the parameter set as given."""


@dataclass(frozen=True)
class Stepped:
    """One parameter stepped to the :data:`~feeder.design.differences.OFFSETS`.

    Attributes:
        parameter: The parameter.
        value: Its value as given [unit].
        h: The step [unit] (:func:`~feeder.design.differences.step`).
        steps: The exact steps taken [unit], (5,); the middle one is 0.
        sets: The parameter sets at the five offsets (the middle one is the given set).
        reason: Why a stepped set fails its checks (:func:`~feeder.device.loop.check_device`),
            or "" when all pass.
    """

    parameter: DesignParameter
    value: float
    h: float
    steps: np.ndarray
    sets: tuple[FeederParameters, ...]
    reason: str

    def variant(self, k: int) -> str:
        """The variant name of its cases at offset ``k`` (the given set's is :data:`NOMINAL`)."""
        return NOMINAL if OFFSETS[k] == 0.0 else f"{self.parameter.name}{OFFSETS[k]:+g}h"


def stepped(params: FeederParameters, parameter: DesignParameter, factor: float) -> Stepped:
    """``parameter`` of ``params`` stepped by the relative step ``factor``, each set checked."""
    value = parameter.value(params)
    h = step(value, parameter.scale, factor)
    values, steps = offsets(value, h)
    sets, reason = [], ""
    for k, stepped_value in enumerate(values):
        changed = params if OFFSETS[k] == 0.0 else parameter.changed(params, float(stepped_value))
        if not reason and changed is not params:
            try:
                check_device(changed)
            except FeederError as exc:
                reason = f"{parameter.name} = {stepped_value:.9g} {parameter.unit}: {exc}"
        sets.append(changed)
    return Stepped(parameter, value, h, steps, tuple(sets), reason)


def cases_of(
    params: FeederParameters,
    steps: Sequence[Stepped],
    elevations_deg: Sequence[float],
    spec: CycleSpec,
) -> list[SweepCase]:
    """Every case to run: the given set at each elevation, then each parameter's stepped sets
    that pass their checks (by parameter, offset, elevation: a batch reuses one model)."""
    cases = [
        SweepCase(params.name, NOMINAL, float(e), math.radians(e), params, spec)
        for e in elevations_deg
    ]
    for item in steps:
        if item.reason:
            continue
        for k, changed in enumerate(item.sets):
            if OFFSETS[k] == 0.0:
                continue
            cases += [
                SweepCase(params.name, item.variant(k), float(e), math.radians(e), changed, spec)
                for e in elevations_deg
            ]
    return cases


Outcome = Row | str
"""A case's peaks (a sweep table's row), or why its cycle failed."""


def _outcome(case: SweepCase) -> tuple[tuple[str, str, float], Outcome]:
    """A case's key and outcome (in a worker)."""
    try:
        return case.key, case_peaks(case)
    except FeederError as exc:
        return case.key, f"{case.variant} at {case.elevation_deg:g}°: {exc}"


def run_evaluations(
    cases: Sequence[SweepCase],
    executor: Executor | None,
    slots: int = 1,
    progress: bool = True,
) -> Iterator[tuple[tuple[str, str, float], Outcome]]:
    """Run the cases, yielding (key, outcome) as they complete (not in order).

    Args:
        cases: The cases (:func:`cases_of`).
        executor: Where to run them (:func:`~feeder.study.sweep.sweep_executor`); None: here.
        slots: Cases the executor runs at once (sets the batch size, as the sweep's).
        progress: A progress bar on a terminal.
    """
    return run_cases(
        cases, executor, slots, progress, work=_outcome, unit="cycle", desc="sensitivities"
    )
