"""The drives' position loops (feeder.dynamics.servo): the reference's interpolation, the gains,
the limits, the clipping and the drive lag."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder.dynamics.servo import CycleServo, ServoGains
from feeder.exceptions import InputError


def test_gains_give_each_loop_its_bandwidth_and_damping():
    gains = ServoGains(bandwidth_hz=3.0, damping=0.7)
    inertia = np.array([800.0, 2.5])
    kp, kd = gains.gains(inertia)
    for m, p, d in zip(inertia, kp, kd, strict=True):
        poles = np.roots([m, d, p])  # m s² + K_d s + K_p
        np.testing.assert_allclose(np.abs(poles), 2.0 * math.pi * 3.0, rtol=1e-12)
        np.testing.assert_allclose(-poles.real / np.abs(poles), 0.7, rtol=1e-12)


def test_limits_are_the_supply_pressure_on_the_areas_and_the_rack_force(feeder):
    p = feeder.params
    gains = ServoGains(supply_pressure=1e7, rack_force_limit=1500.0)
    low, high = gains.limits(p)
    bore, rod = p.bore_diameter, p.rod_diameter
    np.testing.assert_allclose(high, [1e7 * math.pi * bore**2 / 4.0, 1500.0 * p.pinion_radius])
    np.testing.assert_allclose(
        low, [-1e7 * math.pi * (bore**2 - rod**2) / 4.0, -1500.0 * p.pinion_radius]
    )


@pytest.mark.parametrize(
    "field", ["bandwidth_hz", "damping", "actuator_hz", "supply_pressure", "rack_force_limit"]
)
@pytest.mark.parametrize("value", [0.0, -1.0, math.nan, "5"])
def test_bad_settings_are_refused(field, value):
    with pytest.raises(InputError, match=field):
        ServoGains(**{field: value})


def _servo(actuator_hz=None, x0=None):
    t = np.linspace(0.0, 1.0, 11)
    still = np.zeros((t.size, 2))
    u = np.column_stack([np.full(t.size, 100.0), np.full(t.size, -2.0)])
    return CycleServo(
        t, still + [0.3, 0.1], still, still, u, [3, 1], np.array([1e4, 50.0]),
        np.array([1e3, 5.0]), np.array([-500.0, -10.0]), np.array([800.0, 10.0]),
        actuator_hz, x0,
    )  # fmt: skip


def test_the_law_clips_at_the_limits_and_lags_the_drives():
    servo = _servo()
    q, v = np.zeros(4), np.zeros(4)
    q[[3, 1]] = [0.3 - 0.01, 0.1 + 0.05]  # r2 1 cm short, φ4 0.05 rad past
    v[[3, 1]] = [0.05, 0.0]
    expected = np.array([100.0 + 1e4 * 0.01 - 1e3 * 0.05, -2.0 - 50.0 * 0.05])
    np.testing.assert_allclose(servo.command(0.5, q, v), expected, rtol=1e-12)
    u, xdot = servo(0.5, q, v, np.zeros(0))
    np.testing.assert_allclose(u, expected, rtol=1e-12)
    assert xdot.size == 0
    q[3] = 0.3 - 0.2  # 20 cm short: 2 kN asked, the cylinder gives 800 N
    assert servo(0.5, q, v, np.zeros(0))[0][0] == 800.0
    lagged = _servo(actuator_hz=10.0)
    assert lagged.n_states == 2
    x = np.array([100.0, 0.0])
    u, xdot = lagged(0.5, q, v, x)
    np.testing.assert_array_equal(u, x)  # the drive applies its state
    command = np.clip(lagged.command(0.5, q, v), [-500.0, -10.0], [800.0, 10.0])
    np.testing.assert_allclose(xdot, 2.0 * math.pi * 10.0 * (command - x), rtol=1e-12)
    np.testing.assert_allclose(lagged.start(0.0, q, v), command, rtol=1e-12)
    np.testing.assert_array_equal(_servo(10.0, x0=[1.0, 2.0]).start(0.0, q, v), [1.0, 2.0])


def test_the_command_of_many_instants_is_each_instants(rng):
    servo = _servo()
    t = rng.uniform(0.0, 1.0, 7)
    q, v = rng.normal(size=(7, 4)), rng.normal(size=(7, 4))
    each = np.array([servo.command(*row) for row in zip(t, q, v, strict=True)])
    np.testing.assert_array_equal(servo.command(t, q, v), each)


@pytest.mark.parametrize("actuator_hz", [None, 10.0])
def test_the_forces_applied_at_many_samples_are_each_samples(rng, actuator_hz):
    """``at_samples`` (the engine's output samples) against ``__call__``'s u one sample at a
    time, clipped or lagged: the same operations, the same floats."""
    servo = _servo(actuator_hz)
    t = rng.uniform(0.0, 1.0, 9)
    q, v = rng.normal(scale=0.1, size=(9, 4)), rng.normal(size=(9, 4))
    x = rng.normal(scale=100.0, size=(9, servo.n_states))
    each = np.array([servo(*row)[0] for row in zip(t, q, v, x, strict=True)])
    np.testing.assert_array_equal(servo.at_samples(t, q, v, x), each)
