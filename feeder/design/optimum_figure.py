"""The figure of ``feeder design optimize`` (``optimum.png``): each objective term's peak
against elevation, the device as given (dashed) and the optimum (solid), one curve per vehicle
case, after the house conventions of :mod:`feeder.viz.figures`."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from ..viz.axes import panel_title
from ..viz.catalog import display_unit
from ..viz.figures import finish
from .problem import Evaluation
from .report import Optimum

PANEL = (6.5, 3.2)
"""Width and height [in] of a panel."""


def term_curves(opt: Optimum, e: Evaluation, term: int) -> dict[str, np.ndarray]:
    """Vehicle case → the term's peak at each elevation [its unit], (K,): the largest magnitude
    over the term's quantities."""
    p = opt.problem
    quantities = p.objective.terms[term].quantities
    keys = p.scope.keys()
    curves = {}
    for variant in p.scope.variants:
        cases = [k for k, (name, _) in enumerate(keys) if name == variant.name]
        curves[variant.name] = np.array(
            [max(abs(float(e.rows[k][q])) for q in quantities) for k in cases]
        )
    return curves


def optimum_figure(opt: Optimum) -> Figure:
    """Each term's peak against elevation, before and after (module docstring)."""
    p = opt.problem
    terms = p.objective.terms
    fig = Figure(figsize=(PANEL[0], PANEL[1] * len(terms)))
    axes = np.atleast_1d(fig.subplots(len(terms), 1, squeeze=False).ravel())
    elevations = np.array(p.scope.elevations_deg)
    colours = [f"C{k}" for k in range(len(p.scope.variants))]
    device = p.space.device.name
    for j, (ax, term) in enumerate(zip(axes, terms, strict=True)):
        factor, unit = display_unit(term.unit)
        shown = [("as given", opt.reference, "--")]
        if opt.best is not None:
            shown.append(("optimum", opt.best, "-"))
        for label, e, style in shown:
            curves = term_curves(opt, e, j).items()
            for colour, (variant, values) in zip(colours, curves, strict=True):
                case = f", {variant}" if len(p.scope.variants) > 1 else ""
                ax.plot(elevations, values * factor, style, color=colour, marker=".",
                        markersize=3, label=f"{label}{case}")  # fmt: skip
        ax.set_xlabel("elevation ε [deg]")
        ax.set_ylabel(f"peak [{unit}]")
        quantities = " or ".join(q.replace("_", " ") for q in term.quantities)
        panel_title(ax, f"{device} feeder: {term.name} ({quantities})", fontsize=10)
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    fig.suptitle(objective_title(opt, p.objective.unit), fontsize=9)
    finish(fig, left=0.9, right=0.2, bottom=0.6, top=0.75, hspace=0.9)
    return fig


def objective_title(opt: Optimum, unit: str) -> str:
    """The figure's title: the objective as given → at the optimum [``unit``, SI], and the run's
    status."""
    p = opt.problem
    before, after = opt.value(opt.reference), opt.value(opt.best)
    factor, unit = display_unit(unit)
    change = f" → {after * factor:.4g} {unit} ({100.0 * (after - before) / before:+.1f} %)"
    title = f"{p.objective.text}: {before * factor:.4g} {unit}" + (change if opt.best else "")
    return f"{title}; {opt.status}".replace("-", "−")
