"""feeder.chain.blas: a decorated function runs with one BLAS thread, and the caller's limits
come back on return (threadpoolctl's own report, read inside and after)."""

from __future__ import annotations

import numpy as np
import pytest
from threadpoolctl import threadpool_info, threadpool_limits

from feeder.chain.blas import one_blas_thread


def _blas_threads() -> list[int]:
    return [pool["num_threads"] for pool in threadpool_info() if pool["user_api"] == "blas"]


def test_one_blas_thread_inside_and_the_callers_limits_after():
    np.linalg.svd(np.ones((4, 3)))  # numpy's BLAS loaded
    if not _blas_threads():
        pytest.skip("no BLAS library that threadpoolctl can see")

    @one_blas_thread
    def inside() -> list[int]:
        """What it sees."""
        return _blas_threads()

    with threadpool_limits(limits=2, user_api="blas"):
        before = _blas_threads()
        assert inside() == [1] * len(before)
        assert _blas_threads() == before
    assert inside.__doc__ == "What it sees."  # functools.wraps: the docs keep the function's


def test_the_scan_of_the_libraries_is_kept_until_an_import(monkeypatch):
    """threadpoolctl's scan (~0.3–2 ms) is done again only after an import, which may have loaded
    another BLAS library: one made after a new entry in sys.modules is another."""
    import sys
    import types

    from feeder.chain import blas

    first = blas._controller()
    assert blas._controller() is first
    monkeypatch.setitem(sys.modules, "feeder_test_new_module", types.ModuleType("new"))
    assert blas._controller() is not first
