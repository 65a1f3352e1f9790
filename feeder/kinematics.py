"""Closed-form kinematics of the feeder's cylinder–piston–arm loop, vectorised over samples.

The rod-eye pin P lies on the arm a distance d3 from its pivot A = (L1, L2) and a distance
r2 + d2 from the cylinder pivot B along the cylinder axis (eq. 44, corrected — see the errata):

    P = A + d3 (cos φ3, sin φ3) = (r2 + d2) (cos φ1, sin φ1).

So for a given arm angle φ3: r2 = |P| − d2 and φ1 = atan2(P_y, P_x). Differentiating twice
along u = (cos φ1, sin φ1) and n = (−sin φ1, cos φ1) gives the velocity and acceleration level.
The transmission angle μ is the angle between the piston axis u and the arm lever
(cos φ3, sin φ3) at the pin; the lever arm of the piston force about A is d3 sin μ, and
dr2/dφ3 = d3 sin(φ1 − φ3).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .exceptions import InputError, SingularPoseError, UnreachablePoseError, check_finite
from .parameters import FeederParameters

TRANSMISSION_BAND_DEG = (40.0, 140.0)
"""Documented band [deg] that the transmission angle stays inside over the whole elevation range
(the reference geometry achieves [43°, 137°])."""

SINGULAR_TRANSMISSION_DEG = 5.0
"""Poses with |sin μ| < sin 5° (transmission angle μ within 5° of 0° or 180°) are refused: there
the piston force needed for a given arm moment is over 11× its value at μ = 90° and grows without
bound at the toggle. The reference device stays inside [43°, 137°]."""

TRAVEL_SAMPLES = 2001
"""Arm angles at which :func:`check_travel` checks a parameter set (≤ 0.05° apart over 94°)."""


@dataclass(frozen=True)
class LoopState:
    """Dependent coordinates of the loop and their derivatives; arrays of shape (N,).

    Attributes:
        phi1, dphi1, ddphi1: Cylinder angle [rad], rate [rad/s], acceleration [rad/s²].
        r2, dr2, ddr2: Piston position [m], velocity [m/s], acceleration [m/s²].
    """

    phi1: np.ndarray
    r2: np.ndarray
    dphi1: np.ndarray
    dr2: np.ndarray
    ddphi1: np.ndarray
    ddr2: np.ndarray


def pin_position(p: FeederParameters, phi3: np.ndarray) -> np.ndarray:
    """Rod-eye pin position P (2, N) [m] in the world x-y plane for arm angles φ3 [rad]."""
    phi3 = np.asarray(phi3, dtype=float)
    return np.array([p.L1 + p.d3 * np.cos(phi3), p.L2 + p.d3 * np.sin(phi3)])


def check_reachable(p: FeederParameters, phi3: np.ndarray) -> np.ndarray:
    """Return φ3 as an array, or raise if the loop cannot reach it.

    Raises:
        InputError: NaN or infinite φ3.
        UnreachablePoseError: φ3 outside the arm's end stops, a piston position outside the
            cylinder's stroke [r2_min, r2_max], or a cylinder angle outside its swing
            [phi1_min, phi1_max] (the URDF's joint limits).
    """
    phi3 = check_finite("phi3", phi3)
    pin_xy = pin_position(p, phi3)
    r2 = np.linalg.norm(pin_xy, axis=0) - p.d2
    phi1 = np.arctan2(pin_xy[1], pin_xy[0])
    deg = math.degrees
    if (k := _first_outside(phi3, p.phi3_min, p.phi3_max)) is not None:
        raise UnreachablePoseError(
            f"arm angle φ3 = {deg(np.ravel(phi3)[k]):.3f}° is outside the arm's end stops "
            f"[{deg(p.phi3_min):.1f}°, {deg(p.phi3_max):.1f}°]"
        )
    if (k := _first_outside(r2, p.r2_min, p.r2_max)) is not None:
        raise UnreachablePoseError(
            f"arm angle φ3 = {deg(np.ravel(phi3)[k]):.3f}° needs piston position "
            f"r2 = {np.ravel(r2)[k]:.4f} m, outside the stroke [{p.r2_min:.4f}, {p.r2_max:.4f}] m"
        )
    if (k := _first_outside(phi1, p.phi1_min, p.phi1_max)) is not None:
        raise UnreachablePoseError(
            f"arm angle φ3 = {deg(np.ravel(phi3)[k]):.3f}° needs cylinder angle "
            f"φ1 = {deg(np.ravel(phi1)[k]):.3f}°, outside its swing "
            f"[{deg(p.phi1_min):.1f}°, {deg(p.phi1_max):.1f}°]"
        )
    return phi3


def _first_outside(values: np.ndarray, low: float, high: float) -> int | None:
    """Flat index of the first value outside [low, high] (1e-12 slack for rounding), or None."""
    outside = np.flatnonzero(np.ravel((values < low - 1e-12) | (values > high + 1e-12)))
    return int(outside[0]) if outside.size else None


def _check_rate(name: str, value: np.ndarray | float, phi3: np.ndarray) -> np.ndarray:
    """``value`` as a float array: a scalar, or one entry per arm angle (φ3's shape)."""
    rate = check_finite(name, value)
    if rate.shape not in ((), phi3.shape):
        raise InputError(
            f"{name} must be a scalar or have the shape of phi3 {phi3.shape}, got {rate.shape}"
        )
    return rate


def dependent_coordinates(
    p: FeederParameters,
    phi3: np.ndarray,
    dphi3: np.ndarray | float = 0.0,
    ddphi3: np.ndarray | float = 0.0,
) -> LoopState:
    """φ1, r2 and their first two time derivatives from φ3, φ̇3, φ̈3 (closed form).

    Args:
        p: Device parameters.
        phi3: Arm angle(s) [rad], shape (N,) or scalar.
        dphi3: Arm rate(s) [rad/s].
        ddphi3: Arm acceleration(s) [rad/s²].

    Raises:
        InputError: NaN/inf, or rates whose shape is neither scalar nor φ3's.
        UnreachablePoseError: See :func:`check_reachable`.
    """
    phi3 = check_reachable(p, phi3)
    dphi3 = _check_rate("dphi3", dphi3, phi3)
    ddphi3 = _check_rate("ddphi3", ddphi3, phi3)
    pin_xy = pin_position(p, phi3)
    s = np.linalg.norm(pin_xy, axis=0)
    phi1 = np.arctan2(pin_xy[1], pin_xy[0])
    u = np.array([np.cos(phi1), np.sin(phi1)])
    n = np.array([-np.sin(phi1), np.cos(phi1)])
    u3 = np.array([np.cos(phi3), np.sin(phi3)])
    n3 = np.array([-np.sin(phi3), np.cos(phi3)])
    dpin = p.d3 * dphi3 * n3
    ddpin = p.d3 * (ddphi3 * n3 - dphi3**2 * u3)
    ds = np.sum(u * dpin, axis=0)
    dphi1 = np.sum(n * dpin, axis=0) / s
    dds = np.sum(u * ddpin, axis=0) + s * dphi1**2
    ddphi1 = (np.sum(n * ddpin, axis=0) - 2.0 * ds * dphi1) / s
    return LoopState(phi1=phi1, r2=s - p.d2, dphi1=dphi1, dr2=ds, ddphi1=ddphi1, ddr2=dds)


def stroke_ratio(p: FeederParameters, phi3: np.ndarray) -> np.ndarray:
    """dr2/dφ3 = d3 sin(φ1 − φ3) [m/rad]: piston travel per radian of arm."""
    state = dependent_coordinates(p, phi3)
    return p.d3 * np.sin(state.phi1 - np.asarray(phi3, dtype=float))


def transmission_angle(p: FeederParameters, phi3: np.ndarray) -> np.ndarray:
    """Angle μ [rad] in [0, π] between the piston axis and the arm lever at the pin."""
    state = dependent_coordinates(p, phi3)
    delta = state.phi1 - np.asarray(phi3, dtype=float)
    return np.abs(np.arctan2(np.sin(delta), np.cos(delta)))


def transmission_sine(q: np.ndarray) -> np.ndarray:
    """|sin μ| of the transmission angle μ = ∠(piston axis, arm lever) = |φ1 − φ3| (wrapped).

    Args:
        q: Configurations [φ1, r2, φ3, φ4] in paper order, shape (N, 4).

    Returns:
        Shape (N,); 1 at μ = 90°, 0 at the toggle.
    """
    return np.abs(np.sin(q[:, 0] - q[:, 2]))


def check_transmission(q: np.ndarray, times: np.ndarray | None = None) -> None:
    """Raise :class:`SingularPoseError` if any pose is within 5° of the toggle.

    Args:
        q: Configurations in paper order, shape (N, 4).
        times: Sample times [s] for the message (default: sample indices).
    """
    sine = transmission_sine(q)
    bad = np.flatnonzero(sine < math.sin(math.radians(SINGULAR_TRANSMISSION_DEG)))
    if bad.size:
        k = int(bad[np.argmin(sine[bad])])
        delta = math.remainder(q[k, 0] - q[k, 2], 2.0 * math.pi)
        where = f"t = {times[k]:.4f} s" if times is not None else f"sample {k}"
        raise SingularPoseError(
            f"transmission angle {math.degrees(abs(delta)):.3f}° at {where} "
            f"(φ1 = {math.degrees(q[k, 0]):.3f}°, φ3 = {math.degrees(q[k, 2]):.3f}°) is within "
            f"{SINGULAR_TRANSMISSION_DEG:g}° of the toggle: the loads are unbounded there"
        )


def arm_travel(elevation: float) -> float:
    """Arm rotation [rad] from loading to ramming at ``elevation`` [rad]: 90° − ε."""
    return math.pi / 2.0 - elevation


def required_stroke(p: FeederParameters) -> float:
    """Piston stroke [m] that the whole elevation range needs (loading to the lowest ε)."""
    travel = arm_travel(p.elevation_min)
    ends = dependent_coordinates(p, np.array([p.phi3_load, p.phi3_load + travel]))
    return float(ends.r2[1] - ends.r2[0])


def check_travel(p: FeederParameters) -> None:
    """Raise unless the loop assembles, away from the toggle, over the whole arm travel.

    The travel runs from the loading pose φ3 = ``phi3_load`` to φ3 = ``phi3_load`` + 90° − ε at
    every elevation ε of the range, i.e. over [phi3_load + 90° − ε_max, phi3_load + 90° − ε_min]
    and the loading pose; it is checked at :data:`TRAVEL_SAMPLES` arm angles, both ends included.

    Raises:
        UnreachablePoseError: A pose of the travel outside the arm's end stops, the piston's
            stroke or the cylinder's swing (:func:`check_reachable`).
        InputError: A pose whose transmission angle is within
            :data:`SINGULAR_TRANSMISSION_DEG` of the toggle.
    """
    ends = p.phi3_load + np.array([arm_travel(p.elevation_max), arm_travel(p.elevation_min)])
    phi3 = np.linspace(min(p.phi3_load, ends[0]), max(p.phi3_load, ends[1]), TRAVEL_SAMPLES)
    try:
        loop = dependent_coordinates(p, phi3)
    except UnreachablePoseError as exc:
        pin_xy = pin_position(p, phi3)
        r2 = np.linalg.norm(pin_xy, axis=0) - p.d2
        phi1 = np.degrees(np.arctan2(pin_xy[1], pin_xy[0]))
        raise UnreachablePoseError(
            f"parameters {p.name!r}: the feeding cycle's arm travel "
            f"[{math.degrees(phi3[0]):.2f}°, {math.degrees(phi3[-1]):.2f}°] cannot be assembled: "
            f"{exc}. This geometry needs r2 in [{r2.min():.5f}, {r2.max():.5f}] m and φ1 in "
            f"[{phi1.min():.2f}°, {phi1.max():.2f}°]: widen r2_min/r2_max (phi1_min/phi1_max, "
            "phi3_min/phi3_max) to match, or narrow the elevation range"
        ) from exc
    poses = np.column_stack([loop.phi1, loop.r2, phi3, np.zeros_like(phi3)])
    try:
        check_transmission(poses)
    except SingularPoseError as exc:
        raise InputError(f"parameters {p.name!r}, the feeding cycle's arm travel: {exc}") from exc
