"""The tables and the summary of a sensitivity study (:mod:`feeder.design.sensitivities`).

* ``sensitivities.csv`` (:func:`wide_rows`): one row per scope and peak: ``scope``, ``peak``,
  ``unit``, ``value``, ``elevation_deg``, ``time_s``, then ``d_<parameter>`` for every
  parameter (the derivative, in the peak's unit per the parameter's: N/m, Pa/kg, …), then
  ``elasticity_<parameter>`` (percent of the peak per percent of the parameter). An empty cell:
  unavailable (the details say why), or an elasticity of a zero peak.
* ``sensitivity_details.csv`` (:func:`detail_rows`): one row per scope, peak and parameter, with
  the step, the error estimate, the one-sided differences, the kink test and the reason.

Numbers are written as Python's ``repr`` of the float (the shortest text that reads back as the
same float), in SI units.
"""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path

from ..files import write_text
from ..viz.catalog import display_unit, words
from .sensitivities import Scope, Sensitivities, Sensitivity

DETAIL_COLUMNS = (
    "scope",
    "peak",
    "unit",
    "parameter",
    "parameter_unit",
    "parameter_value",
    "step",
    "derivative",
    "derivative_unit",
    "error",
    "elasticity",
    "forward",
    "backward",
    "residual",
    "status",
    "moved",
    "reason",
)
"""The columns of ``sensitivity_details.csv`` (docs/REFERENCE.md explains each)."""

SUMMARY_TOP = 5
"""Elasticities the summary lists per peak, largest magnitude first."""


def cell(value: float | None) -> str:
    """A number as a table's cell: the float's ``repr``; empty when missing or not finite."""
    return "" if value is None or not math.isfinite(value) else repr(float(value))


def wide_rows(result: Sensitivities) -> list[list[str]]:
    """``sensitivities.csv``: the header, then one row per scope and peak (module docstring)."""
    names = [p.name for p in result.parameters]
    header = ["scope", "peak", "unit", "value", "elevation_deg", "time_s"]
    rows = [header + [f"d_{n}" for n in names] + [f"elasticity_{n}" for n in names]]
    for scope in result.scopes:
        for peak in scope.peaks:
            entries = [scope.entries[(peak.name, n)] for n in names]
            rows.append(
                [scope.name, peak.name, peak.unit, cell(peak.value)]
                + [cell(peak.elevation_deg), cell(peak.time)]
                + [cell(e.derivative) for e in entries]
                + [cell(e.elasticity) for e in entries]
            )
    return rows


def detail_rows(result: Sensitivities) -> list[list[str]]:
    """``sensitivity_details.csv``: the header :data:`DETAIL_COLUMNS`, then one row per scope,
    peak and parameter."""
    rows = [list(DETAIL_COLUMNS)]
    for scope in result.scopes:
        for peak in scope.peaks:
            for parameter in result.parameters:
                e = scope.entries[(peak.name, parameter.name)]
                found = e.estimate
                rows.append(
                    [scope.name, peak.name, peak.unit, parameter.name, parameter.unit]
                    + [cell(e.value), cell(e.h), cell(e.derivative)]
                    + [f"{peak.unit}/{parameter.unit}", cell(found and found.error)]
                    + [cell(e.elasticity), cell(found and found.forward)]
                    + [cell(found and found.backward), cell(found and found.residual)]
                    + [e.status, e.moved, e.reason]
                )
    return rows


def write_rows(path: str | Path, rows: list[list[str]]) -> Path:
    """Write rows of text as CSV (quoted where a cell holds a comma), atomically."""
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="\n").writerows(rows)
    return write_text(path, buffer.getvalue())


def _count(count: int, one: str, many: str) -> str:
    return f"{count} {one if count == 1 else many}"


def _signed(value: float, form: str) -> str:
    """``value`` formatted with a true minus sign (−1.32, not -1.32), as the figures write it."""
    return format(value, form).replace("-", "−")


def shown(value: float, unit: str, form: str = ".4g") -> str:
    """A value [SI ``unit``] as the summaries print it: in the unit figures show, formatted by
    ``form``, with a true minus sign; "–" when not finite."""
    if not math.isfinite(value):
        return "–"
    factor, unit_shown = display_unit(unit)
    return f"{_signed(value * factor, form)} {unit_shown}".rstrip()


def top_elasticities(scope: Scope, peak: str, names: list[str]) -> str:
    entries = [scope.entries[(peak, n)] for n in names]
    ranked = sorted(
        (e for e in entries if math.isfinite(e.elasticity)), key=lambda e: -abs(e.elasticity)
    )
    if not ranked:
        return "no elasticity (the peak is zero, or no derivative is available)"
    mark = {"ok": "", "kink": "*"}
    return ", ".join(
        f"{e.parameter.name} {_signed(e.elasticity, '+.3f')}{mark[e.status]}"
        for e in ranked[:SUMMARY_TOP]
    )


def summary(result: Sensitivities) -> str:
    """The summary printed and written to ``summary.txt``: what was run, then per scope each
    peak with its largest elasticities, the kinks, the moved argmaxes, the unavailable ones."""
    names = [p.name for p in result.parameters]
    lengths = sum(p.unit == "m" for p in result.parameters)
    errors = [
        (e.estimate.error * max(abs(e.value), e.parameter.scale) / abs(e.peak.value), e)
        for scope in result.scopes
        for e in scope.entries.values()
        if e.status == "ok" and e.peak.value != 0.0
    ]
    lines = [
        f"Sensitivities of the {result.device} feeder's peaks to {len(names)} parameters "
        f"({_count(lengths, 'length', 'lengths')}, "
        f"{_count(len(names) - lengths, 'mass', 'masses')}): {result.cycles} cycles at "
        f"{result.spec.rate:g} Hz in {result.seconds:.1f} s.",
        f"Step h = {result.factor:.3g} · max(|p|, 0.1 m or 1 kg), derivative over h/2, error "
        "estimate |D(h) − D(h/2)|.",
    ]
    if errors:
        worst, entry = max(errors, key=lambda pair: pair[0])
        lines.append(
            f"Largest error estimate {worst:.1e} in elasticity units (% per %: the error times "
            f"max(|p|, scale) over the peak; {entry.peak.name}, {entry.parameter.name})."
        )
    for scope in result.scopes:
        lines += ["", f"{scope.title}: largest elasticities [% of the peak per % of parameter]"]
        width = max(len(words(p.name)) for p in scope.peaks)
        for peak in scope.peaks:
            where = (
                f"ε = {_signed(peak.elevation_deg, 'g')}°, " if scope.name == "envelope" else ""
            )
            lines.append(
                f"  {words(peak.name):<{width}}  {shown(peak.value, peak.unit)} "
                f"({where}t = {peak.time:g} s): {top_elasticities(scope, peak.name, names)}"
            )
        lines += flag_lines(scope)
    return "\n".join(lines)


def flag_lines(scope: Scope) -> list[str]:
    entries = list(scope.entries.values())
    kinks = [e for e in entries if e.status == "kink"]
    moved = [e for e in entries if e.moved and e.status == "ok"]
    missing = [e for e in entries if e.status == "unavailable"]
    lines = []
    if kinks:
        lines.append(
            f"  * kink: not differentiable within the step ({len(kinks)}; "
            "sensitivity_details.csv gives the one-sided derivatives): " + _pairs(kinks)
        )
    if moved:
        lines.append(
            f"  argmax moved within the step, one-sided derivatives agree ({len(moved)}): "
            + _pairs(moved)
        )
    reasons = {e.parameter.name: e.reason for e in missing}
    for name, reason in reasons.items():
        lines.append(f"  unavailable: {name}: {reason}")
    if not (kinks or moved or missing):
        lines.append("  every derivative smooth within its step: no kink, no argmax moved")
    return lines


def _pairs(entries: list[Sensitivity], most: int = 6) -> str:
    text = ", ".join(
        f"{e.peak.name}/{e.parameter.name}" + (f" ({e.moved} moved)" if e.moved else "")
        for e in entries[:most]
    )
    return text + (", …" if len(entries) > most else "")
