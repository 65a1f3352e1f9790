"""The cycle's timing (CycleSpec) and the quintic rest-to-rest law of every stage."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder.device.feeder import load_feeder
from feeder.dynamics.cycle import cycle_dynamics
from feeder.exceptions import FeederWarning, InputError
from feeder.motion.laws import MAX_SAMPLES, CycleSpec, peak_miss_bound, rest_to_rest

LAW_ROUND_OFF = 1e-12
"""A polynomial of degree ≤ 5 with coefficients ≤ 60 evaluated on [0, 1] in double precision."""

STEP = 1e-5
"""Central-difference step in s for the law's derivatives."""

DIFFERENCE_TOLERANCE = 1e-8
"""Central differences of h, h′ err by STEP²/6 · max|h‴|, |h⁗| ≤ 360 (6e-9) plus rounding
~1e-16 / STEP (1e-11); a wrong coefficient is off by ≥ 1e-1."""


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"rate": 0.0}, "0.0"),
        ({"rate": float("nan")}, "nan"),
        ({"rate": "fast"}, "fast"),
        ({"rate": "100"}, "text '100'"),
        ({"durations": ("1", "1", "2")}, r"numeric, got \('1', '1', '2'\)"),
        ({"rate": (100.0, 200.0)}, r"\(100.0, 200.0\)"),
        ({"durations": (1.0, -1.0, 2.0)}, r"\(1.0, -1.0, 2.0\)"),
        ({"durations": (1.0, 2.0)}, r"\(1.0, 2.0\)"),
        ({"rate": 1e9}, r"1e\+09 Hz .* 4000000001 samples"),
    ],
)
def test_bad_timing(kwargs, message):
    with pytest.raises(InputError, match=message):
        CycleSpec(**kwargs)


def test_timing_is_stored_as_checked_floats():
    """Integers and numpy numbers become floats; text is refused (a number typed as text is
    the caller's mistake, see feeder.validation.check_finite)."""
    spec = CycleSpec(durations=(1, np.int64(1), np.float32(2.0)), rate=100)
    assert spec.durations == (1.0, 1.0, 2.0) and spec.rate == 100.0
    assert all(type(x) is float for x in (*spec.durations, spec.rate))
    assert spec == CycleSpec(rate=100.0)
    assert spec.times().size == 401
    largest = CycleSpec(rate=(MAX_SAMPLES - 1) / 4.0)  # the cap itself is accepted
    assert largest.times().size == MAX_SAMPLES


@pytest.mark.parametrize(
    "rate, fitting",
    [(13.7, "13.5 Hz, 13.75 Hz"), (0.9, "0.75 Hz, 1 Hz"), (0.3, "0.25 Hz, 0.5 Hz"),
     (1e-300, "0.25 Hz"), (1000.2, "1000 Hz, 1000.25 Hz")],
)  # fmt: skip
def test_a_rate_that_does_not_fit_the_cycle_is_refused_with_rates_that_do(rate, fitting):
    """A sample would fall past the cycle's end (or the end would not be sampled): refused,
    naming the nearest rates that divide the 4 s cycle into whole steps."""
    with pytest.raises(InputError, match=f"does not divide the 4 s cycle .* use e.g. {fitting}$"):
        CycleSpec(rate=rate)


@pytest.mark.parametrize("rate", [0.25, 13.75, 1000.0])
def test_the_samples_span_the_cycle_at_one_step(rate):
    t = CycleSpec(rate=rate).times()
    assert t[0] == 0.0 and t[-1] == 4.0
    np.testing.assert_allclose(np.diff(t), 1.0 / rate, rtol=1e-12)


def test_rest_to_rest_law_starts_and_ends_at_rest():
    """h goes 0 → 1 monotonically with h′ = h″ = 0 at both ends, and h′, h″ are its derivatives
    (central differences), so every stage starts and ends at rest."""
    h, dh, ddh = rest_to_rest(np.array([0.0, 1.0]))
    np.testing.assert_array_equal(h, [0.0, 1.0])
    np.testing.assert_array_equal(dh, [0.0, 0.0])
    np.testing.assert_array_equal(ddh, [0.0, 0.0])
    s = np.linspace(STEP, 1.0 - STEP, 999)
    h, dh, ddh = rest_to_rest(s)
    assert np.all(np.diff(h) > 0.0) and np.all(dh > 0.0)
    plus, minus = rest_to_rest(s + STEP), rest_to_rest(s - STEP)
    np.testing.assert_allclose((plus[0] - minus[0]) / (2 * STEP), dh, atol=DIFFERENCE_TOLERANCE)
    np.testing.assert_allclose((plus[1] - minus[1]) / (2 * STEP), ddh, atol=DIFFERENCE_TOLERANCE)
    # Symmetric about s = 1/2: h(s) + h(1 − s) = 1.
    np.testing.assert_allclose(h + rest_to_rest(1.0 - s)[0], 1.0, rtol=0, atol=LAW_ROUND_OFF)


@pytest.mark.parametrize("rate", [5.0, 10.0, 35.0])
def test_coarse_sampling_warns_with_a_bound_that_holds(rate):
    """A cycle sampled too coarsely to resolve its peaks says so, and the miss it states is an
    upper bound of the true one: the peak piston force and forearm moment against a 1 kHz
    cycle computed independently."""
    device = load_feeder()
    with pytest.warns(FeederWarning, match="too coarse .* missed by up to"):
        spec = CycleSpec(rate=rate)
    coarse = cycle_dynamics(device, math.radians(-4.0), spec, forward=False).loads
    fine = cycle_dynamics(device, math.radians(-4.0), forward=False).loads
    for name in ("piston_force", "forearm_torque"):
        peak = np.abs(getattr(fine, name)).max()
        miss = 1.0 - np.abs(getattr(coarse, name)).max() / peak
        assert 0.0 <= miss + 1e-12 <= peak_miss_bound(rate, 1.0)  # 1e-12: equal peaks' round-off


@pytest.mark.parametrize("rate", [71.0, 1000.0])
def test_fine_enough_sampling_is_silent(rate, recwarn):
    CycleSpec(rate=rate)
    assert not [w for w in recwarn if "too coarse" in str(w.message)]
