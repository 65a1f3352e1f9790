"""The hull's motion as six channels against time, and the protocol a profile of it follows.

Two sets of axes:

* **vehicle axes** (ISO 8855): x forward, y left, z up, fixed to the hull (in the model's axes:
  :meth:`feeder.chain.model.base.BaseMotion.vehicle_axes`).
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

A profile (:class:`HullProfile`: the profiles of :mod:`feeder.chain.model.profiles`, a hull table
of :mod:`feeder.chain.model.hull_table`, any object with ``channels`` and ``describe``) gives the
channels at any times; the base's motion (:mod:`feeder.chain.model.base`) adds the channels of
several. One that knows its peaks (:class:`BoundedProfile`) is checked against the plausible
limits of :mod:`feeder.chain.model.hull`; one written in code without ``peaks`` is the
programmer's: its channels are taken as they are.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np


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


def at_rest(t: np.ndarray) -> Channels:
    """The channels of a hull at rest (all zero) at the times t [s], (N,)."""
    return Channels(*(np.zeros((t.size, 6)) for _ in range(3)))


@runtime_checkable
class HullProfile(Protocol):
    """A hull motion: its channels at the times t [s], (N,)."""

    def channels(self, t: np.ndarray) -> Channels: ...

    def describe(self) -> str: ...


@runtime_checkable
class BoundedProfile(HullProfile, Protocol):
    """A hull motion that knows its peaks (every profile of :mod:`feeder.chain.model.profiles`,
    a hull table): checked against the plausible limits (:mod:`feeder.chain.model.hull`) alone
    and with the others."""

    def peaks(self) -> np.ndarray:
        """Bounds on the magnitudes of each channel's value, rate and acceleration (3, 6): rows
        value, rate, acceleration; columns :data:`~feeder.chain.model.hull.CHANNELS` [m, rad;
        per s; per s²]."""
        ...
