"""One BLAS thread for the small dense linear algebra of a mechanism's runs.

The chain's matrices are small (a closure Jacobian of 120 × 81 for an N-four-bar with N = 40, a
few dozen rows elsewhere). OpenBLAS splits even these over every core it sees; on a machine whose
cores other processes share, the threads wait for each other: one 120 × 81 SVD took 7–67 ms on
two threads against ~1 ms on one (issue 29), and a forward run of the N = 40 four-bar 5 × longer.
:func:`one_blas_thread` runs a function with every BLAS library loaded at that moment limited to
one thread (threadpoolctl), and restores the previous limits on return; a library loaded during
the call keeps its own setting until the next decorated call. Finding the loaded libraries costs
~0.3–2 ms (threadpoolctl scans the process's shared objects), which the N-four-bar's inverse
dynamics at N = 2 spend in ~0.5 ms of mechanics: the scan is kept (:func:`_controller`) and
redone only after an import (a new library comes with a new module), so that a call costs ~5 µs
and the decorator still wraps whole runs (a forward run, an inverse dynamics, a tracking), not
per-sample kernels.
"""

from __future__ import annotations

import functools
import sys
from collections.abc import Callable
from typing import ParamSpec, TypeVar

from threadpoolctl import ThreadpoolController

P = ParamSpec("P")
R = TypeVar("R")


_scanned: list[tuple[int, ThreadpoolController]] = []
"""The last scan of the loaded libraries, with the number of modules imported at its time."""


def _controller() -> ThreadpoolController:
    """threadpoolctl's view of the BLAS libraries loaded now, scanned again only when a module
    has been imported since the last scan (module docstring)."""
    modules = len(sys.modules)
    if not _scanned or _scanned[0][0] != modules:
        _scanned[:] = [(modules, ThreadpoolController())]
    return _scanned[0][1]


def one_blas_thread(function: Callable[P, R]) -> Callable[P, R]:
    """``function`` run with the loaded BLAS libraries limited to one thread (module docstring)."""

    @functools.wraps(function)
    def limited(*args: P.args, **kwargs: P.kwargs) -> R:
        with _controller().limit(limits=1, user_api="blas"):
            return function(*args, **kwargs)

    return limited
