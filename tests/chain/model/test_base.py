"""The base's motion: every profile's rates and accelerations against finite differences of its
values, the attitude's angular velocity and acceleration against finite differences of its
rotation, and the refusals."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from feeder.chain.model.base import (
    BaseMotion,
    Bump,
    Channels,
    Recoil,
    Slope,
    Terrain,
    attitude,
)
from feeder.exceptions import InputError

STEP = 1e-5
"""[s] Central-difference step: truncation h² f‴/6 ~ 1e-10 relative for the profiles' 1–10 Hz,
round-off ε/h ~ 1e-11."""

DIFFERENCE = 1e-7
"""Relative agreement of a derivative with its central difference (bound above, with margin for
the highest-frequency terms)."""

GRAVITY = np.array([0.0, -9.81, 0.0])


def _central(function, t: np.ndarray) -> np.ndarray:
    return (function(t + STEP) - function(t - STEP)) / (2.0 * STEP)


@pytest.mark.parametrize(
    "profile",
    [Terrain(), Bump(start=0.3, duration=0.2), Recoil(start=0.1), Slope(0.1, -0.2)],
    ids=["terrain", "bump", "recoil", "slope"],
)
def test_profile_rates_are_the_derivatives_of_its_values(profile):
    # away from the pulse's and the shot's corners, where the derivatives jump
    t = np.array([0.05, 0.2, 0.35, 0.45, 0.7, 1.3, 2.1])
    channels = profile.channels(t)
    scale = max(np.abs(channels.acceleration).max(), np.abs(channels.rate).max(), 1.0)
    rate = _central(lambda x: profile.channels(x).value, t)
    acceleration = _central(lambda x: profile.channels(x).rate, t)
    assert np.abs(rate - channels.rate).max() <= DIFFERENCE * scale
    assert np.abs(acceleration - channels.acceleration).max() <= DIFFERENCE * scale


def test_bump_leaves_with_the_pulse_velocity():
    """The half-sine pulse's area: Δż = 2 peak duration / π; z keeps rising at that rate."""
    bump = Bump(peak=20.0, duration=0.1, start=0.5)
    channels = bump.channels(np.array([0.4, 0.7, 0.8]))
    assert channels.value[0, 2] == 0.0
    np.testing.assert_allclose(channels.rate[1:, 2], 2 * 20.0 * 0.1 / math.pi, rtol=1e-14)
    assert channels.acceleration[1:, 2].tolist() == [0.0, 0.0]
    np.testing.assert_allclose(
        channels.value[2, 2] - channels.value[1, 2], 0.1 * channels.rate[1, 2], rtol=1e-12
    )


@dataclass(frozen=True)
class Tumble:
    """A profile of six sinusoids, all three angles moving at once with the translations:
    channel k = amplitude[k] sin(w[k] t + offset k)."""

    w: tuple[float, ...] = (1.3, 2.1, 0.7, 1.7, 2.9, 0.9)
    amplitude: tuple[float, ...] = (0.1, -0.2, 0.05, 0.6, -0.4, 1.1)
    offset: float = 0.3

    def channels(self, t):
        w, amplitude = np.array(self.w), np.array(self.amplitude)
        phase = w * t[:, None] + np.arange(6) * self.offset
        return Channels(
            amplitude * np.sin(phase),
            amplitude * w * np.cos(phase),
            -amplitude * w**2 * np.sin(phase),
        )

    def describe(self):
        return "tumble"


def test_attitude_rates_against_the_rotation():
    """Rᵀ Ṙ = [ω]× (vehicle axes) and α = dω/dt, both by central differences."""
    tumble = Tumble()
    t = np.linspace(0.0, 3.0, 7)
    rotation, omega, alpha = attitude(tumble.channels(t))
    assert np.abs(np.swapaxes(rotation, 1, 2) @ rotation - np.eye(3)).max() <= 1e-15
    rate = _central(lambda x: attitude(tumble.channels(x))[0], t)
    skew = np.swapaxes(rotation, 1, 2) @ rate
    measured = np.column_stack([skew[:, 2, 1], skew[:, 0, 2], skew[:, 1, 0]])
    assert np.abs(measured - omega).max() <= DIFFERENCE * np.abs(omega).max()
    spin = _central(lambda x: attitude(tumble.channels(x))[1], t)
    assert np.abs(spin - alpha).max() <= DIFFERENCE * np.abs(alpha).max()


def test_state_in_the_model_axes():
    """The device's axes (forward −x, up +y, so left +z): a pitch turns about the model's z, a
    roll about −x, heave is along y; gravity in the moving axes is Rᵀ g."""
    pitch = BaseMotion((Slope(pitch=0.2),), forward=(-1.0, 0.0, 0.0)).state(np.zeros(1), GRAVITY)
    c, s = math.cos(0.2), math.sin(0.2)
    expected = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])  # about left = model +z
    np.testing.assert_allclose(pitch.rotation[0], expected, atol=1e-15)
    np.testing.assert_allclose(expected @ [0.0, 1.0, 0.0], [-s, c, 0.0])  # up tips forward
    np.testing.assert_allclose(pitch.gravity[0], expected.T @ GRAVITY, atol=1e-15)
    assert not pitch.moving
    heave = BaseMotion((Terrain(pitch=0.0, roll=0.0),), forward=(-1.0, 0.0, 0.0))
    state = heave.state(np.array([0.1]), GRAVITY)
    assert state.moving
    assert np.abs(state.acceleration[0, [0, 2]]).max() == 0.0
    assert state.acceleration[0, 1] != 0.0


def test_refusals():
    vertical = r"axis \[0.0, 1.0, 0.0\] must be horizontal .* gravity \[0.0, -9.81, 0.0\] m/s²"
    with pytest.raises(InputError, match=vertical):
        BaseMotion((Slope(0.1),), forward=(0.0, 1.0, 0.0)).vehicle_axes(GRAVITY)
    with pytest.raises(InputError, match="gravity"):
        BaseMotion((Slope(0.1),)).vehicle_axes(np.zeros(3))
    with pytest.raises(InputError, match="forward"):
        BaseMotion((), forward=(0.0, 0.0, 0.0))
    with pytest.raises(InputError, match="90"):
        Slope(pitch=2.0)
    with pytest.raises(InputError, match="damping"):
        Recoil(damping=1.0)
    with pytest.raises(InputError, match="frequency"):
        Terrain(frequency=0.0)
    with pytest.raises(InputError):
        Bump(peak=float("nan"))
