"""Force elements: what acts on a mechanism besides its actuators, the closures and gravity.

Each element acts on two bodies (or one body and the ground), equal and opposite, so each has a
reaction on both. These classes are the inputs: checked, frozen, with their laws in time and in
their own coordinate; the dynamics (:mod:`feeder.chain.dynamics.elements`) bind each kind to a
chain as a class of its own that turns it into generalized forces for the forward runs and into
body wrenches for the inverse dynamics and the joint reactions. SI units throughout; vectors in
world axes.

* :class:`Spring` — point-to-point spring–damper–actuator between the origins of two frames.
  Its *tension* T = k (ℓ − ℓ₀) + c ℓ̇ − F(t) [N] pulls the two frames together (T < 0 pushes
  them apart); F(t) is the actuator's push (extending), a constant, a function of time or a
  :class:`Table`.
* :class:`Cylinder` — a hydraulic cylinder between two frames (cap end first): its push is
  F = p_cap A_cap − p_rod A_ann with A_cap = π D²/4, A_ann = π (D² − d²)/4 (bore D, rod d);
  pressures [Pa] constant, functions of time or tables; optional damping c [N·s/m].
* :class:`JointSpring` — a torsion (revolute joint) or linear (prismatic joint) spring–damper:
  it resists with τ = τ₀ + k (q − q₀) + c q̇ [N·m or N] (τ₀ the preload at q₀), acting on the
  joint's child body and, opposite, on its parent.
* :class:`Load` — a force [N] and a moment [N·m] on a frame's body, at the frame's origin,
  world axes: constant, or a :class:`Table` of six columns (fx, fy, fz, mx, my, mz) in time.

Gravity is the model's (``gravity`` in the mechanism file).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from ...exceptions import InputError
from ...validation import check_finite, check_number

TimeFunction = Callable[[float], float]
"""A scalar function of time t [s]."""


@dataclass(frozen=True)
class Table:
    """Values against time, linearly interpolated.

    Attributes:
        t: Increasing times [s], (K,), K ≥ 2.
        values: (K, m).
        source: Where the table comes from (a file name), for messages.
    """

    t: np.ndarray
    values: np.ndarray
    source: str = "table"

    def __post_init__(self):
        t = check_finite(f"{self.source}: t", self.t)
        values = check_finite(f"{self.source}: values", self.values)
        if values.ndim == 1:
            values = values[:, None]
        if t.ndim != 1 or t.size < 2 or np.any(np.diff(t) <= 0.0) or values.shape[0] != t.size:
            raise InputError(
                f"{self.source}: needs at least two rows at increasing times, one value row each "
                f"(got t {t.shape}, values {values.shape})"
            )
        object.__setattr__(self, "t", t)
        object.__setattr__(self, "values", values)

    def __call__(self, time: float) -> np.ndarray:
        """The values (m,) at ``time`` [s] (within the table's range: :meth:`check_covers`)."""
        k = int(np.clip(np.searchsorted(self.t, time) - 1, 0, self.t.size - 2))
        w = (time - self.t[k]) / (self.t[k + 1] - self.t[k])
        return (1.0 - w) * self.values[k] + w * self.values[k + 1]

    def check_covers(self, start: float, end: float) -> None:
        """Raise :class:`InputError` unless the table's times cover [start, end] [s]."""
        if start < self.t[0] - 1e-12 or end > self.t[-1] + 1e-12:
            raise InputError(
                f"{self.source} covers t = {self.t[0]:g}…{self.t[-1]:g} s, the run "
                f"{start:g}…{end:g} s: extend the table (values are not extrapolated)"
            )


Profile = float | Table | TimeFunction
"""A scalar input in time: a constant, a one-column :class:`Table`, or a function of t [s]."""


def profile_value(profile: Profile, time: float) -> float:
    """The value of a :data:`Profile` at ``time`` [s]."""
    if isinstance(profile, Table):
        return float(profile(time)[0])
    if callable(profile):
        return float(profile(time))
    return float(profile)


def _tables(*profiles: Profile | None) -> tuple[Table, ...]:
    """The :class:`Table` s among ``profiles``."""
    return tuple(profile for profile in profiles if isinstance(profile, Table))


def _check_profile(name: str, profile: Profile) -> Profile:
    if isinstance(profile, Table):
        if profile.values.shape[1] != 1:
            raise InputError(f"{name}: a table of one value column, got {profile.values.shape[1]}")
        return profile
    if callable(profile):
        return profile
    return check_number(name, profile)


def _check_nonnegative(name: str, value: float) -> float:
    value = check_number(name, value)
    if value < 0.0:
        raise InputError(f"{name} must be ≥ 0, got {value!r}")
    return value


@dataclass(frozen=True)
class Spring:
    """Point-to-point spring–damper–actuator (module docstring).

    Attributes:
        frames: The two frames (a, b) whose origins it joins.
        stiffness: k [N/m] (≥ 0).
        rest_length: ℓ₀ [m] (≥ 0).
        damping: c [N·s/m] (≥ 0).
        force: F(t), the actuator's push [N] (:data:`Profile`).
        name: Its label in the results (default ``spring:a-b``).
    """

    frames: tuple[str, str]
    stiffness: float = 0.0
    rest_length: float = 0.0
    damping: float = 0.0
    force: Profile = 0.0
    name: str = ""

    def __post_init__(self):
        _check_frames(self.frames, "spring")
        label = self.name or f"spring:{self.frames[0]}-{self.frames[1]}"
        object.__setattr__(self, "name", label)
        for key in ("stiffness", "rest_length", "damping"):
            object.__setattr__(self, key, _check_nonnegative(f"{label} {key}", getattr(self, key)))
        object.__setattr__(self, "force", _check_profile(f"{label} force [N]", self.force))

    @property
    def timed(self) -> bool:
        """Whether its push varies in time (a table or a function of t)."""
        return callable(self.force)

    def tables(self) -> tuple[Table, ...]:
        """The tables it reads (to check that they cover a run)."""
        return _tables(self.force)

    def push(self, time: float) -> float:
        """F(t), the actuator's push [N] at ``time`` [s]."""
        return profile_value(self.force, time)


@dataclass(frozen=True)
class Cylinder:
    """Hydraulic cylinder between two frames, cap end first (module docstring).

    Attributes:
        frames: (cap end, rod end).
        bore: D [m] (> 0). rod: d [m] (0 ≤ d < D).
        pressure: Cap-side pressure [Pa] (:data:`Profile`).
        rod_pressure: Rod-side pressure [Pa] (:data:`Profile`).
        damping: c [N·s/m] (≥ 0).
        name: Its label in the results (default ``cylinder:a-b``).
    """

    frames: tuple[str, str]
    bore: float
    rod: float
    pressure: Profile = 0.0
    rod_pressure: Profile = 0.0
    damping: float = 0.0
    name: str = ""
    cap_area: float = field(init=False)
    annulus_area: float = field(init=False)
    stiffness: ClassVar[float] = 0.0
    """k [N/m]: a cylinder is a line element without a spring (its law is a spring's)."""
    rest_length: ClassVar[float] = 0.0
    """ℓ₀ [m], with no spring to rest."""

    def __post_init__(self):
        _check_frames(self.frames, "cylinder")
        label = self.name or f"cylinder:{self.frames[0]}-{self.frames[1]}"
        object.__setattr__(self, "name", label)
        bore = check_number(f"{label} bore [m]", self.bore)
        rod = _check_nonnegative(f"{label} rod [m]", self.rod)
        if not 0.0 <= rod < bore:
            raise InputError(f"{label}: needs 0 ≤ rod < bore, got rod {rod!r} m, bore {bore!r} m")
        object.__setattr__(self, "bore", bore)
        object.__setattr__(self, "rod", rod)
        object.__setattr__(self, "cap_area", math.pi * bore**2 / 4.0)
        object.__setattr__(self, "annulus_area", math.pi * (bore**2 - rod**2) / 4.0)
        for key in ("pressure", "rod_pressure"):
            object.__setattr__(
                self, key, _check_profile(f"{label} {key} [Pa]", getattr(self, key))
            )
        object.__setattr__(self, "damping", _check_nonnegative(f"{label} damping", self.damping))

    @property
    def timed(self) -> bool:
        """Whether a pressure varies in time (a table or a function of t)."""
        return callable(self.pressure) or callable(self.rod_pressure)

    def tables(self) -> tuple[Table, ...]:
        """The tables it reads (to check that they cover a run)."""
        return _tables(self.pressure, self.rod_pressure)

    def push(self, time: float) -> float:
        """F = p_cap A_cap − p_rod A_ann [N] at ``time`` [s] (extending positive)."""
        return profile_value(self.pressure, time) * self.cap_area - (
            profile_value(self.rod_pressure, time) * self.annulus_area
        )


@dataclass(frozen=True)
class JointSpring:
    """Torsion or linear spring–damper on a one-coordinate joint (module docstring).

    Attributes:
        joint: The joint's name (revolute, continuous or prismatic).
        stiffness: k [N·m/rad or N/m] (≥ 0).
        rest: q₀ [rad or m].
        damping: c [N·m·s/rad or N·s/m] (≥ 0).
        preload: τ₀ [N·m or N], its resistance at q₀.
        name: Its label in the results (default ``joint_spring:<joint>``).
    """

    joint: str
    stiffness: float = 0.0
    rest: float = 0.0
    damping: float = 0.0
    preload: float = 0.0
    name: str = ""
    timed: ClassVar[bool] = False
    """Its law does not depend on time."""

    def __post_init__(self):
        if not isinstance(self.joint, str) or not self.joint:
            raise InputError(f"a joint spring needs a joint name, got {self.joint!r}")
        label = self.name or f"joint_spring:{self.joint}"
        object.__setattr__(self, "name", label)
        for key in ("stiffness", "damping"):
            object.__setattr__(self, key, _check_nonnegative(f"{label} {key}", getattr(self, key)))
        for key in ("rest", "preload"):
            object.__setattr__(self, key, check_number(f"{label} {key}", getattr(self, key)))

    def tables(self) -> tuple[Table, ...]:
        """None: its law is constant."""
        return ()

    def resistance(self, angle: float, rate: float) -> float:
        """τ [N·m or N] at joint value ``angle`` and rate ``rate``."""
        return self.preload + self.stiffness * (angle - self.rest) + self.damping * rate

    def energy(self, angle: float) -> float:
        """Elastic energy τ₀ (q − q₀) + ½ k (q − q₀)² [J]."""
        stretch = angle - self.rest
        return self.preload * stretch + 0.5 * self.stiffness * stretch**2

    def power(self, rate: float) -> float:
        """Power [W] of its damper on the mechanism."""
        return -self.damping * rate * rate


@dataclass(frozen=True)
class Load:
    """A force and a moment on a frame's body at the frame's origin, world axes.

    Attributes:
        frame: The frame.
        force: [N] (3,). moment: [N·m] (3,). Constant; or
        table: A :class:`Table` of six columns (fx, fy, fz, mx, my, mz) in time (then force and
            moment must be left zero).
        name: Its label in the results (default ``load:<frame>``).
    """

    frame: str
    force: tuple[float, float, float] = (0.0, 0.0, 0.0)
    moment: tuple[float, float, float] = (0.0, 0.0, 0.0)
    table: Table | None = None
    name: str = ""

    def __post_init__(self):
        if not isinstance(self.frame, str) or not self.frame:
            raise InputError(f"a load needs a frame name, got {self.frame!r}")
        label = self.name or f"load:{self.frame}"
        object.__setattr__(self, "name", label)
        wrench = []
        for key in ("force", "moment"):
            value = check_finite(f"{label} {key}", getattr(self, key))
            if value.shape != (3,):
                raise InputError(f"{label}: {key} must be 3 numbers, got {getattr(self, key)!r}")
            wrench.append(value)
        constant = np.concatenate(wrench)
        if self.table is not None:
            if np.any(constant != 0.0):
                raise InputError(f"{label}: give either force/moment or a table, not both")
            if self.table.values.shape[1] != 6:
                raise InputError(f"{label}: the table needs six columns (fx fy fz mx my mz)")
        object.__setattr__(self, "force", tuple(wrench[0]))
        object.__setattr__(self, "moment", tuple(wrench[1]))

    @property
    def timed(self) -> bool:
        """Whether it varies in time (a table)."""
        return self.table is not None

    def tables(self) -> tuple[Table, ...]:
        """The tables it reads (to check that they cover a run)."""
        return _tables(self.table)

    def wrench(self, time: float) -> np.ndarray:
        """[force (3) N, moment (3) N·m] (6,), world axes, at ``time`` [s]."""
        if self.table is not None:
            return self.table(time)
        return np.array([*self.force, *self.moment])


ForceElement = Spring | Cylinder | JointSpring | Load
"""Any force element."""


def _check_frames(frames, what: str) -> None:
    if (
        not isinstance(frames, tuple | list)
        or len(frames) != 2
        or not all(isinstance(f, str) and f for f in frames)
        or frames[0] == frames[1]
    ):
        raise InputError(f"a {what} needs two distinct frame names, got {frames!r}")


def tables_of(elements: tuple[ForceElement, ...]) -> list[Table]:
    """Every :class:`Table` the elements read (to check that they cover a run)."""
    return [table for element in elements for table in element.tables()]
