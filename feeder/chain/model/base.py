"""The base's motion: a mechanism on a moving vehicle, a slope, a hull that rocks after a shot.

The mechanism's base (the root link of its tree, and every frame on it) is fixed to a vehicle
whose motion is prescribed: six channels against time (:mod:`feeder.chain.model.channels`: the
vehicle and level axes, x, y, z, roll, pitch, yaw), given by profiles
(:mod:`feeder.chain.model.profiles`, :mod:`feeder.chain.model.hull_table`). The mechanism file
says which of the model's axes points forward (``forward``, default the model's x); up is against
the model's gravity; left = up × forward.

The hull's attitude is R = R_z(ψ) R_y(θ) R_x(φ) (vehicle axes → level axes); its angular
velocity in the vehicle's axes (the Z-Y-X kinematic equations),

    ω = [φ̇ − ψ̇ sin θ,  θ̇ cos φ + ψ̇ cos θ sin φ,  −θ̇ sin φ + ψ̇ cos θ cos φ],

and its angular acceleration α = dω/dt (the same in either axes: ω × ω = 0). Channels of several
profiles add (:class:`BaseMotion`): a slope with a ride over terrain, say.

A hull is a ground vehicle on its suspension: each profile and hull table refuses a motion no
hull makes alone (the limits of :mod:`feeder.chain.model.hull`: a 45° slope, 5 rad/s,
200 rad/s², 40 g, 20 Hz), and :class:`BaseMotion` refuses one that all of them make together (a
slope plus a ride plus a table), from the bounds of their channels
(:class:`~feeder.chain.model.channels.BoundedProfile`). A profile written in code without
``peaks`` (any object with ``channels`` and ``describe``) is the programmer's: its channels are
taken as they are.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ...exceptions import InputError
from ...validation import check_finite
from .channels import BoundedProfile, Channels, HullProfile, at_rest
from .hull import implausible, reaches
from .profiles import Slope

PERPENDICULAR = 1e-6
"""Largest accepted |cos| between the forward axis and gravity: forward must be horizontal."""


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
    # one stack per array (not a column_stack per row): a forward run asks for one time at each
    # evaluation of its equations, where numpy's per-call overhead is the cost
    rotation = np.stack(
        [cp * ct, cp * st * sf - sp * cf, cp * st * cf + sp * sf,
         sp * ct, sp * st * sf + cp * cf, sp * st * cf - cp * sf,
         -st, ct * sf, ct * cf],
        axis=-1,
    ).reshape(phi.size, 3, 3)  # fmt: skip
    omega = np.stack(
        [dphi - dpsi * st, dtheta * cf + dpsi * ct * sf, -dtheta * sf + dpsi * ct * cf], axis=-1
    )
    alpha = np.stack(
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
        ],
        axis=-1,
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
        profiles: A list or tuple of the profiles of :mod:`feeder.chain.model.profiles`
            (Slope, Terrain, Bump, Recoil), :class:`~feeder.chain.model.hull_table.HullTable`
            (or any object with ``channels(t)`` and ``describe()``); together within the
            plausible limits (:mod:`feeder.chain.model.hull`: the sum of the peaks of those that
            have them, :class:`~feeder.chain.model.channels.BoundedProfile`).
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

    def state(
        self, t: np.ndarray, gravity: np.ndarray, axes: np.ndarray | None = None
    ) -> BaseState:
        """The base's motion (:class:`BaseState`) at the times t [s] (N,), for the model's
        standing gravity [m/s²] (3,); ``axes``: :meth:`vehicle_axes` of that gravity, when the
        caller keeps them (a forward run asks for one time at each evaluation)."""
        t = np.asarray(t, dtype=float)
        channels = at_rest(t)
        for profile in self.profiles:
            channels = channels + profile.channels(t)
        axes = self.vehicle_axes(gravity) if axes is None else axes
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
