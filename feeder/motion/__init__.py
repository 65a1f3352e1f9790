"""The motion: the feeding cycle's timing and rest-to-rest laws, the sampled cycle (closed loop
and payload path) and the payload's workspace (paper Figs. 4, 7, 8, 10)."""

from typing import TYPE_CHECKING

from ..lazy import lazy_names

# Bound here, not on first use: once the submodule ``workspace`` is imported (by any module),
# the package's attribute ``workspace`` would be that module, and __getattr__ never asked.
from .workspace import workspace

if TYPE_CHECKING:  # the names for type checkers; at run time they load on first use
    from .cycle import CycleKinematics, feeding_cycle
    from .laws import CycleSpec
    from .workspace import Workspace

_SOURCES = {
    "CycleKinematics": ".cycle",
    "CycleSpec": ".laws",
    "Workspace": ".workspace",
    "feeding_cycle": ".cycle",
}
"""Public name → the module that defines it."""

__all__ = ["CycleKinematics", "CycleSpec", "Workspace", "feeding_cycle", "workspace"]


__getattr__, __dir__ = lazy_names(__name__, _SOURCES, __all__)
