"""What ``feeder design optimize MODEL --design FILE`` reports for a mechanism: ``optimum.csv``
and the summary, in the device's columns (:data:`feeder.design.report.COLUMNS`), one row per:

* ``objective``: the objective [its unit], before (the model as given, the variables' starts)
  and after (the written model, run as ``feeder analyze`` runs it);
* ``variable``: each design variable [its unit], with its bounds; ``active`` is ``lower`` or
  ``upper`` where it ends on a bound;
* ``constraint``: each constraint's least margin over the samples [its unit] (≥ 0: met;
  stroke ends, the velocity gain, the limits); ``active`` 1 where its multiplier is positive
  or its scaled margin is below 1e-6; ``multiplier``: the objective's fall per unit the
  constraint were relaxed [objective unit per constraint unit], from SLSQP's last QP;
* ``binding``: each sample (a table and a time) whose value sets the objective at the
  optimum, with its multiplier (the shares of a term add up to its weight);
* ``peak``: every peak, the value of largest magnitude over every table [its unit].
"""

from __future__ import annotations

import math

import numpy as np

from ..report import ACTIVE, COLUMNS, Optimum, change_percent, result_lines, variable_rows
from ..tables import cell, shown


def _unit(opt: Optimum) -> str:
    """The objective's unit: its peak's, or "" for a weighted sum."""
    e = opt.reference
    return "" if opt.objective.weighted else e.run.units[opt.objective.terms[0].quantities[0]]


def _factor(opt: Optimum) -> float:
    return 1.0 if opt.objective.weighted else opt.problem.references[0]


def _least(e, name: str, margins) -> float:
    if e is None:
        return math.nan
    return next(float(m.min()) for n, _, m, _, _ in margins if n == name)


def optimum_rows(opt: Optimum) -> list[list[str]]:
    """``optimum.csv``: the header, then its rows (module docstring)."""
    p, before, after = opt.problem, opt.reference, opt.best
    unit = _unit(opt)
    rows = [list(COLUMNS)]
    value = (opt.value(before), opt.value(after))
    rows.append(["objective", opt.objective.text, unit, *map(cell, value),
                 change_percent(*value), "", "", "", "", "",
                 " + ".join(t.name for t in opt.objective.terms)])  # fmt: skip
    rows += variable_rows(opt)
    margins_before = p.margins(before)
    margins_after = None if after is None else p.margins(after)
    for name, c_unit, _, scale, meaning in margins_before:
        last = _least(after, name, margins_after)
        shares = [m for n, m in opt.multipliers.items() if n.startswith(f"{name}@")]
        multiplier = sum(shares) * _factor(opt) / scale if shares else math.nan
        active = after is not None and (last / scale <= ACTIVE or multiplier > 0.0)
        rows.append(["constraint", name, c_unit, cell(_least(before, name, margins_before)),
                     cell(last), "", "", "", str(int(active)), cell(multiplier),
                     f"{unit or '-'} per {c_unit}", meaning])  # fmt: skip
    cases = p.case_labels() if opt.multipliers else []
    for name, multiplier in opt.multipliers.items():
        if name.startswith("peak:") and multiplier > 0.0:
            quantity, _, case = name.split(":", 2)[2].partition("@")
            k = cases.index(case)
            table, _, sample = case.partition("#")
            time_s = float(np.concatenate(after.run.times)[k])
            peaks = [
                math.nan if e is None else float(e.peaks(quantity)[k]) for e in (before, after)
            ]
            rows.append(["binding", f"{quantity} in {table} at t = {time_s:g} s (sample {sample})",
                         before.run.units[quantity], *map(cell, peaks), change_percent(*peaks),
                         "", "", "1", cell(multiplier), "-", "sets the objective"])  # fmt: skip
    for q, q_unit in before.run.units.items():
        peaks = [math.nan if e is None else e.run.signed_peak(q)[0] for e in (before, after)]
        rows.append(["peak", q, q_unit, *map(cell, peaks), change_percent(*peaks),
                     "", "", "", "", "", ""])  # fmt: skip
    return rows


def summary(opt: Optimum, written: str) -> str:
    """The summary printed and written to ``summary.txt``; ``written`` names the model files."""
    p = opt.problem
    before, after = opt.value(opt.reference), opt.value(opt.best)
    unit = _unit(opt)
    change = f" ({100.0 * (after - before) / before:+.2f} %)".replace("-", "−")
    lines = [
        f"status: {opt.status}",
        f"Minimise {opt.objective.text} (the largest |value| over the samples of "
        f"{', '.join(p.tables)}) of the {p.mechanism.model.stem} mechanism.",
        f"Objective: {shown(before, unit, '.6g')} ({p.given}) → {shown(after, unit, '.6g')}"
        + (change if math.isfinite(after) else ""),
    ]
    lines += result_lines(optimum_rows(opt)[1:])
    lines += [*opt.messages]
    if written:
        lines.append(f"The optimum as a model: {written} (its peaks above are feeder analyze's).")
    lines.append(f"{len(p.space.variables)} variables, {p.cycles} runs in {opt.seconds:.1f} s.")
    return "\n".join(lines)
