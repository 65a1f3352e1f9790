"""The elevation sweep (feeder.study.sweep): the peaks of each elevation's cycle."""

from __future__ import annotations

import numpy as np
import pytest

from feeder.dynamics.cycle import cycle_dynamics
from feeder.exceptions import ElevationError, InputError
from feeder.motion.laws import CycleSpec
from feeder.study.peaks import cycle_peaks
from feeder.study.sweep import elevation_sweep

SWEEP_SPEC = CycleSpec(rate=100.0)
"""100 Hz: below the forward run's minimum rate, which the sweep does not need."""


def test_sweep_peaks_are_the_cycles_peaks(feeder, capsys):
    """The sweep needs no forward run (so no minimum rate), and is quiet off a terminal."""
    elevations = np.radians([-4.0, 50.0])
    sweep = elevation_sweep(feeder, elevations, SWEEP_SPEC)
    assert capsys.readouterr().err == ""
    np.testing.assert_array_equal(sweep.elevations, elevations)
    for k, elevation in enumerate(elevations):
        peaks = cycle_peaks(cycle_dynamics(feeder, elevation, SWEEP_SPEC, forward=False))
        assert list(sweep.peaks) == [peak.name for peak in peaks]
        for peak in peaks:
            assert sweep.peaks[peak.name][k] == peak.value
            assert sweep.times[peak.name][k] == peak.time
            assert sweep.units[peak.name] == peak.unit


@pytest.mark.parametrize("bad", [[], np.zeros((2, 2)), 0.1, [0.1, float("nan")]])
def test_sweep_needs_a_list_of_finite_elevations(feeder, bad):
    with pytest.raises(InputError, match="elevations"):
        elevation_sweep(feeder, bad)


def test_sweep_checks_every_elevation_first(feeder):
    with pytest.raises(ElevationError, match="80.000°"):
        elevation_sweep(feeder, np.radians([10.0, 80.0]))
