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
    """A smoke test of the large mechanisms' part at two small N and two sample counts: a time
    per N, its split into a fixed cost per call and a cost per sample (time = fixed +
    per_sample × samples through both counts: the fit reproduces the time at the first count),
    and the exponents."""
    spec = importlib.util.spec_from_file_location(
        "bench_chain", REPO / "benchmarks" / "bench_chain.py"
    )
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    figures = bench.measure_large(20, loops=(2, 3), fit=40)
    assert figures["loops"] == [2, 3] and figures["samples"] == [20, 40]
    assert all(x > 0.0 for x in figures["bare_us"] + figures["loads_us"])
    # the fit's bookkeeping (the line through the first count's time, the ratio of its slope):
    # a check of the script's arithmetic and JSON keys, not of the times themselves, which are
    # the benchmark's to report (CI's cores may be busy)
    for k in range(2):
        fitted = figures["fixed_ms"][k] * 1e3 + figures["per_sample_us"][k] * 20
        assert np.isclose(fitted, figures["inverse_dynamics_us"][k] * 20, rtol=1e-9)
        ratio = figures["per_sample_us"][k] / figures["bare_us"][k]
        assert np.isclose(figures["per_sample_ratio"][k], ratio, rtol=1e-12)
    assert all(np.isfinite(list(figures["growth"].values())))
    printed = capsys.readouterr().out
    assert "growth exponents over N = 2 … 3" in printed and "µs/sample" in printed
