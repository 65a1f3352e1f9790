"""The cylinder–piston–arm loop in closed form: the only copy of its geometry, vectorised.

The rod-eye pin P lies on the arm a distance d3 from its pivot A = (L1, L2) and a distance
r2 + d2 from the cylinder pivot B along the cylinder axis (eq. 44, corrected — see the errata):

    P = A + d3 (cos φ3, sin φ3) = (r2 + d2) (cos φ1, sin φ1).

So for a given arm angle φ3: r2 = |P| − d2 and φ1 = atan2(P_y, P_x). Differentiating twice
along u = (cos φ1, sin φ1) and n = (−sin φ1, cos φ1) gives the velocity and acceleration level.
The transmission angle μ is the angle between the piston axis u and the arm lever
(cos φ3, sin φ3) at the pin; the lever arm of the piston force about A is d3 sin μ, and
dr2/dφ3 = d3 sin(φ1 − φ3).

Configurations are in the paper's order q = [φ1, r2, φ3, φ4] (eq. 29), shape (..., 4).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..exceptions import InputError, SingularPoseError, UnreachablePoseError
from ..validation import check_finite, first_outside
from .parameters import SINGULAR_TRANSMISSION_DEG, FeederParameters

TRANSMISSION_BAND_DEG = (40.0, 140.0)
"""Documented band [deg] that the transmission angle stays inside over the whole elevation range
(the reference geometry achieves [43°, 137°])."""

TRAVEL_SAMPLES = 2001
"""Arm angles at which :func:`check_travel` checks a parameter set (≤ 0.05° apart over 94°)."""

CLOSURE_TOLERANCE = 1e-9
"""Largest accepted closure error [m] of a given configuration (eq. 44): the closed form and the
Newton assembly close the loop to ~1e-15 m; 1e-9 m leaves room for data rounded to 9 digits."""

VELOCITY_TOLERANCE = 1e-9
"""Largest accepted rate of the pin gap [m/s] of given velocities (same reasoning)."""


@dataclass(frozen=True)
class LoopState:
    """Closed-loop coordinates and their first two time derivatives, paper order.

    Attributes:
        q: [φ1, r2, φ3, φ4] [rad, m, rad, rad], shape (..., 4).
        v: Their rates [rad/s, m/s, rad/s, rad/s], shape (..., 4).
        a: Their accelerations [rad/s², m/s², rad/s², rad/s²], shape (..., 4).
    """

    q: np.ndarray
    v: np.ndarray
    a: np.ndarray


def pin_position(p: FeederParameters, phi3: np.ndarray) -> np.ndarray:
    """Rod-eye pin position P [m] in the world x-y plane for arm angles φ3 [rad]: (2, ...)."""
    phi3 = np.asarray(phi3, dtype=float)
    return np.array([p.L1 + p.d3 * np.cos(phi3), p.L2 + p.d3 * np.sin(phi3)])


def loop_residual(p: FeederParameters, q: np.ndarray) -> np.ndarray:
    """Closure error of eq. (44): distance [m] between the pin as reached from the cylinder side,
    (r2 + d2) (cos φ1, sin φ1), and from the arm side, P(φ3); q (..., 4) → shape (...)."""
    reach = q[..., 1] + p.d2
    piston_side = np.array([reach * np.cos(q[..., 0]), reach * np.sin(q[..., 0])])
    return np.linalg.norm(piston_side - pin_position(p, q[..., 2]), axis=0)


def check_closed(p: FeederParameters, q: np.ndarray, what: str = "sample") -> None:
    """Raise :class:`UnreachablePoseError` unless every configuration closes the loop.

    Args:
        p: Device parameters.
        q: Configurations in paper order, shape (N, 4), N ≥ 1.
        what: How the message names a configuration ("sample" → "sample 3").
    """
    residual = loop_residual(p, q)
    worst = int(np.argmax(residual))
    if residual[worst] > CLOSURE_TOLERANCE:
        name = f"{what} {worst}" if q.shape[0] > 1 else what
        raise UnreachablePoseError(
            f"{name} does not close the loop: pin gap {residual[worst]:.3e} m "
            f"> {CLOSURE_TOLERANCE:g} m at q = {np.round(q[worst], 6)}"
        )


def loop_residual_rate(p: FeederParameters, q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Rate [m/s] at which the pin gap of eq. (44) opens: |d/dt [(r2 + d2) u1 − A − d3 u3]| with
    u_i = (cos φi, sin φi), for q, v (..., 4); zero for velocities that keep the loop closed."""
    c1, s1, c3, s3 = np.cos(q[..., 0]), np.sin(q[..., 0]), np.cos(q[..., 2]), np.sin(q[..., 2])
    reach = q[..., 1] + p.d2
    rate_x = v[..., 1] * c1 - reach * v[..., 0] * s1 + p.d3 * v[..., 2] * s3
    rate_y = v[..., 1] * s1 + reach * v[..., 0] * c1 - p.d3 * v[..., 2] * c3
    return np.hypot(rate_x, rate_y)


def check_closed_velocity(
    p: FeederParameters, q: np.ndarray, v: np.ndarray, what: str = "sample"
) -> None:
    """Raise :class:`InputError` unless the velocities v keep the loop closed at q, (N, 4).

    Args:
        what: How the message names a sample ("sample" → "sample 3").
    """
    rate = loop_residual_rate(p, q, v)
    worst = int(np.argmax(rate))
    if rate[worst] > VELOCITY_TOLERANCE:
        name = f"{what} {worst}" if q.shape[0] > 1 else what
        raise InputError(
            f"the velocities of {name} violate the closure: the pin gap opens at "
            f"{rate[worst]:.3e} m/s > {VELOCITY_TOLERANCE:g} m/s (v = {np.round(v[worst], 6)})"
        )


def check_reachable(p: FeederParameters, phi3: np.ndarray) -> None:
    """Raise unless the loop can reach every arm angle φ3 [rad] within the joint limits.

    Raises:
        UnreachablePoseError: φ3 outside the arm's end stops, a piston position outside the
            cylinder's stroke [r2_min, r2_max], or a cylinder angle outside its swing
            [phi1_min, phi1_max] (the URDF's joint limits).
    """
    pin_xy = pin_position(p, phi3)
    r2 = np.linalg.norm(pin_xy, axis=0) - p.d2
    phi1 = np.arctan2(pin_xy[1], pin_xy[0])
    phi3, deg = np.ravel(phi3), math.degrees
    if (k := first_outside(phi3, p.phi3_min, p.phi3_max)) is not None:
        raise UnreachablePoseError(
            f"arm angle φ3 = {deg(phi3[k]):.3f}° is outside the arm's end stops "
            f"[{deg(p.phi3_min):.1f}°, {deg(p.phi3_max):.1f}°]"
        )
    if (k := first_outside(r2, p.r2_min, p.r2_max)) is not None:
        raise UnreachablePoseError(
            f"arm angle φ3 = {deg(phi3[k]):.3f}° needs piston position "
            f"r2 = {np.ravel(r2)[k]:.4f} m, outside the stroke [{p.r2_min:.4f}, {p.r2_max:.4f}] m"
        )
    if (k := first_outside(phi1, p.phi1_min, p.phi1_max)) is not None:
        raise UnreachablePoseError(
            f"arm angle φ3 = {deg(phi3[k]):.3f}° needs cylinder angle "
            f"φ1 = {deg(np.ravel(phi1)[k]):.3f}°, outside its swing "
            f"[{deg(p.phi1_min):.1f}°, {deg(p.phi1_max):.1f}°]"
        )


def solve_loop(
    p: FeederParameters,
    phi3: np.ndarray,
    phi4: np.ndarray | float = 0.0,
    rates: tuple[np.ndarray | float, np.ndarray | float] = (0.0, 0.0),
    accelerations: tuple[np.ndarray | float, np.ndarray | float] = (0.0, 0.0),
) -> LoopState:
    """The closed loop from the independent coordinates (φ3, φ4), their rates and accelerations.

    For checked, broadcastable float inputs (see :func:`loop_state` for the public, checking
    version); φ1 and r2 come from the closed form of the module docstring.
    """
    phi3, phi4 = np.broadcast_arrays(np.asarray(phi3, float), np.asarray(phi4, float))
    dphi3, dphi4, ddphi3, ddphi4 = np.broadcast_arrays(phi3, *rates, *accelerations)[1:]
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
    return LoopState(
        q=np.stack([phi1, s - p.d2, phi3, phi4], axis=-1),
        v=np.stack([dphi1, ds, dphi3, dphi4], axis=-1),
        a=np.stack([ddphi1, dds, ddphi3, ddphi4], axis=-1),
    )


def loop_state(
    p: FeederParameters,
    phi3: np.ndarray | float,
    phi4: np.ndarray | float = 0.0,
    rates: tuple[np.ndarray | float, np.ndarray | float] = (0.0, 0.0),
    accelerations: tuple[np.ndarray | float, np.ndarray | float] = (0.0, 0.0),
) -> LoopState:
    """Closed configurations [φ1, r2, φ3, φ4] and derivatives from φ3, φ4 and theirs.

    Args:
        p: Device parameters.
        phi3: Arm angle(s) [rad], scalar or shape (...).
        phi4: Forearm angle(s) [rad], broadcastable to φ3.
        rates: (φ̇3, φ̇4) [rad/s], each broadcastable to φ3.
        accelerations: (φ̈3, φ̈4) [rad/s²], each broadcastable to φ3.

    Returns:
        The :class:`LoopState`, arrays of shape (..., 4) (φ3's shape, then the coordinate).

    Raises:
        InputError: NaN/inf, text, or shapes that do not broadcast to φ3's.
        UnreachablePoseError: An arm angle the loop cannot reach (:func:`check_reachable`).
    """
    phi3 = check_finite("phi3 [rad]", phi3)
    named = {"phi4 [rad]": phi4, "dphi3 [rad/s]": rates[0], "dphi4 [rad/s]": rates[1]}
    named |= {"ddphi3 [rad/s²]": accelerations[0], "ddphi4 [rad/s²]": accelerations[1]}
    checked = {name: check_finite(name, value) for name, value in named.items()}
    for name, value in checked.items():
        try:
            fits = np.broadcast_shapes(phi3.shape, value.shape) == phi3.shape
        except ValueError:
            fits = False
        if not fits:
            raise InputError(
                f"{name} must be a scalar or broadcast to phi3's shape {phi3.shape}, "
                f"got {value.shape}"
            )
    check_reachable(p, phi3)
    phi4, dphi3, dphi4, ddphi3, ddphi4 = checked.values()
    return solve_loop(p, phi3, phi4, (dphi3, dphi4), (ddphi3, ddphi4))


def transmission_sine(q: np.ndarray) -> np.ndarray:
    """|sin μ| of the transmission angle μ = ∠(piston axis, arm lever) = |φ1 − φ3| (wrapped).

    Args:
        q: Configurations [φ1, r2, φ3, φ4] in paper order, shape (..., 4).

    Returns:
        Shape (...); 1 at μ = 90°, 0 at the toggle.
    """
    return np.abs(np.sin(q[..., 0] - q[..., 2]))


def transmission_angle(q: np.ndarray) -> np.ndarray:
    """Transmission angle μ [rad] in [0, π] between the piston axis and the arm lever at the
    pin, for configurations q (..., 4) in paper order; shape (...)."""
    delta = q[..., 0] - q[..., 2]
    return np.abs(np.arctan2(np.sin(delta), np.cos(delta)))


def check_transmission(q: np.ndarray, times: np.ndarray | None = None) -> None:
    """Raise :class:`SingularPoseError` if any pose is within
    :data:`~feeder.device.parameters.SINGULAR_TRANSMISSION_DEG` of the toggle.

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


def arm_travel(elevation: float | np.ndarray) -> float | np.ndarray:
    """Arm rotation [rad] from loading to ramming at ``elevation`` [rad]: 90° − ε."""
    return math.pi / 2.0 - elevation


def required_stroke(p: FeederParameters) -> float:
    """Piston stroke [m] that the whole elevation range needs (loading to the lowest ε)."""
    ends = solve_loop(p, p.phi3_load + np.array([0.0, arm_travel(p.elevation_min)]))
    return float(ends.q[1, 1] - ends.q[0, 1])


def check_travel(p: FeederParameters) -> None:
    """Raise unless the loop assembles, away from the toggle, over the whole arm travel.

    The travel runs from the loading pose φ3 = ``phi3_load`` to φ3 = ``phi3_load`` + 90° − ε at
    every elevation ε of the range, i.e. over [phi3_load + 90° − ε_max, phi3_load + 90° − ε_min]
    and the loading pose; it is checked at :data:`TRAVEL_SAMPLES` arm angles, both ends included.

    Raises:
        UnreachablePoseError: A pose of the travel outside the arm's end stops, the piston's
            stroke or the cylinder's swing (:func:`check_reachable`).
        InputError: A pose whose transmission angle is within
            :data:`~feeder.device.parameters.SINGULAR_TRANSMISSION_DEG` of the toggle.
    """
    ends = p.phi3_load + np.array([arm_travel(p.elevation_max), arm_travel(p.elevation_min)])
    phi3 = np.linspace(min(p.phi3_load, ends[0]), max(p.phi3_load, ends[1]), TRAVEL_SAMPLES)
    loop = solve_loop(p, phi3)
    try:
        check_reachable(p, phi3)
    except UnreachablePoseError as exc:
        r2, phi1 = loop.q[:, 1], np.degrees(loop.q[:, 0])
        raise UnreachablePoseError(
            f"parameters {p.name!r}: the feeding cycle's arm travel "
            f"[{math.degrees(phi3[0]):.2f}°, {math.degrees(phi3[-1]):.2f}°] cannot be assembled: "
            f"{exc}. This geometry needs r2 in [{r2.min():.5f}, {r2.max():.5f}] m and φ1 in "
            f"[{phi1.min():.2f}°, {phi1.max():.2f}°]: widen r2_min/r2_max (phi1_min/phi1_max, "
            "phi3_min/phi3_max) to match, or narrow the elevation range"
        ) from exc
    try:
        check_transmission(loop.q)
    except SingularPoseError as exc:
        raise InputError(f"parameters {p.name!r}, the feeding cycle's arm travel: {exc}") from exc


def check_device(p: FeederParameters) -> None:
    """Every check of a parameter set: its numbers (:meth:`FeederParameters.check`), then the
    loop over the whole arm travel (:func:`check_travel`).

    Raises:
        InputError, InertiaError, UnreachablePoseError: See the two checks.
    """
    p.check()
    check_travel(p)
