"""The IFToMM spatial rigid slider-crank (``examples/iftomm/slider_crank.*``), run by the README's
``feeder simulate`` command and compared with the reference of
``examples/iftomm/slider_crank_reference.py``, computed without multibody code (the crank angle
as the one coordinate, the closure in closed form, the motion by its energy and the time by
quadrature): the crank's angle, rate and turn times and the slider's position over 5 s, at the
benchmark's "high" accuracy, 1e-3 [m, m/s], with the room measured."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.interpolate

from .iftomm_examples import readme_states, reference_module

HIGH = 1e-3
"""The IFToMM benchmark's "high" accuracy limit [m, m/s]."""


@pytest.fixture(scope="module")
def reference():
    return reference_module("slider_crank").Reference()


@pytest.fixture(scope="module")
def states(tmp_path_factory):
    """states.csv of the README's command (figures left out)."""
    return readme_states("slider_crank", 5.0, tmp_path_factory.mktemp("slider_crank"))


def test_the_reference_is_resolved(reference):
    """One turn's time by SciPy's quad (error estimate 1e-14 s) and by the Chebyshev interpolant
    the motion is read from (last coefficients 1e-15 of its first) agree: T = 0.5758594564 s."""
    assert reference.tail <= 1e-12
    assert abs(reference.chebyshev_turn - reference.turn) <= 1e-12


def test_it_starts_as_the_benchmark(states):
    """The start: B = (0, 0.1, 0.2), C = (0.2, 0, 0) and the crank at 6 rad/s; the slider's rate
    then follows from |B − C| = 0.3 kept: (B − C)·(v_B − v_C) = 0 with v_B = 6 x × (0, 0, 0.08) =
    (0, −0.48, 0): 0.2 v_C − 0.048 = 0, v_C = 0.24 m/s (round-off of the closure's solve)."""
    assert states["q_crank"][0] == 0.0 and abs(states["q_slider"][0] - 0.2) <= 1e-12
    assert abs(states["v_crank"][0] - 6.0) <= 1e-12
    assert abs(states["v_slider"][0] - 0.24) <= 1e-12


def test_it_follows_the_reference_over_5_s(states, reference):
    """Against the reference at every sample (0.005 s apart): measured 2.5e-9 rad of the crank,
    5.6e-11 m of the slider and 4.3e-8 rad/s of the crank's rate at rtol 1e-10 — the benchmark's
    1e-3 met with five orders of magnitude to spare; the limits asserted (1e-6) leave the
    integrator's tolerance room."""
    theta = reference.angle(states["t"])
    assert np.abs(states["q_crank"] - theta).max() <= 1e-6
    assert np.abs(states["q_slider"] - reference.slider(theta)).max() <= HIGH * 1e-3
    assert np.abs(states["v_crank"] - reference.rate(theta)).max() <= HIGH * 1e-3
    # no force but gravity: the energy is kept (the summary's balance, measured 1.4e-10 J)
    assert np.abs(states["energy_balance"]).max() <= 1e-8


def test_its_turns_take_the_reference_time(states, reference):
    """The times the crank completes each of its 8 turns in 5 s (cubic Hermite interpolation of
    the samples' angles and rates) at multiples of T: measured 6e-9 s off at most, the run's
    phase error; the interpolation's O(h⁴) over 0.005 s is below 1e-9 s."""
    angle = scipy.interpolate.CubicHermiteSpline(states["t"], states["q_crank"], states["v_crank"])
    turns = np.array([angle.solve(2.0 * math.pi * k, extrapolate=False)[0] for k in range(1, 9)])
    assert np.abs(turns - reference.turn * np.arange(1, 9)).max() <= 1e-7
