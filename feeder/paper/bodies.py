"""The bodies of the hand-derived model: centres of gravity, Jacobians and inertias (eqs. 30–39).

Generalized coordinates q = [φ1, r2, φ3, φ4] = [q1, q2, q3, q4] (eq. 29); every function takes
arrays of shape (..., 4) (one state or N time samples) and returns arrays with the same leading
shape. World frame: x horizontal, y up, z along the pivots; gravity −y, g = 9.81 m/s².
Abbreviations: c_i = cos q_i, s_i = sin q_i, A = (L1, L2) the arm pivot, P1 = q2 + d2.

**Bodies** (eq. 30, corrected; see :mod:`feeder.paper.errata` for what the paper printed):
1 cylinder, 2 piston, 3 arm, 4 forearm, 5 payload (the projectile, rigidly held by the forearm
from the end of stage 1; the paper leaves it out). A point fixed in the forearm frame at
(p_x, p_y, p_z) — the forearm CG (e, −d, 0) or the payload CG (e5, h5, z5) — is, in the arm
frame, (a1, −f, c) + R_y(q4) (p_x, p_y, p_z); with

    u = p_x c4 + p_z s4,   w = −p_x s4 + p_z c4,   ρx = a1 + u,   ρy = p_y − f,

its world position is r = (L1 + ρx c3 − ρy s3,  L2 + ρx s3 + ρy c3,  c + w), so that

    J_T = ∂r/∂q = [0 0 −ρx s3 − ρy c3  w c3;  0 0 ρx c3 − ρy s3  w s3;  0 0 0  −u]   (34)

and, the forearm hinge being the arm's y axis (−s3, c3, 0) which turns with φ3,

    ω4 = ω5 = q̇3 z + q̇4 (−s3, c3, 0),   J_R = [0 0 0 −s3;  0 0 0 c3;  0 0 1 0]     (38)

(in the forearm frame ω = (−q̇3 s4, q̇4, q̇3 c4)). Bodies 1–3: r1 = l1 (c1, s1, 0),
r2 = q2 (c1, s1, 0), r3 = A + l3 (c3, s3, 0), ω1 = ω2 = q̇1 z, ω3 = q̇3 z (eqs. 31–33, 35–37).
"""

from __future__ import annotations

import numpy as np

from ..device.parameters import GRAVITY, FeederParameters
from ..exceptions import InputError
from ..validation import check_finite

G = float(-GRAVITY[1])
"""Gravitational acceleration g [m/s²], acting along −y
(:data:`~feeder.device.parameters.GRAVITY`)."""


def coordinates(name: str, value: np.ndarray) -> np.ndarray:
    """``value`` as a finite float array of shape (..., 4) = [φ1, r2, φ3, φ4]."""
    array = check_finite(name, value)
    if array.ndim == 0 or array.shape[-1] != 4:
        raise InputError(f"{name} must have shape (..., 4) = [φ1, r2, φ3, φ4], got {array.shape}")
    return array


def grip_weight(gripped: bool | np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    """The grip flags (bool or 0/1, broadcast to ``shape``) as a float array: 1 where the
    forearm holds the payload (body 5)."""
    if isinstance(gripped, bool | np.bool_) or np.asarray(gripped).dtype.kind == "b":
        gripped = np.asarray(gripped, dtype=float)  # truth values are flags here
    weight = check_finite("gripped", gripped)
    if not np.all((weight == 0.0) | (weight == 1.0)):
        raise InputError(f"gripped must be 0/1 (or bool), got {gripped!r}")
    try:
        return np.broadcast_to(weight, shape)
    except ValueError as exc:
        raise InputError(f"gripped of shape {weight.shape} does not fit samples {shape}") from exc


def held_points(p: FeederParameters) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Forearm and payload CGs in the forearm frame (2, 3) [m], masses (2,) [kg], moments (2, 3)
    [kg·m²] about their CGs in forearm-frame axes."""
    points = np.array([[p.e, -p.d, 0.0], [p.e5, p.h5, p.z5]])
    masses = np.array([p.forearm.mass, p.payload.mass])
    moments = np.array([p.forearm.moments, p.payload.moments])
    return points, masses, moments


def per_body(values: np.ndarray, ndim: int) -> np.ndarray:
    """Forearm and payload values (2,) shaped (2, 1, …, 1) to broadcast against (2, ...)."""
    return np.reshape(values, (2,) + (1,) * ndim)


def held_geometry(p: FeederParameters, c4: np.ndarray, s4: np.ndarray):
    """u, w, ρx, ρy of the forearm and payload CGs, body axis first: (2, ...) each (ρy, constant,
    is (2, 1, …, 1)), from c4 = cos φ4, s4 = sin φ4 of shape (...)."""
    px, py, pz = (per_body(x, np.ndim(c4)) for x in held_points(p)[0].T)
    u = px * c4 + pz * s4
    w = pz * c4 - px * s4
    return u, w, p.a1 + u, py - p.f


def body_masses(p: FeederParameters) -> np.ndarray:
    """Masses m1 … m5 [kg], shape (5,) (Table I)."""
    return np.array([p.cylinder.mass, p.piston.mass, p.arm.mass, p.forearm.mass, p.payload.mass])


def body_positions(p: FeederParameters, q: np.ndarray) -> np.ndarray:
    """Centres of gravity r1 … r5 (eq. 30, corrected), world frame [m], shape (..., 5, 3)."""
    q = coordinates("q", q)
    c1, s1, c3, s3 = np.cos(q[..., 0]), np.sin(q[..., 0]), np.cos(q[..., 2]), np.sin(q[..., 2])
    zero = np.zeros_like(c1)
    _, w, rx, ry = held_geometry(p, np.cos(q[..., 3]), np.sin(q[..., 3]))
    held = np.stack([p.L1 + rx * c3 - ry * s3, p.L2 + rx * s3 + ry * c3, p.c + w], axis=-1)
    links = np.stack(
        [
            np.stack([p.l1 * c1, p.l1 * s1, zero], axis=-1),
            np.stack([q[..., 1] * c1, q[..., 1] * s1, zero], axis=-1),
            np.stack([p.L1 + p.l3 * c3, p.L2 + p.l3 * s3, zero], axis=-1),
        ],
        axis=-2,
    )
    return np.concatenate([links, np.moveaxis(held, 0, -2)], axis=-2)


def translational_jacobians(p: FeederParameters, q: np.ndarray) -> np.ndarray:
    """J_Ti = ∂r_i/∂q of the five bodies (eqs. 31–34, corrected), world frame, (..., 5, 3, 4).

    Columns 1 and 3 [m/rad], column 2 [m/m], column 4 [m/rad].
    """
    q = coordinates("q", q)
    c1, s1, c3, s3 = np.cos(q[..., 0]), np.sin(q[..., 0]), np.cos(q[..., 2]), np.sin(q[..., 2])
    u, w, rx, ry = held_geometry(p, np.cos(q[..., 3]), np.sin(q[..., 3]))
    jac = np.zeros((*q.shape[:-1], 5, 3, 4))
    jac[..., 0, 0, 0], jac[..., 0, 1, 0] = -p.l1 * s1, p.l1 * c1  # (31)
    jac[..., 1, 0, 0], jac[..., 1, 1, 0] = -q[..., 1] * s1, q[..., 1] * c1  # (32)
    jac[..., 1, 0, 1], jac[..., 1, 1, 1] = c1, s1
    jac[..., 2, 0, 2], jac[..., 2, 1, 2] = -p.l3 * s3, p.l3 * c3  # (33)
    for b, body in enumerate((3, 4)):  # (34), forearm and payload
        jac[..., body, 0, 2] = -rx[b] * s3 - ry[b] * c3
        jac[..., body, 1, 2] = rx[b] * c3 - ry[b] * s3
        jac[..., body, 0, 3] = w[b] * c3
        jac[..., body, 1, 3] = w[b] * s3
        jac[..., body, 2, 3] = -u[b]
    return jac


def rotational_jacobians(p: FeederParameters, q: np.ndarray) -> np.ndarray:
    """J_Ri = ∂ω_i/∂q̇ of the five bodies (eqs. 35–38, corrected), world frame, (..., 5, 3, 4).

    ω4 = ω5 = q̇3 z + q̇4 y_arm with y_arm = (−sin φ3, cos φ3, 0): the forearm turns with the
    arm and about the arm's y axis.
    """
    q = coordinates("q", q)
    jac = np.zeros((*q.shape[:-1], 5, 3, 4))
    jac[..., 0:2, 2, 0] = 1.0  # (35), (36)
    jac[..., 2:, 2, 2] = 1.0  # (37), and the arm's rotation carried by the forearm and payload
    jac[..., 3:, 0, 3] = -np.sin(q[..., 2:3])  # (38)
    jac[..., 3:, 1, 3] = np.cos(q[..., 2:3])
    return jac


def body_rotations(p: FeederParameters, q: np.ndarray) -> np.ndarray:
    """Orientations R_i (world ← link) of the five bodies, (..., 5, 3, 3).

    R1 = R2 = R_z(φ1), R3 = R_z(φ3), R4 = R5 = R_z(φ3) R_y(φ4).
    """
    q = coordinates("q", q)

    def rot_z(angle):
        c, s, o, i = np.cos(angle), np.sin(angle), np.zeros_like(angle), np.ones_like(angle)
        return np.stack(
            [np.stack([c, -s, o], -1), np.stack([s, c, o], -1), np.stack([o, o, i], -1)], -2
        )

    c4, s4 = np.cos(q[..., 3]), np.sin(q[..., 3])
    o, i = np.zeros_like(c4), np.ones_like(c4)
    rot_y = np.stack(
        [np.stack([c4, o, s4], -1), np.stack([o, i, o], -1), np.stack([-s4, o, c4], -1)], -2
    )
    r1, r3 = rot_z(q[..., 0]), rot_z(q[..., 2])
    r4 = r3 @ rot_y
    return np.stack([r1, r1, r3, r4, r4], axis=-3)


def mass_matrix_from_jacobians(
    masses: np.ndarray, j_t: np.ndarray, j_r: np.ndarray, inertias: np.ndarray
) -> np.ndarray:
    """Eq. (17): M = Σ_i (m_i J_Tiᵀ J_Ti + J_Riᵀ I_i J_Ri), summed over the body axis.

    Args:
        masses: m_i [kg], shape (..., B) (a zero mass removes a body).
        j_t: Translational Jacobians, (..., B, 3, n).
        j_r: Rotational Jacobians, (..., B, 3, n), same frame as ``inertias``.
        inertias: Central inertia tensors I_i [kg·m²], (..., B, 3, 3); scale them with the
            masses to remove a body.

    Returns:
        M, shape (..., n, n).
    """
    translation = np.einsum("...b,...bki,...bkj->...ij", masses, j_t, j_t)
    return translation + np.einsum("...bki,...bkl,...blj->...ij", j_r, inertias, j_r)
