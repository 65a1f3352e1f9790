"""Designing the device's geometry: how much each peak load changes per unit of each length and
mass (``feeder design sensitivities``), and the free geometry that minimises a peak within
bounds and constraints (``feeder design optimize``).

Sensitivities:

* :mod:`~feeder.design.differentiable` — which parameters are differentiated, and the
  parameter set with one of them changed;
* :mod:`~feeder.design.differences` — central differences with a step chosen and checked, and
  the kink test;
* :mod:`~feeder.design.evaluations` — the cycles to run, on every core or a Dask cluster;
* :mod:`~feeder.design.sensitivities` — the derivatives and elasticities of every peak, at one
  elevation and as the envelope over a range;
* :mod:`~feeder.design.tables`, :mod:`~feeder.design.figure`, :mod:`~feeder.design.outputs` —
  the tables, the summary, the heat map and the output folder.

Optimisation:

* :mod:`~feeder.design.design_space` — the design file: free parameters, bounds, fixed ones,
  the constraints' settings, limits on other peaks;
* :mod:`~feeder.design.objectives` — what is minimised (``--objective``);
* :mod:`~feeder.design.constraints`, :mod:`~feeder.design.feasibility` — the geometric
  constraints in closed form, and points that meet them found without a cycle;
* :mod:`~feeder.design.problem` — the problem in SLSQP's form and the cycles it runs;
* :mod:`~feeder.design.search`, :mod:`~feeder.design.history` — the global start and SLSQP,
  and the convergence history that a resumed run continues;
* :mod:`~feeder.design.report`, :mod:`~feeder.design.optimum_figure`,
  :mod:`~feeder.design.optimize` — ``optimum.csv``, the summary, the figure and the output
  folder.

Any mechanism (``feeder design sensitivities|optimize MODEL --closures F --design D --motion
M``): :mod:`feeder.design.mechanism`, a client of the same differences, epigraph form, search,
history, tables and heat map.

The names below load on first use, so that ``feeder design sensitivities`` does not import the
optimisation's SciPy modules (``scipy.optimize``, ``scipy.stats``), nor the command line's
parser either of the commands.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..lazy import lazy_names

if TYPE_CHECKING:  # the names for type checkers; at run time they load on first use
    from .design_space import BUILT_IN, DesignSpace, read_design
    from .differentiable import DesignParameter, design_parameters
    from .mechanism.design_file import MechanismDesign, read_mechanism_design
    from .mechanism.optimize import run_mechanism_optimization
    from .mechanism.outputs import run_mechanism_sensitivities
    from .mechanism.sensitivities import MechanismSensitivities, mechanism_sensitivities
    from .objectives import Objective, parse_objective
    from .optimize import run_optimization
    from .outputs import run_sensitivities
    from .report import Optimum
    from .sensitivities import Sensitivities, Sensitivity, design_sensitivities

_SOURCES = {
    "BUILT_IN": ".design_space",
    "DesignSpace": ".design_space",
    "read_design": ".design_space",
    "DesignParameter": ".differentiable",
    "design_parameters": ".differentiable",
    "MechanismDesign": ".mechanism.design_file",
    "read_mechanism_design": ".mechanism.design_file",
    "run_mechanism_optimization": ".mechanism.optimize",
    "run_mechanism_sensitivities": ".mechanism.outputs",
    "MechanismSensitivities": ".mechanism.sensitivities",
    "mechanism_sensitivities": ".mechanism.sensitivities",
    "Objective": ".objectives",
    "parse_objective": ".objectives",
    "run_optimization": ".optimize",
    "run_sensitivities": ".outputs",
    "Optimum": ".report",
    "Sensitivities": ".sensitivities",
    "Sensitivity": ".sensitivities",
    "design_sensitivities": ".sensitivities",
}
"""Public name → the module that defines it."""

__all__ = [
    "BUILT_IN",
    "DesignParameter",
    "DesignSpace",
    "MechanismDesign",
    "MechanismSensitivities",
    "Objective",
    "Optimum",
    "Sensitivities",
    "Sensitivity",
    "design_parameters",
    "design_sensitivities",
    "mechanism_sensitivities",
    "parse_objective",
    "read_design",
    "read_mechanism_design",
    "run_mechanism_optimization",
    "run_mechanism_sensitivities",
    "run_optimization",
    "run_sensitivities",
]


__getattr__, __dir__ = lazy_names(__name__, _SOURCES, __all__)
