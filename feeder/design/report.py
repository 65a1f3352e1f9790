"""What ``feeder design optimize`` reports: ``optimum.csv`` (every peak, variable and
constraint before and after, the active constraints with their multipliers) and the summary.

``optimum.csv`` has the columns :data:`COLUMNS`, one row per:

* ``objective``: the objective [its unit], before (the device as given) and after;
* ``variable``: each free parameter [its unit], with its bounds; ``active`` is ``lower`` or
  ``upper`` where it ends on a bound;
* ``constraint``: each geometric constraint's margin [its unit] (≥ 0: met), and each limit's
  (the limit less the peak's largest magnitude; the limit under ``upper``); ``active`` 1 where
  SLSQP's multiplier is positive or the margin is within 1e-6 of its scale of zero;
  ``multiplier``: by how much the objective would fall per unit the constraint were relaxed
  [objective unit per constraint unit], from SLSQP's last QP;
* ``binding``: each case whose peak sets the objective at the optimum, with its multiplier
  (its share of the term's weight: the shares of a term add up to its weight);
* ``peak``: every peak of ``sweep_peaks.csv``, the signed value of largest magnitude over the
  elevations and cases [its unit], before and after.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..study.elevation_sweeps import UNITS
from ..study.sweep_table import QUANTITIES
from .objectives import Objective
from .problem import Evaluation, Problem
from .tables import cell, shown

COLUMNS = (
    "kind", "name", "unit", "before", "after", "change_percent", "lower", "upper", "active",
    "multiplier", "multiplier_unit", "meaning",
)  # fmt: skip

ACTIVE = 1e-6
"""A constraint whose scaled margin is below this [-] is active (SLSQP ends with its active
constraints met to ~1e-12)."""

INTERRUPTED = "interrupted: best so far"


@dataclass(frozen=True)
class Optimum:
    """A finished (or interrupted) optimisation.

    Attributes:
        status: ``converged``, ``not converged`` (SLSQP's message says why), ``no feasible
            point`` or :data:`INTERRUPTED`.
        messages: How each local search ended.
        problem: The problem (its variables, constraints, references and cycles).
        reference: The device as given.
        best: The optimum (its rows are those of the parameter file written); None when no
            point was feasible.
        multipliers: Constraint name → SLSQP's multiplier (scaled), when they belong to the
            optimum; else empty.
        seconds: Wall time [s].
    """

    status: str
    messages: tuple[str, ...]
    problem: Problem
    reference: Evaluation
    best: Evaluation | None
    multipliers: dict[str, float]
    seconds: float

    @property
    def objective(self) -> Objective:
        """The objective."""
        return self.problem.objective

    def value(self, e: Evaluation | None) -> float:
        """The objective at ``e`` [its unit] (NaN for None)."""
        return math.nan if e is None else self.problem.objective_value(e)


def change_percent(before: float, after: float) -> str:
    if before == 0.0 or not (math.isfinite(before) and math.isfinite(after)):
        return ""
    return repr(float(100.0 * (after - before) / abs(before)))


def signed_peak(e: Evaluation | None, quantity: str) -> float:
    """The signed value of largest magnitude of ``quantity`` over the cases [its unit]."""
    if e is None or e.failure:
        return math.nan
    values = np.array([float(row[quantity]) for row in e.rows])
    return float(values[int(np.argmax(np.abs(values)))])


def _multiplier_factor(opt: Optimum) -> float:
    """The objective's unit per scaled unit of the cost (module docstring of problem)."""
    return 1.0 if opt.objective.weighted else opt.problem.references[0]


def variable_rows(opt: Optimum) -> list[list[str]]:
    """The ``variable`` rows of ``optimum.csv`` (the device's and a mechanism's): each variable
    before and after [its unit], its bounds, and the bound it ends on."""
    rows, before, after = [], opt.reference, opt.best
    for k, v in enumerate(opt.problem.space.variables):
        end = math.nan if after is None else float(after.x[k])
        z = (end - v.lower) / (v.upper - v.lower)
        active = "lower" if z <= ACTIVE else "upper" if z >= 1.0 - ACTIVE else ""
        rows.append(["variable", v.name, v.unit, cell(before.x[k]), cell(end),
                     change_percent(before.x[k], end), cell(v.lower), cell(v.upper), active,
                     "", "", v.parameter.meaning])  # fmt: skip
    return rows


def optimum_rows(opt: Optimum) -> list[list[str]]:
    """``optimum.csv``: the header :data:`COLUMNS`, then its rows (module docstring)."""
    p, before, after = opt.problem, opt.reference, opt.best
    unit = opt.objective.unit
    rows = [list(COLUMNS)]
    value = (opt.value(before), opt.value(after))
    rows.append(["objective", opt.objective.text, unit, *map(cell, value), change_percent(*value),
                 "", "", "", "", "", " or ".join(opt.objective.quantities())])  # fmt: skip
    rows += variable_rows(opt)
    factor = _multiplier_factor(opt)
    for k, c in enumerate(p.geometry):
        margin = math.nan if after is None else float(after.margins[k])
        multiplier = opt.multipliers.get(c.name, math.nan) * factor / c.scale
        active = after is not None and (margin / c.scale <= ACTIVE or multiplier > 0.0)
        rows.append(["constraint", c.name, c.unit, cell(before.margins[k]), cell(margin),
                     "", "", "", str(int(active)), cell(multiplier), _per(unit, c.unit),
                     c.meaning])  # fmt: skip
    for q, limit in p.space.limits.items():
        margins = [limit - abs(signed_peak(e, q)) for e in (before, after)]
        shares = [m for n, m in opt.multipliers.items() if n.startswith(f"limit:{q}@")]
        multiplier = sum(shares) * factor / limit if shares else math.nan
        active = after is not None and (margins[1] / limit <= ACTIVE or multiplier > 0.0)
        rows.append(["constraint", f"limit:{q}", UNITS[q], *map(cell, margins), "", "",
                     cell(limit), str(int(active)), cell(multiplier), _per(unit, UNITS[q]),
                     f"peak {q} ≤ {limit:g} {UNITS[q]}"])  # fmt: skip
    for name, (quantity, case, share) in binding(opt).items():
        peaks = [_case_peak(e, quantity, case) for e in (before, after)]
        rows.append(["binding", name, UNITS[quantity], *map(cell, peaks), change_percent(*peaks),
                     "", "", "1", cell(share), "-", "sets the objective"])  # fmt: skip
    for q in QUANTITIES:
        peaks = [signed_peak(e, q) for e in (before, after)]
        rows.append(["peak", q, UNITS[q], *map(cell, peaks), change_percent(*peaks),
                     "", "", "", "", "", ""])  # fmt: skip
    return rows


def _per(unit: str, other: str) -> str:
    return f"{unit or '-'} per {other}"


def _case_peak(e: Evaluation | None, quantity: str, case: int) -> float:
    return math.nan if e is None or e.failure else abs(float(e.rows[case][quantity]))


def binding(opt: Optimum) -> dict[str, tuple[str, int, float]]:
    """The cases whose epigraph constraint has a positive multiplier: ``q at variant, ε`` →
    (quantity, case index, multiplier)."""
    keys = opt.problem.scope.keys()
    found = {}
    for name, multiplier in opt.multipliers.items():
        if not name.startswith("peak:") or not multiplier > 0.0:
            continue
        _, _, rest = name.partition(":")
        _, _, rest = rest.partition(":")
        quantity, _, where = rest.partition("@")
        variant, _, elevation = where.rpartition(",")
        case = keys.index((variant, float(elevation)))
        found[f"{quantity} at {variant}, {float(elevation):g}°"] = (quantity, case, multiplier)
    return found


def result_lines(rows: list[list[str]]) -> list[str]:
    """The summary's lines of the rows of ``optimum.csv`` (the device's and a mechanism's): the
    variables before → after, the active constraints with their multipliers, the binding
    cases."""
    lines = ["Variables:"]
    for row in (r for r in rows if r[0] == "variable"):
        bound = f" (at its {row[8]} bound)" if row[8] else ""
        end = f"{float(row[4]):.6g}" if row[4] else "–"
        lines.append(f"  {row[1]} = {float(row[3]):.6g} → {end} {row[2]}{bound}")
    active = [r for r in rows if r[0] == "constraint" and r[8] == "1"]
    lines.append(
        "Active constraints (multiplier: the objective's fall per unit the constraint were "
        "relaxed):"
        if active
        else "Active constraints: none"
    )
    for row in active:
        multiplier = f"{float(row[9]):.4g} {row[10]}" if row[9] else "no multiplier"
        lines.append(f"  {row[1]} ({row[11]}): margin {float(row[4]):.3g} {row[2]}, {multiplier}")
    for row in (r for r in rows if r[0] == "binding"):
        lines.append(f"  binding case: {row[1]}, multiplier {float(row[9]):.4g}")
    return lines


def summary(opt: Optimum, elevations: str) -> str:
    """The summary printed and written to ``summary.txt``."""
    p = opt.problem
    before, after = opt.value(opt.reference), opt.value(opt.best)
    unit = opt.objective.unit
    terms = ", ".join(f"{t.name} ({' or '.join(t.quantities)})" for t in opt.objective.terms)
    cases = len(p.scope.variants)
    lines = [
        f"status: {opt.status}",
        f"Minimise {opt.objective.text}: {terms}, over {elevations}, "
        f"{cases} vehicle case{'s' if cases > 1 else ''}, at {p.scope.spec.rate:g} Hz.",
        f"Objective: {shown(before, unit, '.6g')} (the device as given) → "
        f"{shown(after, unit, '.6g')}"
        + (
            f" ({100.0 * (after - before) / before:+.2f} %)".replace("-", "−")
            if math.isfinite(after)
            else ""
        ),
    ]
    rows = optimum_rows(opt)[1:]
    lines += result_lines(rows)
    lines += [*opt.messages]
    lines.append(f"{len(p.space.variables)} variables, {p.cycles} cycles in {opt.seconds:.1f} s.")
    return "\n".join(lines)
