"""The paper's hand-derived equations: an independent cross-check of the Pinocchio pipeline.

Depends on the device's parameters and numpy only, never on Pinocchio or the pipeline
(tests/test_layers.py checks it): :mod:`~feeder.paper.bodies` (eqs. 30–39),
:mod:`~feeder.paper.lagrange` (the corrected Lagrange equations, eqs. 40–47),
:mod:`~feeder.paper.coriolis` (the Kronecker-product Coriolis matrix, eq. 27),
:mod:`~feeder.paper.printed` (the equations as printed) and :mod:`~feeder.paper.errata` (what
differs, and by how much).
"""

from .coriolis import christoffel_coriolis, kronecker_coriolis
from .errata import ReferenceMotion, errata_markdown, errata_rows
from .lagrange import LagrangeLoads, lagrange_loads, mass_matrix
from .printed import PrintedEquations, printed_equations

__all__ = [
    "LagrangeLoads",
    "PrintedEquations",
    "ReferenceMotion",
    "christoffel_coriolis",
    "errata_markdown",
    "errata_rows",
    "lagrange_loads",
    "kronecker_coriolis",
    "mass_matrix",
    "printed_equations",
]
