"""The base's motion: every profile's rates and accelerations against finite differences of its
values, the attitude's angular velocity and acceleration against finite differences of its
rotation, and the refusals."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from feeder.chain.model.base import BaseMotion, attitude
from feeder.chain.model.channels import Channels
from feeder.chain.model.forces import Table
from feeder.chain.model.hull import ATTITUDE, G
from feeder.chain.model.hull_table import COLUMNS, HullTable
from feeder.chain.model.profiles import Bump, Recoil, Slope, Terrain
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
    with pytest.raises(InputError, match="45°"):
        Slope(pitch=2.0)
    with pytest.raises(InputError, match="damping"):
        Recoil(damping=1.0)
    with pytest.raises(InputError, match="frequency"):
        Terrain(frequency=0.0)
    with pytest.raises(InputError):
        Bump(peak=float("nan"))


BOUND = 1e-12
"""Relative slack of a sampled channel against its peak: the bound is analytic, the samples
carry round-off of a few ulps."""


@pytest.mark.parametrize(
    "profile",
    [
        Terrain(),
        Terrain(heave=0.1, pitch=0.2, roll=0.1, frequency=2.0, roll_phase=1.0),
        Bump(peak=-14.0 * G, duration=0.05, start=0.2),
        Recoil(amplitude=-0.1, frequency=3.0, damping=0.05, start=0.1),
        Recoil(damping=0.0),
        Slope(-0.3, 0.2),
    ],
    ids=["terrain", "terrain-2hz", "bump-down", "recoil-nose-down", "recoil-undamped", "slope"],
)
def test_peaks_bound_the_sampled_channels(profile):
    """Every channel's value, rate and acceleration, sampled densely over a few periods, stays
    within the profile's peaks; the periodic ones reach them (within the sampling)."""
    t = np.linspace(0.0, 3.0, 30_001)
    channels = profile.channels(t)
    sampled = np.array(
        [np.abs(c).max(axis=0) for c in (channels.value, channels.rate, channels.acceleration)]
    )
    peaks = profile.peaks()
    assert peaks.shape == (3, 6)
    assert np.all(sampled <= peaks * (1.0 + BOUND))
    if isinstance(profile, Terrain | Slope):
        finite = np.isfinite(peaks) & (peaks > 0.0)
        np.testing.assert_allclose(sampled[finite], peaks[finite], rtol=1e-6)


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (
            lambda: Slope(pitch=math.radians(60.0)),
            r"pitch reaches ±1.047 rad \(60°\), beyond the plausible ±0.7854 rad \(45°\)",
        ),
        (lambda: Slope(roll=-1.0), r"roll reaches ±1 rad \(57.3°\)"),
        (lambda: Terrain(frequency=1e6), r"terrain frequency is 1e\+06 Hz, beyond .* 20 Hz"),
        (lambda: Terrain(frequency=1e308), r"terrain frequency is 1e\+308 Hz"),
        (lambda: Terrain(pitch=math.radians(1000.0)), r"pitch reaches ±17.45 rad \(1000°\)"),
        (lambda: Terrain(heave=40.0), r"terrain heave is 40 m, beyond the plausible 1 m"),
        (lambda: Terrain(roll_phase=90.0), r"roll_phase is 90 rad \(5157°\), beyond .*360°"),
        (lambda: Terrain(roll=0.0, frequency=15.0), r"pitch acceleration reaches ±465.1 rad/s²"),
        (
            lambda: Recoil(amplitude=math.radians(1e6)),
            r"pitch reaches ±1.745e\+04 rad \(1e\+06°\)",
        ),
        (lambda: Recoil(amplitude=0.5, frequency=10.0), r"pitch rate reaches ±31.42 rad/s"),
        (lambda: Recoil(frequency=100.0), r"recoil frequency is 100 Hz"),
        (lambda: Bump(peak=1e12), r"z acceleration reaches ±1e\+12 m/s², beyond .*392.4 m/s²"),
        (lambda: Bump(duration=1e-3), r"bump duration is 0.001 s, shorter than .* 0.025 s"),
    ],
    ids=[
        "slope-60deg",
        "slope-1rad",
        "terrain-1MHz",
        "terrain-1e308Hz",
        "terrain-1000deg",
        "terrain-heave-mm",
        "terrain-phase-deg",
        "terrain-15Hz",
        "recoil-1e6deg",
        "recoil-rate",
        "recoil-100Hz",
        "bump-1e12",
        "bump-1ms",
    ],
)
def test_implausible_profiles_are_refused(make, match):
    with pytest.raises(InputError, match=match) as caught:
        make()
    assert "\n" not in str(caught.value)


def test_plausible_profiles_are_kept():
    """The defaults, the notebooks' cases (a 15° side slope, bumps of ±14 g) and a slope at
    the limit itself."""
    BaseMotion((Slope(roll=math.radians(15.0)), Terrain(), Recoil(), Bump()))
    BaseMotion((Bump(peak=14.0 * G), Bump(peak=-14.0 * G, start=2.0)))
    BaseMotion((Slope(ATTITUDE / 2), Slope(ATTITUDE / 2)))
    Slope(pitch=-ATTITUDE, roll=ATTITUDE)


@pytest.mark.parametrize(
    ("profiles", "match"),
    [
        (
            (Slope(math.radians(30.0)), Slope(math.radians(30.0))),
            r"pitch reaches ±1.047 rad \(60°\)",
        ),
        ((Slope(roll=0.5), Terrain(roll=0.3)), r"roll reaches ±0.8 rad"),
        (
            (Bump(peak=30.0 * G), Bump(peak=20.0 * G, start=3.0)),
            r"z acceleration reaches ±490.5 m/s²",
        ),
    ],
    ids=["two-slopes", "slope-and-ride", "two-bumps"],
)
def test_profiles_together_past_a_limit_are_refused(profiles, match):
    """Each profile is plausible alone; their sum is not: the message names them all."""
    with pytest.raises(InputError, match=f"the base's profiles together .*: their {match}"):
        BaseMotion(profiles)


@pytest.mark.parametrize(
    ("profiles", "match"),
    [
        (Slope(0.1), r" must be a list or tuple .*got Slope\(.*\) \(one profile: \(profile,\)\)"),
        (None, " must be a list or tuple .*got None"),
        ("terrain", " must be a list or tuple .*got 'terrain'"),
        (3, " must be a list or tuple .*got 3"),
        ([Slope(0.1), "terrain"], r"\[1\] must be one of .*got 'terrain'"),
        ([Terrain], r"\[0\] must be one of .*got <class"),
    ],
    ids=["one-profile", "none", "text", "number", "text-in-list", "a-class"],
)
def test_base_motion_profiles_argument(profiles, match):
    with pytest.raises(InputError, match=f"BaseMotion profiles{match}"):
        BaseMotion(profiles)


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda: Slope(pitch="0.1"), r"slope pitch \[rad\] must be numeric, got the text"),
        (lambda: Slope(roll=None), r"slope roll \[rad\] must be numeric, got None"),
        (lambda: Terrain(heave=math.inf), r"terrain heave \[m\] must be finite"),
        (lambda: Terrain(pitch_phase=True), "terrain pitch_phase .* truth value"),
        (lambda: Terrain(frequency="fast"), r"terrain frequency \[Hz\] must be numeric"),
        (lambda: Bump(start=math.nan), r"bump start \[s\] must be finite"),
        (lambda: Bump(duration=[0.1, 0.2]), r"bump duration \[s\] must be one number"),
        (lambda: Recoil(damping=None), "recoil damping must be numeric"),
        (lambda: HullTable("hull.csv"), "a hull table is a Table .*got 'hull.csv'"),
        (lambda: HullTable(None), "a hull table is a Table .*got None"),
        (lambda: HullTable(_table(), columns=("t",)), "columns must be 18 names"),
    ],
)
def test_profile_arguments(make, match):
    with pytest.raises(InputError, match=match):
        make()


def _table(column: str = "z", values=(0.0, 0.0, 0.0)) -> Table:
    """A hull table's Table at t = 0, 1, 2 s with one of its :data:`COLUMNS` set."""
    table = np.zeros((3, 18))
    table[:, COLUMNS.index(column)] = values
    return Table(np.arange(3.0), table, source="hull motion test")


@pytest.mark.parametrize(
    ("column", "values", "match"),
    [
        (
            "roll",
            (0.0, 30.0, 0.0),
            r"roll = 30 rad \(1719°\) at t = 1 s is beyond .*; if it "
            r"holds degrees, name the column roll_deg",
        ),
        ("v_yaw", (0.0, 0.0, -20.0), r"v_yaw = -20 rad/s \(-1146°/s\) at t = 2 s .*v_yaw_deg"),
        (
            "a_z",
            (1e12, 0.0, 0.0),
            r"a_z = 1e\+12 m/s² at t = 0 s is beyond the plausible ±392.4"
            r" m/s² \([^;]*\)$",
        ),
        ("pitch", (0.0, 90.0, 0.0), r"pitch = 90 rad \(5157°\) at t = 1 s is beyond [^;]*$"),
    ],
    ids=["roll-in-degrees", "yaw-rate-in-degrees", "acceleration", "pitch-not-even-degrees"],
)
def test_hull_table_past_a_limit_is_refused(column, values, match):
    """The column as given, the value in its unit and its time; for an angle in radians that
    would be plausible in degrees, the column's _deg name (not for 90, implausible either way,
    nor for an acceleration)."""
    with pytest.raises(InputError, match=f"^hull motion test: {match}"):
        HullTable(_table(column, values))
    HullTable(_table(column, 0.1 * np.sign(values)))  # 0.1 in any unit is plausible
