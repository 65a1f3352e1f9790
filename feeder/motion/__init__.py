"""The motion: the feeding cycle's timing and rest-to-rest laws, the sampled cycle (closed loop
and payload path) and the payload's workspace (paper Figs. 4, 7, 8, 10)."""

import importlib
from typing import TYPE_CHECKING

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


def __getattr__(name: str):
    if name not in _SOURCES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(_SOURCES[name], __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
