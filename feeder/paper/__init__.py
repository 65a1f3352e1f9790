"""The paper's hand-derived equations: an independent cross-check of the Pinocchio pipeline.

Depends on the device's parameters and numpy only, never on Pinocchio or the pipeline
(tests/test_layers.py checks it): :mod:`~feeder.paper.bodies` (eqs. 30–39),
:mod:`~feeder.paper.lagrange` (the corrected Lagrange equations, eqs. 40–47),
:mod:`~feeder.paper.coriolis` (the Kronecker-product Coriolis matrix, eq. 27),
:mod:`~feeder.paper.printed` (the equations as printed) and :mod:`~feeder.paper.errata` (what
differs, and by how much).
"""

from typing import TYPE_CHECKING

from ..lazy import lazy_names

# Bound here, not on first use: once the submodule ``errata_rows`` is imported (by any module),
# the package's attribute ``errata_rows`` would be that module, and __getattr__ never asked.
from .errata import errata_rows

if TYPE_CHECKING:  # the names for type checkers; at run time they load on first use
    from .coriolis import christoffel_coriolis, kronecker_coriolis
    from .errata import ReferenceMotion, errata_markdown
    from .lagrange import LagrangeLoads, lagrange_loads, mass_matrix
    from .printed import PrintedEquations, printed_equations

_SOURCES = {
    "LagrangeLoads": ".lagrange",
    "PrintedEquations": ".printed",
    "ReferenceMotion": ".errata",
    "christoffel_coriolis": ".coriolis",
    "errata_markdown": ".errata",
    "kronecker_coriolis": ".coriolis",
    "lagrange_loads": ".lagrange",
    "mass_matrix": ".lagrange",
    "printed_equations": ".printed",
}
"""Public name → the module that defines it."""

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


__getattr__, __dir__ = lazy_names(__name__, _SOURCES, __all__)
