"""Sensitivities of a mechanism's peaks to its design variables (``feeder design sensitivities
MODEL --design FILE``): the derivative of every peak of the loads (drive loads, joint
reactions, closure forces and moments, element forces, the velocity gain; each the largest
|value| over the samples of every motion table) with respect to every variable of the design
file, in SI units per unit of the variable and as an elasticity (percent of the peak per
percent of the variable).

As for the device (:mod:`feeder.design.sensitivities`, which says why finite differences of
full runs), each variable is stepped to the five offsets of :mod:`feeder.design.differences`
(step ε^(1/3) · max(|p|, its unit's scale), checked by halving, the kink test where the argmax
sample or table moves); the 4n + 1 points run in one batch on the sweep's executor
(:mod:`~feeder.design.mechanism.problem`). The tables, the summary and the heat map are the
device's (:mod:`feeder.design.tables`, :mod:`feeder.design.figure`), with the motion tables in
place of the elevations.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from ...exceptions import InputError
from ...study.sweep import sweep_executor
from ..differences import OFFSETS, estimate, offsets, step
from ..differentiable import DesignParameter
from ..sensitivities import Sensitivity
from ..tables import cell, flag_lines, shown, top_elasticities
from .design_file import MechanismDesign
from .evaluation import Mechanism
from .problem import MechanismProblem


@dataclass(frozen=True)
class MechanismPeak:
    """A peak of the model as given.

    Attributes:
        name: Its name (:mod:`~feeder.design.mechanism.evaluation`: a ``loads.csv`` column).
        unit: Its SI unit.
        value: The value of largest magnitude over every table's samples [unit].
        table: The motion table where it is.
        time: Its time there [s].
    """

    name: str
    unit: str
    value: float
    table: str
    time: float


@dataclass(frozen=True)
class MotionScope:
    """The sensitivities of every peak over the motion tables (the device's
    :class:`~feeder.design.sensitivities.Scope`, with tables for elevations)."""

    name: str
    tables: tuple[str, ...]
    peaks: tuple[MechanismPeak, ...]
    entries: dict[tuple[str, str], Sensitivity]

    @property
    def title(self) -> str:
        """``over motion.csv, lowering.csv``."""
        return "over " + ", ".join(self.tables)


@dataclass(frozen=True)
class MechanismSensitivities:
    """What :func:`mechanism_sensitivities` computed.

    Attributes:
        name: The model's name (its file's stem).
        parameters: The variables, in table order.
        scopes: The one scope over every motion table.
        zero: The peaks left out: zero to round-off (:meth:`~.evaluation.Run.round_off`).
        factor: The relative step.
        runs: Runs made (points × tables).
        seconds: Wall time [s].
    """

    name: str
    parameters: tuple[DesignParameter, ...]
    scopes: tuple[MotionScope, ...]
    zero: tuple[str, ...]
    factor: float
    runs: int
    seconds: float

    @property
    def title(self) -> str:
        """What the figure's panels are titled with."""
        return f"{self.name} mechanism"


def mechanism_sensitivities(
    design: MechanismDesign,
    mechanism: Mechanism,
    factor: float,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = True,
) -> MechanismSensitivities:
    """The derivatives of every peak at the variables' starts (module docstring).

    Raises:
        InputError: Bad workers or scheduler; the model as given fails to run (its reason).
    """
    x0 = np.array([v.start for v in design.variables])
    points, grids = [x0], []
    for k, v in enumerate(design.variables):
        values, steps = offsets(x0[k], step(x0[k], v.parameter.scale, factor))
        grid = [x0.copy() for _ in OFFSETS]
        for i, value in enumerate(values):
            grid[i][k] = x0[k] if OFFSETS[i] == 0.0 else value
        grids.append((grid, steps))
        points += [g for i, g in enumerate(grid) if OFFSETS[i] != 0.0]
    began = time.monotonic()
    with sweep_executor(workers, scheduler) as (executor, slots):
        problem = MechanismProblem(design, mechanism, executor, slots)
        found = problem.evaluate(points)
    seconds = time.monotonic() - began
    reference = found[0]
    if reference.failure:
        raise InputError(f"the model as given fails: {reference.failure}")
    run = reference.run
    peaks, zero = [], [name for name in run.series if run.round_off(name)]
    for name in (name for name in run.series if name not in zero):
        value, m, t = run.signed_peak(name)
        peaks.append(MechanismPeak(name, run.units[name], value, problem.tables[m], t))
    entries = {}
    for (grid, steps), v, k in zip(grids, design.variables, range(len(grids)), strict=True):
        evaluated = problem.evaluate(grid)
        failed = next((e.failure for e in evaluated if e.failure), "")
        for peak in peaks:
            found_estimate, moved, reason = None, "", ""
            if failed:
                reason = f"{v.name} stepped: {failed}"
            else:
                values = np.array([e.peaks(peak.name).max() for e in evaluated])
                found_estimate = estimate(values, steps, factor)
                places = {int(np.argmax(e.peaks(peak.name))) for e in evaluated}
                moved = "time" if len(places) > 1 else ""  # the sample, in a table or another
            h = float(steps[-1])
            entries[(peak.name, v.name)] = Sensitivity(
                peak, v.parameter, float(x0[k]), h, found_estimate, reason, moved
            )
    scope = MotionScope("motion", tuple(problem.tables), tuple(peaks), entries)
    parameters = tuple(v.parameter for v in design.variables)
    return MechanismSensitivities(
        mechanism.model.stem, parameters, (scope,), tuple(zero), factor, problem.cycles, seconds
    )


def wide_rows(result: MechanismSensitivities) -> list[list[str]]:
    """``sensitivities.csv``: ``peak``, ``unit``, ``value``, ``motion`` (the table of the peak),
    ``time_s``, then ``d_<variable>`` [peak unit per variable unit] and
    ``elasticity_<variable>`` [% per %] for each variable."""
    names = [p.name for p in result.parameters]
    rows = [["peak", "unit", "value", "motion", "time_s"]]
    rows[0] += [f"d_{n}" for n in names] + [f"elasticity_{n}" for n in names]
    (scope,) = result.scopes
    for peak in scope.peaks:
        entries = [scope.entries[(peak.name, n)] for n in names]
        rows.append(
            [peak.name, peak.unit, cell(peak.value), peak.table, cell(peak.time)]
            + [cell(e.derivative) for e in entries]
            + [cell(e.elasticity) for e in entries]
        )
    return rows


def summary(result: MechanismSensitivities) -> str:
    """The summary printed and written to ``summary.txt``."""
    names = [p.name for p in result.parameters]
    (scope,) = result.scopes
    lines = [
        f"Sensitivities of the {result.name} mechanism's peaks to {len(names)} design variables "
        f"({', '.join(names)}): {result.runs} runs {scope.title} in {result.seconds:.1f} s.",
        f"Step h = {result.factor:.3g} · max(|p|, 0.1 m, 0.1 rad, 1 kg or 1), derivative over "
        "h/2, error estimate |D(h) − D(h/2)|.",
        "",
        "largest elasticities [% of the peak per % of the variable]:",
    ]
    width = max(len(p.name) for p in scope.peaks)
    for peak in scope.peaks:
        lines.append(
            f"  {peak.name:<{width}}  {shown(peak.value, peak.unit)} ({peak.table}, "
            f"t = {peak.time:g} s): {top_elasticities(scope, peak.name, names)}"
        )
    if result.zero:
        lines.append(f"  left out, zero to round-off in every run: {', '.join(result.zero)}")
    return "\n".join(lines + flag_lines(scope))
