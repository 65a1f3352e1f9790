"""benchmarks/bench_chain.py runs the slider-crank's whole analysis on the batched continuation
(a smoke test at 100 samples: its figures are the benchmark's to report, not asserted here, as
CI's cores may be busy)."""

from __future__ import annotations

import importlib.util

import numpy as np

from feeder.chain import Closure

from ..conftest import REPO


def test_the_benchmark_runs_the_slider_crank_on_the_batched_path(capsys):
    spec = importlib.util.spec_from_file_location(
        "bench_chain", REPO / "benchmarks" / "bench_chain.py"
    )
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    cut = Closure("rod_tip", "slider_pin", "revolute")
    figures = bench.measure_analysis("slider-crank", *bench.crank_turn("slider_crank", cut, 100))
    assert figures["batched"]
    assert figures["call_us"] > 0.0 and figures["analysis_calls"] > figures["track_calls"] > 0.0
    assert "track, batched" in capsys.readouterr().out


def test_the_benchmark_times_the_n_four_bar_with_its_indeterminacy(capsys):
    """A smoke test of the large mechanisms' part at two small N: a ratio per N (the whole
    analysis costs more than the loads alone, which include every reaction) and the exponents."""
    spec = importlib.util.spec_from_file_location(
        "bench_chain", REPO / "benchmarks" / "bench_chain.py"
    )
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    figures = bench.measure_large(20, loops=(2, 3))
    assert figures["loops"] == [2, 3]
    assert all(x > 0.0 for x in figures["bare_us"] + figures["loads_us"])
    assert all(np.isfinite(list(figures["growth"].values())))
    assert "growth exponents over N = 2 … 3" in capsys.readouterr().out
