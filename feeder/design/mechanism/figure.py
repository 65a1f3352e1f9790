"""The figure of a mechanism's optimisation (``optimum.png``): each objective term's quantity
along every motion table, the model as given (dashed) and the optimum (solid), after the house
conventions of :mod:`feeder.viz.figures`."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from ...viz.axes import panel_title
from ...viz.catalog import display_unit
from ...viz.figures import finish
from ..optimum_figure import objective_title
from ..report import Optimum

PANEL = (6.5, 3.2)
"""Width and height [in] of a panel."""


def mechanism_optimum_figure(opt: Optimum) -> Figure:
    """Each term's quantity against time, before and after (module docstring)."""
    p = opt.problem
    quantities = list(p.objective.quantities())
    fig = Figure(figsize=(PANEL[0], PANEL[1] * len(quantities)))
    axes = np.atleast_1d(fig.subplots(len(quantities), 1, squeeze=False).ravel())
    shown = [("as given", opt.reference, "--")]
    if opt.best is not None:
        shown.append(("optimum", opt.best, "-"))
    for ax, quantity in zip(axes, quantities, strict=True):
        factor, unit = display_unit(opt.reference.run.units[quantity])
        for label, e, style in shown:
            run = e.run
            for m, (t, values) in enumerate(zip(run.times, run.series[quantity], strict=True)):
                table = f", {p.tables[m]}" if len(p.tables) > 1 else ""
                ax.plot(t, values * factor, style, color=f"C{m}", label=f"{label}{table}")
        ax.set_xlabel("time t [s]")
        ax.set_ylabel(f"{quantity.replace('_', ' ')} [{unit}]")
        panel_title(ax, f"{p.mechanism.model.stem}: {quantity}", fontsize=10)
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    terms = p.objective.terms
    unit = "" if p.objective.weighted else opt.reference.run.units[terms[0].quantities[0]]
    fig.suptitle(objective_title(opt, unit), fontsize=9)
    finish(fig, left=0.9, right=0.2, bottom=0.6, top=0.75, hspace=0.9)
    return fig
