"""One BLAS thread for the small dense linear algebra of a mechanism's runs.

The chain's matrices are small (a closure Jacobian of 120 × 81 for an N-four-bar with N = 40, a
few dozen rows elsewhere). OpenBLAS splits even these over every core it sees; on a machine whose
cores other processes share, the threads wait for each other: one 120 × 81 SVD took 7–67 ms on
two threads against ~1 ms on one (issue 29), and a forward run of the N = 40 four-bar 5 × longer.
:func:`one_blas_thread` runs a function with every BLAS library loaded at that moment limited to
one thread (threadpoolctl), and restores the previous limits on return; a library loaded during
the call keeps its own setting until the next decorated call. Limiting costs ~0.6 ms a call, so it
wraps whole runs (a forward run, an inverse dynamics, a tracking), not per-sample kernels.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import ParamSpec, TypeVar

from threadpoolctl import threadpool_limits

P = ParamSpec("P")
R = TypeVar("R")


def one_blas_thread(function: Callable[P, R]) -> Callable[P, R]:
    """``function`` run with the loaded BLAS libraries limited to one thread (module docstring)."""

    @functools.wraps(function)
    def limited(*args: P.args, **kwargs: P.kwargs) -> R:
        with threadpool_limits(limits=1, user_api="blas"):
            return function(*args, **kwargs)

    return limited
