"""The base's motion: a mechanism on a moving vehicle, a slope, a hull that rocks after a shot.

The mechanism's base (the root link of its tree, and every frame on it) is fixed to a vehicle
whose motion is prescribed. Two sets of axes:

* **vehicle axes** (ISO 8855): x forward, y left, z up, fixed to the hull. The mechanism file
  says which of the model's axes points forward (``forward``, default the model's x); up is
  against the model's gravity; left = up × forward.
* **level axes**: the vehicle axes of the hull standing level at rest (an inertial frame).

The hull's motion is six channels against time, each with its rate and acceleration:

========  ======  ===========================================================================
channel   unit    meaning
========  ======  ===========================================================================
x, y, z   m       translation of the mount (the model's origin) along the level axes (z: heave)
roll      rad     φ, right-handed about x (forward): positive lowers the right side
pitch     rad     θ, right-handed about y (left): positive lowers the nose (ISO 8855)
yaw       rad     ψ, right-handed about z (up): positive turns left
========  ======  ===========================================================================

The hull's attitude is R = R_z(ψ) R_y(θ) R_x(φ) (vehicle axes → level axes); its angular
velocity in the vehicle's axes (the Z-Y-X kinematic equations),

    ω = [φ̇ − ψ̇ sin θ,  θ̇ cos φ + ψ̇ cos θ sin φ,  −θ̇ sin φ + ψ̇ cos θ cos φ],

and its angular acceleration α = dω/dt (the same in either axes: ω × ω = 0). Channels of several
profiles add (:class:`BaseMotion`): a slope with a ride over terrain, say.

Profiles (:class:`Slope`, :class:`Terrain`, :class:`Bump`, :class:`Recoil`) have defaults that
are *assumed* (no measured hull data is published for the M77): each says why.

A hull is a ground vehicle on its suspension: the profiles and hull tables refuse a motion no
hull makes (the limits of :mod:`feeder.chain.model.hull`: a 45° slope, 5 rad/s, 200 rad/s²,
40 g, 20 Hz), each alone when it is made and all of them together in :class:`BaseMotion` (a
slope plus a ride plus a table), from the bounds of their channels (:class:`BoundedProfile`). A
profile written in code without ``peaks`` (any object with ``channels`` and ``describe``) is the
programmer's: its channels are taken as they are.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import ClassVar, Protocol, runtime_checkable

import numpy as np

from ...exceptions import InputError
from ...validation import check_finite, check_number
from .forces import Table
from .hull import (
    BUMP_SHORTEST,
    CHANNELS,
    FREQUENCY,
    HEAVE,
    PHASE,
    G,
    beyond,
    check_at_most,
    implausible,
    limit,
    reaches,
    show,
    unit_of,
)

PERPENDICULAR = 1e-6
"""Largest accepted |cos| between the forward axis and gravity: forward must be horizontal."""


@dataclass(frozen=True)
class Channels:
    """The six channels (module docstring) at N times: value, rate, acceleration, each (N, 6)."""

    value: np.ndarray
    rate: np.ndarray
    acceleration: np.ndarray

    def __add__(self, other: Channels) -> Channels:
        return Channels(
            self.value + other.value,
            self.rate + other.rate,
            self.acceleration + other.acceleration,
        )


def _zero(t: np.ndarray) -> Channels:
    return Channels(*(np.zeros((t.size, 6)) for _ in range(3)))


def _channel(t: np.ndarray, index: int, value, rate, acceleration) -> Channels:
    out = _zero(t)
    out.value[:, index], out.rate[:, index], out.acceleration[:, index] = (
        value,
        rate,
        acceleration,
    )
    return out


@runtime_checkable
class HullProfile(Protocol):
    """A hull motion: its channels at the times t [s], (N,)."""

    def channels(self, t: np.ndarray) -> Channels: ...

    def describe(self) -> str: ...


@runtime_checkable
class BoundedProfile(HullProfile, Protocol):
    """A hull motion that knows its peaks (every profile here, a hull table): checked against
    the plausible limits (:mod:`feeder.chain.model.hull`) alone and with the others."""

    def peaks(self) -> np.ndarray:
        """Bounds on the magnitudes of each channel's value, rate and acceleration (3, 6): rows
        value, rate, acceleration; columns :data:`CHANNELS` [m, rad; per s; per s²]."""
        ...


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
    """The hull standing still on a slope: constant pitch and roll [rad] (module docstring's
    signs: a positive pitch lowers the nose, a positive roll the right side), each within
    ±:data:`~feeder.chain.model.hull.ATTITUDE`."""

    pitch: float = 0.0
    roll: float = 0.0
    ANGLES: ClassVar[tuple[str, ...]] = ("pitch", "roll")

    def __post_init__(self):
        for name in ("pitch", "roll"):
            check_number(f"slope {name} [rad]", getattr(self, name))
        _check_plausible(self)

    def channels(self, t: np.ndarray) -> Channels:
        out = _zero(t)
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
        out = _zero(t)
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


COLUMNS = tuple(f"{prefix}{channel}" for prefix in ("", "v_", "a_") for channel in CHANNELS)
"""A hull table's 18 columns, in order: the channels' values, rates (``v_``) and accelerations
(``a_``), angles in radians."""


@dataclass(frozen=True)
class HullTable:
    """The hull's measured or simulated motion: a :class:`Table` of the 18 :data:`COLUMNS`
    against time (module docstring's units), linearly interpolated; times outside the table are
    refused, and so are values past the plausible limits (:mod:`feeder.chain.model.hull`).

    Attributes:
        table: Times t [s] (K,) and values (K, 18).
        columns: The columns' names as the user gave them, for messages (a file's ``roll_deg``,
            converted to radians in the table); default :data:`COLUMNS`.
    """

    table: Table
    columns: tuple[str, ...] = field(default=COLUMNS, compare=False)

    def __post_init__(self):
        if not isinstance(self.table, Table):
            raise InputError(
                f"a hull table is a Table (feeder.chain.model.forces: t [s], values (K, 18)), "
                f"got {self.table!r}"
            )
        if self.table.values.shape[1] != 18:
            raise InputError(
                f"{self.table.source}: a hull table has 18 columns (value, rate, acceleration "
                f"of {', '.join(CHANNELS)}), got {self.table.values.shape[1]}"
            )
        names = self.columns
        if (
            not isinstance(names, tuple)
            or len(names) != 18
            or not all(isinstance(name, str) for name in names)
        ):
            raise InputError(f"{self.table.source}: columns must be 18 names, got {names!r}")
        self._check_plausible()

    def _check_plausible(self) -> None:
        """Raise :class:`InputError` if a column passes its plausible limit: its name as given,
        the value and its time, and for an angle in radians that would be plausible in degrees,
        the column's ``_deg`` form."""
        excess = implausible(self.peaks())
        if excess is None:
            return
        level, channel = excess
        k = 6 * level + channel
        row = int(np.argmax(np.abs(self.table.values[:, k])))
        value = float(self.table.values[row, k])
        hint = ""
        degrees = abs(math.radians(value)) <= limit(level, channel)[0]
        if channel >= 3 and self.columns[k] == COLUMNS[k] and degrees:
            hint = f"; if it holds degrees, name the column {COLUMNS[k]}_deg (angles are radians)"
        raise InputError(
            f"{self.table.source}: {self.columns[k]} = {show(value, unit_of(level, channel))} at "
            f"t = {self.table.t[row]:g} s is {beyond(level, channel)}{hint}"
        )

    def channels(self, t: np.ndarray) -> Channels:
        lo, hi = self.table.t[0], self.table.t[-1]
        if t.size and (t.min() < lo or t.max() > hi):
            raise InputError(
                f"{self.table.source}: the hull motion covers t = {lo:g} … {hi:g} s; the motion "
                f"asks for {t.min():g} … {t.max():g} s"
            )
        values = np.column_stack(
            [np.interp(t, self.table.t, column) for column in self.table.values.T]
        )
        return Channels(values[:, :6], values[:, 6:12], values[:, 12:])

    def peaks(self) -> np.ndarray:
        """The peaks (:meth:`BoundedProfile.peaks`): the largest |entry| of each column (the
        table is interpolated linearly between its rows)."""
        return np.abs(self.table.values).max(axis=0).reshape(3, 6)

    def describe(self) -> str:
        return f"hull motion table {self.table.source}"


PROFILES = {"terrain": Terrain, "bump": Bump, "recoil": Recoil}
"""The named profiles of the hull's motion (a mechanism file's ``[[base.profile]]`` type, the
command line's ``--base-motion NAME``)."""


@dataclass(frozen=True)
class BaseState:
    """The base's motion at N times, in the model's axes as they move with the hull.

    Attributes:
        rotation: The model's axes now in its level ones (N, 3, 3): a vector w in the moving
            axes is ``rotation @ w`` in the level axes.
        position: The model's origin [m] in the level model axes, (N, 3) (zero at rest).
        omega, alpha: Angular velocity [rad/s] and acceleration [rad/s²] of the base, (N, 3).
        velocity, acceleration: Velocity [m/s] and acceleration [m/s²] of the model's origin,
            (N, 3).
        gravity: Gravity [m/s²], (N, 3).
    """

    rotation: np.ndarray
    position: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    gravity: np.ndarray

    def samples(self, index: slice | np.ndarray) -> BaseState:
        """The state at some of the samples."""
        return BaseState(*(getattr(self, f.name)[index] for f in dataclasses.fields(self)))

    @property
    def moving(self) -> bool:
        """Whether the base turns or accelerates (a slope alone only tilts gravity)."""
        return bool(np.any(self.omega) or np.any(self.alpha) or np.any(self.acceleration))


def attitude(channels: Channels) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The hull's attitude R (N, 3, 3), angular velocity ω and acceleration α (N, 3), vehicle
    axes, from its roll, pitch and yaw (module docstring)."""
    phi, theta, psi = (channels.value[:, k] for k in (3, 4, 5))
    dphi, dtheta, dpsi = (channels.rate[:, k] for k in (3, 4, 5))
    ddphi, ddtheta, ddpsi = (channels.acceleration[:, k] for k in (3, 4, 5))
    sf, cf, st, ct, sp, cp = (
        np.sin(phi),
        np.cos(phi),
        np.sin(theta),
        np.cos(theta),
        np.sin(psi),
        np.cos(psi),
    )
    rotation = np.empty((phi.size, 3, 3))
    rotation[:, 0] = np.column_stack([cp * ct, cp * st * sf - sp * cf, cp * st * cf + sp * sf])
    rotation[:, 1] = np.column_stack([sp * ct, sp * st * sf + cp * cf, sp * st * cf - cp * sf])
    rotation[:, 2] = np.column_stack([-st, ct * sf, ct * cf])
    omega = np.column_stack(
        [dphi - dpsi * st, dtheta * cf + dpsi * ct * sf, -dtheta * sf + dpsi * ct * cf]
    )
    alpha = np.column_stack(
        [
            ddphi - ddpsi * st - dpsi * dtheta * ct,
            ddtheta * cf
            - dtheta * dphi * sf
            + ddpsi * ct * sf
            - dpsi * dtheta * st * sf
            + dpsi * dphi * ct * cf,
            -ddtheta * sf
            - dtheta * dphi * cf
            + ddpsi * ct * cf
            - dpsi * dtheta * st * cf
            - dpsi * dphi * ct * sf,
        ]
    )
    return rotation, omega, alpha


def _check_profiles(profiles: object) -> tuple[HullProfile, ...]:
    """``profiles`` as a tuple, if it is a list or tuple of hull profiles (objects with
    ``channels`` and ``describe``), else raise :class:`InputError` naming the argument."""
    kinds = "Slope, Terrain, Bump, Recoil, HullTable or objects with channels(t) and describe()"
    if not isinstance(profiles, list | tuple):
        one = " (one profile: (profile,))" if isinstance(profiles, HullProfile) else ""
        raise InputError(
            f"BaseMotion profiles must be a list or tuple of {kinds}, got {profiles!r}{one}"
        )
    for index, profile in enumerate(profiles):
        if not isinstance(profile, HullProfile) or isinstance(profile, type):
            raise InputError(
                f"BaseMotion profiles[{index}] must be one of {kinds}, got {profile!r}"
            )
    return tuple(profiles)


@dataclass(frozen=True)
class BaseMotion:
    """The base's prescribed motion: the sum of the profiles' channels, with the vehicle's
    forward axis in the model's axes.

    Attributes:
        profiles: A list or tuple of :class:`Slope`, :class:`Terrain`, :class:`Bump`,
            :class:`Recoil`, :class:`HullTable` (or any object with ``channels(t)`` and
            ``describe()``); together within the plausible limits (:mod:`feeder.chain.model.hull`:
            the sum of the peaks of those that have them, :class:`BoundedProfile`).
        forward: The vehicle's forward axis in the model's axes (3,), horizontal.

    Raises:
        InputError: Profiles that are not a list or tuple of profiles, profiles whose motions
            together pass a plausible limit (e.g. two slopes of 30°), a bad forward axis.
    """

    profiles: tuple[HullProfile, ...] = ()
    forward: tuple[float, float, float] = (1.0, 0.0, 0.0)

    def __post_init__(self):
        object.__setattr__(self, "profiles", _check_profiles(self.profiles))
        forward = check_finite("base forward axis", self.forward)
        if forward.shape != (3,) or not np.linalg.norm(forward) > 0.0:
            raise InputError(f"the base's forward axis must be 3 numbers, not zero: {forward}")
        unit = forward / np.linalg.norm(forward)
        object.__setattr__(self, "forward", tuple(float(x) for x in unit))
        bounded = [p for p in self.profiles if isinstance(p, BoundedProfile)]
        peaks = sum((p.peaks() for p in bounded), np.zeros((3, 6)))
        excess = implausible(peaks)
        if excess is not None:
            raise InputError(
                f"the base's profiles together ({'; '.join(p.describe() for p in bounded)}): "
                f"their {reaches(peaks, *excess)}"
            )

    @property
    def timed(self) -> bool:
        """Whether the motion varies in time (anything but slopes)."""
        return any(not isinstance(p, Slope) for p in self.profiles)

    def vehicle_axes(self, gravity: np.ndarray) -> np.ndarray:
        """V (3, 3): the vehicle's forward, left and up axes (columns) in the model's axes, up
        against ``gravity`` [m/s²] (3,) (the model's, standing level).

        Raises:
            InputError: No gravity (up is unknown), or a forward axis that is not horizontal.
        """
        g = float(np.linalg.norm(gravity))
        if not g > 0.0:
            raise InputError("a moving base needs gravity: up is the direction against it")
        up = -np.asarray(gravity, dtype=float) / g
        forward = np.array(self.forward)
        if abs(forward @ up) > PERPENDICULAR:
            raise InputError(
                f"the base's forward axis {forward.tolist()} must be horizontal (perpendicular "
                f"to gravity {(-g * up).tolist()} m/s²)"
            )
        return np.column_stack([forward, np.cross(up, forward), up])

    def state(self, t: np.ndarray, gravity: np.ndarray) -> BaseState:
        """The base's motion (:class:`BaseState`) at the times t [s] (N,), for the model's
        standing gravity [m/s²] (3,)."""
        t = np.asarray(t, dtype=float)
        channels = _zero(t)
        for profile in self.profiles:
            channels = channels + profile.channels(t)
        axes = self.vehicle_axes(gravity)
        rotation, omega, alpha = attitude(channels)
        rotation = axes @ rotation @ axes.T
        level_gravity = np.asarray(gravity, dtype=float)
        to_model = np.swapaxes(rotation, 1, 2)  # level model axes → moving model axes
        velocity = np.einsum("nij,nj->ni", to_model, channels.rate[:, :3] @ axes.T)
        acceleration = np.einsum("nij,nj->ni", to_model, channels.acceleration[:, :3] @ axes.T)
        return BaseState(
            rotation=rotation,
            position=channels.value[:, :3] @ axes.T,  # level vehicle axes → level model axes
            omega=omega @ axes.T,
            alpha=alpha @ axes.T,
            velocity=velocity,
            acceleration=acceleration,
            gravity=to_model @ level_gravity,
        )

    def describe(self) -> str:
        """One line for summaries."""
        if not self.profiles:
            return "standing level"
        return "; ".join(profile.describe() for profile in self.profiles)
