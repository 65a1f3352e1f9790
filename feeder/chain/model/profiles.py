"""The hull's motion profiles: a slope, a ride over terrain, a bump, the rocking after a shot.

Each profile (:class:`Slope`, :class:`Terrain`, :class:`Bump`, :class:`Recoil`) is a small frozen
dataclass that gives the channels of :mod:`feeder.chain.model.channels` (with their signs and
units) at any times, and the peaks of its channels. Their defaults are *assumed* (no measured
hull data is published for the M77): each says why.

A hull is a ground vehicle on its suspension: a profile refuses, when it is made, a motion no hull
makes (the limits of :mod:`feeder.chain.model.hull`: a 45° slope, 5 rad/s, 200 rad/s², 40 g,
20 Hz); the base's motion (:mod:`feeder.chain.model.base`) checks them all together.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ...exceptions import InputError
from ...validation import check_number
from .channels import BoundedProfile, Channels, at_rest
from .hull import (
    BUMP_SHORTEST,
    FREQUENCY,
    HEAVE,
    PHASE,
    G,
    check_at_most,
    implausible,
    reaches,
)


def _channel(t: np.ndarray, index: int, value, rate, acceleration) -> Channels:
    out = at_rest(t)
    out.value[:, index], out.rate[:, index], out.acceleration[:, index] = (
        value,
        rate,
        acceleration,
    )
    return out


def _check_positive(what: str, value: float, unit: str) -> None:
    """Raise :class:`InputError` unless ``value`` [unit] is a finite number > 0."""
    if not check_number(f"{what} [{unit}]", value) > 0.0:
        raise InputError(f"{what} must be positive, got {value} {unit}")


def _check_frequency(what: str, value: float) -> None:
    """Raise :class:`InputError` unless ``value`` [Hz] is in (0, :data:`FREQUENCY`]."""
    _check_positive(what, value, "Hz")
    check_at_most(what, value, FREQUENCY, "Hz", "above a hull's ride and wheel-hop frequencies")


def _check_plausible(profile: BoundedProfile) -> None:
    """Raise :class:`InputError` if the profile's peaks pass a plausible limit."""
    peaks = profile.peaks()
    excess = implausible(peaks)
    if excess is not None:
        raise InputError(f"{profile.describe()}: its {reaches(peaks, *excess)}")


def _peaks(channel: int, value: float, rate: float, acceleration: float) -> np.ndarray:
    """The peaks (3, 6) of a profile that moves one channel (:meth:`BoundedProfile.peaks`)."""
    out = np.zeros((3, 6))
    out[:, channel] = value, rate, acceleration
    return out


@dataclass(frozen=True)
class Slope:
    """The hull standing still on a slope: constant pitch and roll [rad] (the signs of
    :mod:`feeder.chain.model.channels`: a positive pitch lowers the nose, a positive roll the
    right side), each within ±:data:`~feeder.chain.model.hull.ATTITUDE`."""

    pitch: float = 0.0
    roll: float = 0.0
    ANGLES: ClassVar[tuple[str, ...]] = ("pitch", "roll")

    def __post_init__(self):
        for name in ("pitch", "roll"):
            check_number(f"slope {name} [rad]", getattr(self, name))
        _check_plausible(self)

    def channels(self, t: np.ndarray) -> Channels:
        out = at_rest(t)
        out.value[:, 3], out.value[:, 4] = self.roll, self.pitch
        return out

    def peaks(self) -> np.ndarray:
        return _peaks(3, abs(self.roll), 0.0, 0.0) + _peaks(4, abs(self.pitch), 0.0, 0.0)

    def describe(self) -> str:
        return f"slope: pitch {math.degrees(self.pitch):g}°, roll {math.degrees(self.roll):g}°"


@dataclass(frozen=True)
class Terrain:
    """Driving across country: a sinusoidal heave, pitch and roll at one frequency.

    z = heave sin(2π f t), θ = pitch sin(2π f t + pitch_phase), φ = roll sin(2π f t + roll_phase).

    Defaults (assumed): a tracked hull's sprung mass bounces and pitches at about 1–1.5 Hz
    (J. Y. Wong, Theory of Ground Vehicles, 4th ed., ch. 7: ride frequencies of 1–1.5 Hz are the
    design target of vehicle suspensions), taken as 1.2 Hz; ±40 mm of heave, ±3° of pitch and
    ±1.5° of roll are assumed for rough cross-country going at moderate speed (peak hull
    accelerations 0.23 g vertical and 3 rad/s² in pitch); pitch lags heave by a quarter period
    (front and rear road wheels meet a bump one after the other), roll is in phase.

    Attributes:
        heave: Amplitude [m], at most :data:`~feeder.chain.model.hull.HEAVE`. pitch, roll:
            Amplitudes [rad]. frequency: [Hz], at most
            :data:`~feeder.chain.model.hull.FREQUENCY`. pitch_phase, roll_phase: [rad], within
            ±:data:`~feeder.chain.model.hull.PHASE`.
    """

    heave: float = 0.04
    pitch: float = math.radians(3.0)
    roll: float = math.radians(1.5)
    frequency: float = 1.2
    pitch_phase: float = -math.pi / 2
    roll_phase: float = 0.0
    ANGLES: ClassVar[tuple[str, ...]] = ("pitch", "roll", "pitch_phase", "roll_phase")

    def __post_init__(self):
        for name, unit in (("heave", "m"), ("pitch", "rad"), ("roll", "rad")):
            if check_number(f"terrain {name} [{unit}]", getattr(self, name)) < 0.0:
                raise InputError(
                    f"terrain {name} is an amplitude, ≥ 0, got {getattr(self, name):g}: the "
                    "phases give the signs (pitch_phase, roll_phase)"
                )
        for name in ("pitch_phase", "roll_phase"):
            value = check_number(f"terrain {name} [rad]", getattr(self, name))
            check_at_most(f"terrain {name}", value, PHASE, "rad", "one turn")
        check_at_most("terrain heave", self.heave, HEAVE, "m", "a hull's travel on its wheels")
        _check_frequency("terrain frequency", self.frequency)
        _check_plausible(self)

    def channels(self, t: np.ndarray) -> Channels:
        w = 2.0 * math.pi * self.frequency
        out = at_rest(t)
        for index, amplitude, phase in (
            (2, self.heave, 0.0),
            (4, self.pitch, self.pitch_phase),
            (3, self.roll, self.roll_phase),
        ):
            s, c = np.sin(w * t + phase), np.cos(w * t + phase)
            out = out + _channel(t, index, amplitude * s, amplitude * w * c, -amplitude * w**2 * s)
        return out

    def peaks(self) -> np.ndarray:
        w = 2.0 * math.pi * self.frequency
        return sum(
            _peaks(index, amplitude, amplitude * w, amplitude * w**2)
            for index, amplitude in ((2, self.heave), (3, self.roll), (4, self.pitch))
        )

    def describe(self) -> str:
        return (
            f"terrain: heave ±{self.heave * 1e3:g} mm, pitch ±{math.degrees(self.pitch):g}°, "
            f"roll ±{math.degrees(self.roll):g}° at {self.frequency:g} Hz"
        )


@dataclass(frozen=True)
class Bump:
    """A bump: a half-sine pulse of the hull's vertical acceleration,

    z̈ = peak sin(π (t − start) / duration) for start ≤ t ≤ start + duration, else 0,

    the hull at rest before it (z = ż = 0); it leaves the pulse rising at 2 peak duration / π.

    Defaults (assumed): the half-sine is the shape of shock tests (MIL-STD-810H, Method 516);
    a peak of 2 g over 0.1 s is assumed for a hull crossing a ditch edge at low speed.

    Attributes:
        peak: Peak vertical acceleration [m/s²], within
            ±:data:`~feeder.chain.model.hull.ACCELERATION`. duration: [s], at least
            :data:`~feeder.chain.model.hull.BUMP_SHORTEST`. start: [s].
    """

    peak: float = 2.0 * G
    duration: float = 0.1
    start: float = 1.0
    ANGLES: ClassVar[tuple[str, ...]] = ()

    def __post_init__(self):
        check_number("bump peak [m/s²]", self.peak)
        check_number("bump start [s]", self.start)
        _check_positive("bump duration", self.duration, "s")
        if self.duration < BUMP_SHORTEST:
            raise InputError(
                f"bump duration is {self.duration:g} s, shorter than the plausible "
                f"{BUMP_SHORTEST:g} s (half a period at {FREQUENCY:g} Hz, a hull's fastest)"
            )
        _check_plausible(self)

    def channels(self, t: np.ndarray) -> Channels:
        w = math.pi / self.duration
        tau = np.clip(t - self.start, 0.0, self.duration)
        after = np.maximum(t - self.start - self.duration, 0.0)
        a = np.where((t >= self.start) & (t <= self.start + self.duration), 1.0, 0.0)
        acceleration = a * self.peak * np.sin(w * tau)
        rate = self.peak / w * (1.0 - np.cos(w * tau))
        value = self.peak / w * (tau - np.sin(w * tau) / w) + 2.0 * self.peak / w * after
        return _channel(t, 2, value, rate, acceleration)

    def peaks(self) -> np.ndarray:
        """The peaks (:meth:`BoundedProfile.peaks`); z grows without bound after the pulse."""
        rise = 2.0 * abs(self.peak) * self.duration / math.pi
        return _peaks(2, math.inf, rise, abs(self.peak))

    def describe(self) -> str:
        return (
            f"bump: half-sine {self.peak / G:g} g over {self.duration * 1e3:g} ms "
            f"from t = {self.start:g} s"
        )


@dataclass(frozen=True)
class Recoil:
    """The hull rocking in pitch after a shot: a decaying oscillation that starts at ``start``,

    θ = −amplitude e^(−ζ ω_n τ) sin(ω_d τ),  τ = t − start ≥ 0 (0 before),  ω_d = ω_n √(1 − ζ²),

    nose up first (the recoil force acts behind and above the hull's centre of gravity). The
    shot's impulse itself is the step in θ̇ at τ = 0, which samples do not resolve.

    Defaults (assumed): a pitch natural frequency of 1 Hz (a tracked hull on its suspension,
    cf. :class:`Terrain`), a damping ratio of 0.2 (hydraulic shock absorbers; 0.2–0.4 is usual
    for ride), and 2° of rocking amplitude.

    Attributes:
        amplitude: [rad]. frequency: ω_n / 2π [Hz], at most
            :data:`~feeder.chain.model.hull.FREQUENCY`. damping: ζ, 0 ≤ ζ < 1. start: [s].
    """

    amplitude: float = math.radians(2.0)
    frequency: float = 1.0
    damping: float = 0.2
    start: float = 0.0
    ANGLES: ClassVar[tuple[str, ...]] = ("amplitude",)

    def __post_init__(self):
        check_number("recoil amplitude [rad]", self.amplitude)
        check_number("recoil start [s]", self.start)
        _check_frequency("recoil frequency", self.frequency)
        if not 0.0 <= check_number("recoil damping", self.damping) < 1.0:
            raise InputError(f"recoil damping ratio must be in [0, 1), got {self.damping}")
        _check_plausible(self)

    def channels(self, t: np.ndarray) -> Channels:
        wn = 2.0 * math.pi * self.frequency
        sigma = self.damping * wn
        wd = wn * math.sqrt(1.0 - self.damping**2)
        tau = np.maximum(t - self.start, 0.0)
        on = (t >= self.start).astype(float)
        e, s, c = np.exp(-sigma * tau), np.sin(wd * tau), np.cos(wd * tau)
        k = -self.amplitude * on
        value = k * e * s
        rate = k * e * (wd * c - sigma * s)
        acceleration = k * e * ((sigma**2 - wd**2) * s - 2.0 * sigma * wd * c)
        return _channel(t, 4, value, rate, acceleration)

    def peaks(self) -> np.ndarray:
        """The peaks (:meth:`BoundedProfile.peaks`): with σ² + ω_d² = ω_n², the rate's
        factor (ω_d cos − σ sin) is at most ω_n and the acceleration's at most ω_n²."""
        wn = 2.0 * math.pi * self.frequency
        amplitude = abs(self.amplitude)
        return _peaks(4, amplitude, amplitude * wn, amplitude * wn**2)

    def describe(self) -> str:
        return (
            f"recoil rocking: {math.degrees(self.amplitude):g}° at {self.frequency:g} Hz, "
            f"damping {self.damping:g}, from t = {self.start:g} s"
        )


PROFILES = {"terrain": Terrain, "bump": Bump, "recoil": Recoil}
"""The named profiles of the hull's motion (a mechanism file's ``[[base.profile]]`` type, the
command line's ``--base-motion NAME``)."""
