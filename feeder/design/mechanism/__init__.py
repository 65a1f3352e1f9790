"""Designing any mechanism: the sensitivities of its peak loads to the design variables of a
design file, and the variables that minimise a peak (``feeder design sensitivities|optimize
MODEL --closures F --design D --motion M``).

* :mod:`~feeder.design.mechanism.design_file` — the design file: variables, bounds, objective,
  constraints, the search's settings;
* :mod:`~feeder.design.mechanism.urdf_edit` — the URDF with the variables set;
* :mod:`~feeder.design.mechanism.evaluation` — a point run as ``feeder analyze`` runs it;
* :mod:`~feeder.design.mechanism.inputs` — the inputs checked before any folder is made;
* :mod:`~feeder.design.mechanism.sensitivities`, :mod:`~feeder.design.mechanism.outputs` — the
  sensitivities and their files;
* :mod:`~feeder.design.mechanism.problem` — the problem in SLSQP's epigraph form;
* :mod:`~feeder.design.mechanism.report`, :mod:`~feeder.design.mechanism.figure`,
  :mod:`~feeder.design.mechanism.optimize` — the optimisation's files.

The device's modules supply what the two share: the differences and their check, the epigraph
form, the search and its history, the tables and the heat map. The names below load on first
use, as :mod:`feeder.design`'s do.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # the names for type checkers; at run time they load on first use
    from .design_file import MechanismDesign, read_mechanism_design
    from .optimize import run_mechanism_optimization
    from .outputs import run_mechanism_sensitivities
    from .sensitivities import MechanismSensitivities, mechanism_sensitivities

_SOURCES = {
    "MechanismDesign": ".design_file",
    "read_mechanism_design": ".design_file",
    "run_mechanism_optimization": ".optimize",
    "run_mechanism_sensitivities": ".outputs",
    "MechanismSensitivities": ".sensitivities",
    "mechanism_sensitivities": ".sensitivities",
}
"""Public name → the module that defines it."""

__all__ = [
    "MechanismDesign",
    "MechanismSensitivities",
    "mechanism_sensitivities",
    "read_mechanism_design",
    "run_mechanism_optimization",
    "run_mechanism_sensitivities",
]


def __getattr__(name: str):
    """Import a public name on first use (PEP 562) and keep it."""
    if name not in _SOURCES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(_SOURCES[name], __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
