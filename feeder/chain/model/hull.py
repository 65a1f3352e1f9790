"""A hull's motion channels and the plausible limits of a ground vehicle's hull on them.

The hull's motion (:mod:`feeder.chain.model.channels`) is six channels against time, each with its
rate and acceleration. A profile or table that knows its *peaks* — a bound on the magnitude of
each channel's value, rate and acceleration, an array (3, 6): rows value, rate, acceleration;
columns :data:`CHANNELS` — is refused when a peak passes its limit (:func:`implausible`): a hull
does not stand on a 60° slope, ride at 1 MHz or accelerate at 1e12 m/s², and such an input is a
unit mistake (degrees given as radians, millimetres as metres) that would otherwise give loads of
1e14 N without a word. The limits are assumed for any tracked or wheeled hull, each with the
numbers behind it.
"""

from __future__ import annotations

import math

import numpy as np

from ...exceptions import InputError
from ...validation import LIMIT_SLACK

CHANNELS = ("x", "y", "z", "roll", "pitch", "yaw")
"""The hull motion's channels, in order (:mod:`feeder.chain.model.channels`)."""

UNITS = ("m", "m", "m", "rad", "rad", "rad")
"""Their units."""

LEVELS = ("", " rate", " acceleration")
"""A channel's value, rate and acceleration: the rows of a profile's peaks."""

G = 9.81
"""Standard gravity [m/s²], for the profiles' defaults stated in g."""

ATTITUDE = math.radians(45.0)
"""Largest plausible |roll| and |pitch| of a hull [rad] (45°). A vehicle slides down a slope
steeper than its friction angle, arctan μ with μ ≤ 1 for tracks or tyres on dry ground (45°), and
tips over sideways near arctan(half the track width / centre-of-gravity height), about 40–50° for
tracked hulls; vehicles are specified for 60 % gradients (31°) and 30–40 % side slopes
(17–22°). Assumed (no M77 data): beyond it, a value in degrees given as radians, or slopes
added twice."""

ANGULAR_RATE = 5.0
"""Largest plausible |roll|, |pitch| and |yaw| rate of a hull [rad/s] (286°/s). A tracked
vehicle pivot-turns at up to about 1 rad/s; the ride's pitch and roll rates are a few tenths of
a rad/s (:class:`~feeder.chain.model.profiles.Terrain`'s defaults: 0.4 rad/s). Assumed, five times
the fastest of these."""

ACCELERATION = 40.0 * G
"""Largest plausible |x|, |y| or |z| acceleration of a hull [m/s²] (40 g): the functional shock
that MIL-STD-810H, Method 516.8, Procedure I, applies to ground equipment (40 g over 11 ms); a
hull's rigid-body acceleration stays below what its equipment is tested for (gunfire shock,
Method 519, is the structure's vibration, not the hull's motion)."""

ANGULAR_ACCELERATION = 200.0
"""Largest plausible |roll|, |pitch| or |yaw| acceleration of a hull [rad/s²]: :data:`ACCELERATION`
(392 m/s²) at a hull's end, about 2 m from its pitch centre (392 / 2 ≈ 200). Assumed; the ride's
is about 3 rad/s² (:class:`~feeder.chain.model.profiles.Terrain`'s defaults)."""

FREQUENCY = 20.0
"""Highest plausible frequency of a hull's motion [Hz]: a hull's sprung mass rides at 1–1.5 Hz
and its road wheels hop at about 10–15 Hz (J. Y. Wong, Theory of Ground Vehicles, 4th ed.,
ch. 7); faster motion is the structure's vibration, not a rigid base's. Assumed margin: 20 Hz."""

HEAVE = 1.0
"""Largest plausible heave amplitude of a ride [m] (:class:`~feeder.chain.model.profiles.Terrain`):
a hull rides on road wheels that travel a few hundred mm. Assumed, generous: a heave meant in mm
(40 for 0.04 m) is refused."""

PHASE = 2.0 * math.pi
"""Largest |phase| of a periodic profile [rad] (one turn): a larger one is the same as one
within, and likely degrees given as radians."""

BUMP_SHORTEST = 0.5 / FREQUENCY
"""Shortest plausible bump [s] (25 ms): a half-sine pulse of duration d is half a period of a
wave at 1 / (2 d), which :data:`FREQUENCY` bounds."""


def limit(level: int, channel: int) -> tuple[float, str]:
    """The plausible bound on a channel's (index in :data:`CHANNELS`) value (level 0), rate (1)
    or acceleration (2) [:func:`unit_of`], and why, for messages; inf where there is none (a
    position, a heading, a translational speed)."""
    if channel < 3:
        if level == 2:
            return ACCELERATION, "MIL-STD-810H's 40 g shock for ground equipment"
        return math.inf, ""
    if level == 0:
        if channel < 5:
            return ATTITUDE, "steeper than a vehicle stands on"
        return math.inf, ""
    if level == 1:
        return ANGULAR_RATE, "faster than a hull turns or rocks"
    return ANGULAR_ACCELERATION, "40 g at 2 m from the hull's pitch centre"


def unit_of(level: int, channel: int) -> str:
    """The unit of a channel's value (level 0), rate (1) or acceleration (2): "rad/s²", …"""
    return UNITS[channel] + ("", "/s", "/s²")[level]


def show(value: float, unit: str) -> str:
    """``value`` [unit] for a message; an angle in radians also in degrees: "0.5 rad (28.65°)"."""
    text = f"{value:.4g} {unit}"
    if unit.startswith("rad"):
        text += f" ({math.degrees(value):.4g}°{unit[3:]})"
    return text


def implausible(peaks: np.ndarray) -> tuple[int, int] | None:
    """(level, channel) of the first of the bounds ``peaks`` (3, 6) (module docstring) past its
    plausible :func:`limit`; None if none."""
    for level, channel in np.ndindex(3, 6):
        if peaks[level, channel] > limit(level, channel)[0] + LIMIT_SLACK:
            return level, channel
    return None


def beyond(level: int, channel: int) -> str:
    """A channel's limit for a message: "beyond the plausible ±5 rad/s (286.5°/s) (why)"."""
    bound, reason = limit(level, channel)
    return f"beyond the plausible ±{show(bound, unit_of(level, channel))} ({reason})"


def reaches(peaks: np.ndarray, level: int, channel: int) -> str:
    """A channel's peak against its limit, for a message: "pitch rate reaches ±30 rad/s
    (1719°/s), beyond the plausible ±5 rad/s (286.5°/s) (…)"."""
    peak = show(peaks[level, channel], unit_of(level, channel))
    return f"{CHANNELS[channel]}{LEVELS[level]} reaches ±{peak}, {beyond(level, channel)}"


def check_at_most(what: str, value: float, bound: float, unit: str, reason: str) -> None:
    """Raise :class:`InputError` if |value| [unit] passes ``bound`` [unit] (``reason``: why it
    is the limit, for the message)."""
    if abs(value) > bound + LIMIT_SLACK:
        raise InputError(
            f"{what} is {show(value, unit)}, beyond the plausible {show(bound, unit)} ({reason})"
        )
