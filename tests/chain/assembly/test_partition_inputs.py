"""Partition.velocity and Partition.acceleration check their inputs like every public entry
point: NaN, a wrong size (a size-1 array would broadcast), a configuration that does not close
the loop, each refused with a feeder exception; valid input still gives J q̇ = 0."""

from __future__ import annotations

import numpy as np
import pytest

from feeder.chain.assembly.partition import Partition
from feeder.device.feeder import INDEPENDENT_JOINTS
from feeder.exceptions import FeederError, InputError

LOOP_ROUND_OFF = 1e-12
"""[m/s], [m/s²] The closure's velocity and acceleration residuals after a least-squares solve
of a 3 × 4 system with entries ~1: round-off."""


@pytest.fixture(scope="module")
def partition(feeder):
    return Partition(feeder.chain, INDEPENDENT_JOINTS)


@pytest.fixture(scope="module")
def closed(feeder, partition):
    """A closed configuration (φ3 = 0.3 rad, φ4 = 0.2 rad) and a closed-chain velocity there."""
    q = partition.assemble(feeder.to_pinocchio([2.4, 0.35, 0.3, 0.2]))
    return q, partition.velocity(q, np.array([0.5, -0.4]))


def test_valid_input_closes_the_loop(feeder, partition, closed):
    """Independent check: the returned rates keep the pin closed (J q̇ = 0, J q̈ + J̇ q̇ = 0), with
    the independent components as given."""
    q, v = closed
    jac = feeder.chain.jacobian(q)
    assert np.abs(jac @ v).max() <= LOOP_ROUND_OFF
    assert np.array_equal(v[partition.independent], [0.5, -0.4])
    a = partition.acceleration(q, v, np.array([1.0, 2.0]))
    assert np.abs(jac @ a + feeder.chain.bias(q, v)).max() <= LOOP_ROUND_OFF
    assert np.array_equal(a[partition.independent], [1.0, 2.0])


@pytest.mark.parametrize(
    "bad, match",
    [
        ([np.nan, 1.0], "finite"),
        ([1.0], r"shape \(2,\)"),  # would broadcast to both independent rates
        ([1.0, 1.0, 1.0], r"shape \(2,\)"),  # was numpy's broadcast ValueError
        ("1", "text"),
        ([[1.0, 1.0]], r"shape \(2,\)"),
    ],
)
def test_bad_independent_rates(partition, closed, bad, match):
    q, v = closed
    with pytest.raises(InputError, match=match):
        partition.velocity(q, bad)
    with pytest.raises(InputError, match=match):
        partition.acceleration(q, v, bad)


@pytest.mark.parametrize(
    "bad, match", [(np.full(4, np.nan), "finite"), (np.ones(2), r"shape \(4,\)")]
)
def test_bad_velocity_for_the_acceleration(partition, closed, bad, match):
    q, _ = closed
    with pytest.raises(InputError, match=match):
        partition.acceleration(q, bad, np.ones(2))


@pytest.mark.parametrize("method", ["velocity", "acceleration"])
def test_open_loop_configuration_is_refused(partition, closed, method):
    """A q whose pin is open by ~0.1 m has no closed-chain rates: refused, not answered."""
    q, v = closed
    opened = q + 0.1
    arguments = (opened, np.ones(2)) if method == "velocity" else (opened, v, np.ones(2))
    with pytest.raises(FeederError, match="close"):
        getattr(partition, method)(*arguments)


@pytest.mark.parametrize("bad", [np.full(4, np.nan), np.ones(3)])
def test_bad_configuration_is_refused(partition, bad):
    with pytest.raises(InputError):
        partition.velocity(bad, np.ones(2))
