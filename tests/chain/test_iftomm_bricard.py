"""IFToMM A04, Bricard's mechanism (``examples/iftomm/bricard.*``), run by the README's
``feeder simulate`` command and compared with the reference of
``examples/iftomm/bricard_reference.py``, computed without multibody code (numpy and SciPy: the
loop closed by least squares along the branch, the one-freedom motion by its energy, the period
by quadrature): the period, the release acceleration and the point P3 over the benchmark's
10 s, at its "high" accuracy, 1e-3 [m], with the room measured."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.interpolate

from .iftomm_examples import readme_states, reference_module

HIGH = 1e-3
"""The IFToMM benchmark's "high" accuracy limit [m]."""


@pytest.fixture(scope="module")
def reference():
    return reference_module("bricard").Reference()


@pytest.fixture(scope="module")
def states(tmp_path_factory):
    """states.csv of the README's command (figures left out)."""
    return readme_states("bricard", 10.0, tmp_path_factory.mktemp("bricard"))


def test_the_reference_is_resolved(reference):
    """The two quadratures of the half period agree (SciPy's adaptive quad, error estimate
    2.8e-14 s, and the Chebyshev interpolant the motion is read from, whose last coefficients
    are 1e-13 of its first), and the swing ends at the start's mirror pose: q_1 = π, where the
    potential is back to the start's (measured: T = 4.986308608657 s, θ_1 = π to 1e-15)."""
    assert reference.tail <= 1e-11
    assert abs(reference.chebyshev_period - reference.period) <= 1e-10
    assert abs(reference.end - math.pi) <= 1e-12
    assert reference.period == pytest.approx(4.9863, abs=1e-4)  # a swing, not a wobble


def test_its_release_acceleration(states, reference):
    """q̈_1 at release against −V'(0)/m(0) (1.962 rad/s² = g/5: m(0) = 5 kg·m², V'(0) = −g
    N·m/rad); measured 1.2e-14 rad/s² apart, the round-off of the two sums."""
    assert states["t"][0] == 0.0
    assert abs(states["a_j1"][0] - reference.release) <= 1e-9 * abs(reference.release)


def test_its_period(states, reference):
    """The run's turning points (q̇_1 = 0, by cubic Hermite interpolation of the samples' rates
    and accelerations) at the multiples of T/2: four in 10 s, measured 1.0e-11 s off at most (the
    run's phase error: its P3 error over P3's speed); the interpolation's error over samples
    0.01 s apart is O(h⁴), ~1e-9 s: the limit, 1e-7 s, is above both."""
    rate = scipy.interpolate.CubicHermiteSpline(states["t"], states["v_j1"], states["a_j1"])
    turns = np.array([root for root in rate.roots(extrapolate=False) if root > 0.1])
    expected = reference.period / 2.0 * np.arange(1, 5)
    assert turns.size == 4
    assert np.abs(turns - expected).max() <= 1e-7


def test_p3_follows_the_reference_over_10_s(states, reference):
    """P3 (the ``[[point]]`` columns of states.csv) against the reference at every fourth sample
    (0.04 s apart): measured 1.2e-11 m at rtol 1e-10, 8 orders of magnitude inside the
    benchmark's 1e-3; the limit asserted, 1e-6 m, leaves the integrator's tolerance room."""
    every = slice(None, None, 4)
    t = states["t"][every]
    run = np.c_[
        states["point_P3_x"][every], states["point_P3_y"][every], states["point_P3_z"][every]
    ]
    error = np.abs(run - reference.p3(t)).max()
    assert np.abs(run[0] - [1.0, -1.0, 0.0]).max() <= 1e-15  # the benchmark's start
    assert error <= HIGH * 1e-3
    # no force but gravity: the energy is kept (the summary's balance, measured 5.9e-11 J)
    assert np.abs(states["energy_balance"]).max() <= 1e-8
