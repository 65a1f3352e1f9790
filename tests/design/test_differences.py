"""The step rule and the kink test of feeder.design.differences, on functions whose derivative
and kinks are known: smooth ones (not flagged, derivative to the truncation the halving
estimates), kinks placed anywhere inside the step (flagged), and an envelope of two elevations
whose argmax changes (flagged, with the elevation that moved)."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from feeder.design.differences import STEP_FACTOR, check_step_factor, estimate, offsets, step
from feeder.design.sensitivities import envelope_estimate
from feeder.exceptions import InputError

ROUND_OFF = 1e-15
"""Relative round-off [-] added to the constructed values: the size measured on the device's
loads (the five-point residual of its peaks, below 1e-15 of them)."""


def values_of(function, p: float, scale: float = 0.1) -> tuple[np.ndarray, np.ndarray, float]:
    h = step(p, scale)
    stepped, steps = offsets(p, h)
    return np.array([function(x) for x in stepped]), steps, h


def test_step_is_the_cube_root_of_epsilon_relative_to_the_value_or_its_scale():
    assert STEP_FACTOR == pytest.approx(np.finfo(float).eps ** (1 / 3), rel=1e-15)
    assert step(0.49, 0.1) == STEP_FACTOR * 0.49
    assert step(-0.014, 0.1) == STEP_FACTOR * 0.1  # an offset near zero: the scale
    stepped, steps = offsets(0.3, step(0.3, 0.1))
    # The steps are the exact differences of the floats, in exact arithmetic: no rounding.
    for value, h in zip(stepped, steps, strict=True):
        assert Fraction(float(value)) - Fraction(0.3) == Fraction(float(h))
    assert steps[2] == 0.0 and steps[0] < steps[1] < 0.0 < steps[3] < steps[4]


@pytest.mark.parametrize(
    "g, dg",
    [
        (lambda u: math.sin(3.0 * u), lambda u: 3.0 * math.cos(3.0 * u)),
        (lambda u: math.exp(u) / u, lambda u: math.exp(u) * (u - 1.0) / u**2),
        (lambda u: 3.0 * u**3 - u, lambda u: 9.0 * u**2 - 1.0),
    ],
)
@pytest.mark.parametrize("p", [0.19, -0.49, 43.5])
def test_smooth_functions_are_not_kinks_and_their_derivative_is_within_the_estimate(g, dg, p, rng):
    """f(x) = g(x / p): smooth on the scale of the parameter, as the step rule assumes (a load
    changes by its own size when a length or a mass does)."""
    function = lambda x: g(x / p)  # noqa: E731
    derivative = lambda x: dg(x / p) / p  # noqa: E731
    noisy = lambda x: function(x) * (1.0 + ROUND_OFF * rng.standard_normal())  # noqa: E731
    values, steps, h = values_of(noisy, p)
    found = estimate(values, steps)
    assert not found.kink, found
    # The halving estimate bounds the truncation (3× its size); the round-off of the values
    # over the half step adds ≤ 4·ROUND_OFF·|f|/h.
    bound = found.error + 4.0 * ROUND_OFF * np.max(np.abs(values)) / h
    assert abs(found.derivative - derivative(p)) <= bound


@pytest.mark.parametrize("where", [-0.9, -0.5, -1 / 3, -0.1, 0.0, 0.2, 1 / 3, 0.6, 0.95])
def test_a_kink_anywhere_inside_the_step_is_flagged(where):
    """max(f1, f2) of two lines whose slopes differ by 1 % of f/p, crossing at p + where·h."""
    p, slope = 0.19, 1000.0
    h = step(p, 0.1)
    crossing = p + where * h
    jump = 0.01 * 500.0 / p
    function = lambda x: 500.0 + slope * (x - p) + jump * max(0.0, x - crossing)  # noqa: E731
    found = estimate(*values_of(function, p)[:2])
    assert found.kink, found
    if where == 0.0:  # at p exactly: the one-sided differences are the two lines' slopes
        assert found.backward == pytest.approx(slope, rel=1e-6)
        assert found.forward == pytest.approx(slope + jump, rel=1e-6)


def test_an_envelope_whose_argmax_elevation_changes_is_a_kink():
    """Two elevations whose peaks cross at p: the envelope |x − p| + 1000 has no derivative."""
    p = 0.28
    h = step(p, 0.1)
    stepped, steps = offsets(p, h)
    values = np.column_stack([1000.0 + 300.0 * steps, 1000.0 - 300.0 * steps])
    times = np.full_like(values, 2.2)
    found, moved = envelope_estimate(values, times, steps)
    assert found.kink and moved == "elevation"
    assert found.forward == pytest.approx(300.0, rel=1e-6)
    assert found.backward == pytest.approx(-300.0, rel=1e-6)
    # The same two elevations, one larger throughout: smooth, nothing moved.
    found, moved = envelope_estimate(values + [[0.0, 1.0]], times, steps)
    assert not found.kink and moved == ""
    assert found.derivative == pytest.approx(-300.0, rel=1e-6)


def test_a_moved_argmax_time_is_reported():
    p = 0.28
    stepped, steps = offsets(p, step(p, 0.1))
    values = (1000.0 + 300.0 * steps)[:, None]
    times = np.array([[2.2], [2.2], [2.2], [2.21], [2.21]])
    assert envelope_estimate(values, times, steps)[1] == "time"


@pytest.mark.parametrize("factor", [0.0, -1e-6, 0.5, math.nan, "big"])
def test_a_step_that_is_not_positive_and_small_is_refused(factor):
    with pytest.raises(InputError, match="relative step") as info:
        check_step_factor(factor)
    assert "\n" not in str(info.value)
