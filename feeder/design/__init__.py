"""Designing the device's geometry: how much each peak load changes per unit of each length and
mass (``feeder design sensitivities``).

* :mod:`~feeder.design.differentiable` — which parameters are differentiated, and the
  parameter set with one of them changed;
* :mod:`~feeder.design.differences` — central differences with a step chosen and checked, and
  the kink test;
* :mod:`~feeder.design.evaluations` — the cycles to run, on every core or a Dask cluster;
* :mod:`~feeder.design.sensitivities` — the derivatives and elasticities of every peak, at one
  elevation and as the envelope over a range;
* :mod:`~feeder.design.tables`, :mod:`~feeder.design.figure`, :mod:`~feeder.design.outputs` —
  the tables, the summary, the heat map and the output folder.
"""

from .differentiable import DesignParameter, design_parameters
from .outputs import run_sensitivities
from .sensitivities import Sensitivities, Sensitivity, design_sensitivities

__all__ = [
    "DesignParameter",
    "Sensitivities",
    "Sensitivity",
    "design_parameters",
    "design_sensitivities",
    "run_sensitivities",
]
