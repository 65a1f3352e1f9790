"""The paper's Lagrange equations of the feeder (sections III–IV), corrected, vectorised.

Generalized coordinates q = [φ1, r2, φ3, φ4] = [q1, q2, q3, q4] (eq. 29); every function takes
arrays of shape (..., 4) (one state or N time samples) and returns arrays with the same leading
shape. World frame: x horizontal, y up, z along the pivots; gravity −y, g = 9.81 m/s².
Abbreviations: c_i = cos q_i, s_i = sin q_i, A = (L1, L2) the arm pivot, P1 = q2 + d2.

**Bodies** (eq. 30, corrected; see :mod:`feeder.errata` for what the paper printed):
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

**Inertia matrix** (eq. 17 = eq. 39 summed over the five bodies; corrected eq. 40), with
(I_bx, I_by, I_bz) the central moments of body b in its link frame, sums over b ∈ {4, 5}
(5 only while the payload is held):

    M11 = I1z + I2z + m1 l1² + m2 q2²,        M22 = m2,
    M33 = I3z + m3 l3² + Σ_b [m_b (ρx_b² + ρy_b²) + I_bx s4² + I_bz c4²],
    M44 = Σ_b [m_b (p_bx² + p_bz²) + I_by],   M34 = M43 = −Σ_b m_b ρy_b w_b,

all other entries zero. **∂M/∂q** (eq. 4 layout, entry (i, 4 (j−1) + k) = ∂M_ij/∂q_k, 1-based):
a_{1,2} = 2 m2 q2, a_{3,12} = Σ_b [2 m_b ρx_b w_b + (I_bx − I_bz) sin 2q4],
a_{3,16} = a_{4,12} = Σ_b m_b ρy_b u_b, every other a_ij = 0 (a_{4,16} = 0: M44 is constant).
**C** from the Kronecker formula (27) (:func:`feeder.coriolis.kronecker_coriolis`). Written out
with these a_ij, (C q̇)_i = Σ_jk ∂M_ij/∂q_k q̇_j q̇_k − ½ Σ_jk ∂M_jk/∂q_i q̇_j q̇_k is

    C q̇ = [a_{1,2} q̇1 q̇2,  −½ a_{1,2} q̇1²,  a_{3,12} q̇3 q̇4 + a_{3,16} q̇4²,  −½ a_{3,12} q̇3²]

(in row 4 the a_{4,12} q̇3 q̇4 of the first sum and the a_{3,16} q̇3 q̇4 of the second cancel).

**Gravity** (Π = Σ m_i g y_i, eq. 42 corrected; g = (∂Π/∂q)ᵀ, eq. 43 corrected):

    g1 = g (m1 l1 + m2 q2) c1,   g2 = g m2 s1,
    g3 = g [m3 l3 c3 + Σ_b m_b (ρx_b c3 − ρy_b s3)],   g4 = g Σ_b m_b w_b s3.

**Closure** (eq. 44 corrected: the pin P = A + d3 (c3, s3) = P1 (c1, s1), as in
:mod:`feeder.kinematics`):

    f = [P1 c1 − d3 c3 − L1;  P1 s1 − d3 s3 − L2],
    J_f = [−P1 s1  c1  d3 s3  0;  P1 c1  s1  −d3 c3  0],
    J̇_f q̇ = [−2 s1 q̇1 q̇2 − P1 c1 q̇1² + d3 c3 q̇3²;  2 c1 q̇1 q̇2 − P1 s1 q̇1² + d3 s3 q̇3²].

**Equations of motion** (eqs. 28, 46–47): M q̈ + C q̇ + g = τ − J_fᵀ λ, J_f q̈ = −J̇_f q̇.
Since f = p_piston_pin − p_arm_pin, the pin force that the arm exerts on the piston is −λ
(world x, y) [N]: λ is the force of the piston on the arm. The actuators are the piston force
τ2 = F [N] on ``piston_joint`` and the rack moment τ4 [N·m] on ``forearm_joint``; φ1 and φ3 are
passive (τ1 = τ3 = 0). Inverse dynamics (:func:`inverse_dynamics`: these closed forms, every
sample at once), with h = M q̈ + C q̇ + g: rows 1 and 3 give
[P1 s1, −P1 c1; −d3 s3, d3 c3] λ = [h1; h3] (determinant P1 d3 sin(q1 − q3), zero only at the
toggle), then τ2 = h2 + c1 λ1 + s1 λ2 and τ4 = h4.

**Pinocchio's convention**: ``constraintDynamics`` returns λ_c with M a + b − τ = Jᵀ λ_c, J the
CONTACT_3D Jacobian in the LOCAL frame c1 of ``piston_pin`` (rotation R_c1 = R_z(φ1)), i.e.
J = R_c1ᵀ ∂(p_piston_pin − p_arm_pin)/∂q; λ_c is the arm's force on the piston in c1 axes.
The x, y rows of R_c1 J are J_f (its z row vanishes), so λ = −R_c1[:2, :] λ_c.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .coriolis import kronecker_coriolis
from .cycle import CycleKinematics
from .device import GRAVITY, Feeder
from .exceptions import InputError, SingularPoseError, check_finite
from .parameters import FeederParameters

G = float(-GRAVITY[1])
"""Gravitational acceleration g [m/s²], acting along −y (:data:`feeder.device.GRAVITY`)."""

TOGGLE_TOLERANCE = 1e-9
"""|sin(φ1 − φ3)| below which the passive rows cannot give λ (piston axis on the arm lever)."""


def _coordinates(name: str, value: np.ndarray) -> np.ndarray:
    array = check_finite(name, value)
    if array.ndim == 0 or array.shape[-1] != 4:
        raise InputError(f"{name} must have shape (..., 4) = [φ1, r2, φ3, φ4], got {array.shape}")
    return array


def _payload_weight(payload: bool | np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    weight = check_finite("payload", payload)
    if not np.all((weight == 0.0) | (weight == 1.0)):
        raise InputError(f"payload must be 0/1 (or bool), got {payload!r}")
    try:
        return np.broadcast_to(weight, shape)
    except ValueError as exc:
        raise InputError(f"payload of shape {weight.shape} does not fit samples {shape}") from exc


def _held_points(p: FeederParameters) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Forearm and payload CGs in the forearm frame (2, 3) [m], masses (2,) [kg], moments (2, 3)
    [kg·m²] about their CGs in forearm-frame axes."""
    points = np.array([[p.e, -p.d, 0.0], [p.e5, p.h5, p.z5]])
    masses = np.array([p.forearm.mass, p.payload.mass])
    moments = np.array([p.forearm.moments, p.payload.moments])
    return points, masses, moments


def _per_body(values: np.ndarray, ndim: int) -> np.ndarray:
    """Forearm and payload values (2,) shaped (2, 1, …, 1) to broadcast against (2, ...)."""
    return np.reshape(values, (2,) + (1,) * ndim)


def _held_geometry(p: FeederParameters, c4: np.ndarray, s4: np.ndarray):
    """u, w, ρx, ρy of the forearm and payload CGs, body axis first: (2, ...) each (ρy, constant,
    is (2, 1, …, 1)), from c4 = cos φ4, s4 = sin φ4 of shape (...)."""
    px, py, pz = (_per_body(x, np.ndim(c4)) for x in _held_points(p)[0].T)
    u = px * c4 + pz * s4
    w = pz * c4 - px * s4
    return u, w, p.a1 + u, py - p.f


def body_masses(p: FeederParameters) -> np.ndarray:
    """Masses m1 … m5 [kg], shape (5,) (Table I)."""
    return np.array([p.cylinder.mass, p.piston.mass, p.arm.mass, p.forearm.mass, p.payload.mass])


def body_positions(p: FeederParameters, q: np.ndarray) -> np.ndarray:
    """Centres of gravity r1 … r5 (eq. 30, corrected), world frame [m], shape (..., 5, 3)."""
    q = _coordinates("q", q)
    c1, s1, c3, s3 = np.cos(q[..., 0]), np.sin(q[..., 0]), np.cos(q[..., 2]), np.sin(q[..., 2])
    zero = np.zeros_like(c1)
    _, w, rx, ry = _held_geometry(p, np.cos(q[..., 3]), np.sin(q[..., 3]))
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
    q = _coordinates("q", q)
    c1, s1, c3, s3 = np.cos(q[..., 0]), np.sin(q[..., 0]), np.cos(q[..., 2]), np.sin(q[..., 2])
    u, w, rx, ry = _held_geometry(p, np.cos(q[..., 3]), np.sin(q[..., 3]))
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
    q = _coordinates("q", q)
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
    q = _coordinates("q", q)

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


def central_inertias(p: FeederParameters, q: np.ndarray) -> np.ndarray:
    """I_i = R_i diag(I_ix, I_iy, I_iz) R_iᵀ: central inertia tensors in world axes [kg·m²],
    (..., 5, 3, 3) (eq. 17's I_i, full tensors)."""
    rot = body_rotations(p, q)
    moments = np.array([link.moments for link in p.links().values()])
    return np.einsum("...bij,bj,...bkj->...bik", rot, moments, rot)


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


class _Terms(NamedTuple):
    """The nonzero entries of M, ∂M/∂q and g at each sample, shape (...) each (M22 = m2 is
    constant), with the cosines and sines of φ1 and φ3 that the closure needs as well.

    m11, m33, m34 (= M43), m44: M [kg·m²] (corrected eq. 40); a1_2 = ∂M11/∂q2 [kg·m],
    a3_12 = ∂M33/∂q4, a3_16 = a4_12 = ∂M34/∂q4 [kg·m²] (eq. 4 names, 1-based); g1 … g4: g
    [N·m, N, N·m, N·m] (corrected eq. 43).
    """

    c1: np.ndarray
    s1: np.ndarray
    c3: np.ndarray
    s3: np.ndarray
    m11: np.ndarray
    m33: np.ndarray
    m34: np.ndarray
    m44: np.ndarray
    a1_2: np.ndarray
    a3_12: np.ndarray
    a3_16: np.ndarray
    g1: np.ndarray
    g2: np.ndarray
    g3: np.ndarray
    g4: np.ndarray


def _terms(p: FeederParameters, q: np.ndarray, payload: bool | np.ndarray) -> _Terms:
    """Every formula of M, ∂M/∂q and g (module docstring), each trigonometric function of q
    evaluated once, for checked q of shape (..., 4) and payload flags (bool or (...) 0/1)."""
    flag = _payload_weight(payload, q.shape[:-1])
    r2 = q[..., 1]
    c1, s1 = np.cos(q[..., 0]), np.sin(q[..., 0])
    c3, s3 = np.cos(q[..., 2]), np.sin(q[..., 2])
    c4, s4 = np.cos(q[..., 3]), np.sin(q[..., 3])
    points, masses, moments = _held_points(p)
    m, ix, iy, iz, px2_pz2 = (
        _per_body(x, c4.ndim) for x in (masses, *moments.T, points[:, 0] ** 2 + points[:, 2] ** 2)
    )
    u, w, rx, ry = _held_geometry(p, c4, s4)

    def held(per_body: np.ndarray) -> np.ndarray:
        """Σ_b over the forearm and, where the flag is 1, the payload."""
        return per_body[0] + flag * per_body[1]

    m_rx, m_ry, m2 = m * rx, m * ry, p.piston.mass
    return _Terms(
        c1=c1,
        s1=s1,
        c3=c3,
        s3=s3,
        m11=p.cylinder.moments[2] + p.piston.moments[2] + p.cylinder.mass * p.l1**2 + m2 * r2**2,
        m33=p.arm.moments[2]
        + p.arm.mass * p.l3**2
        + held(m_rx * rx + m_ry * ry + iz + (ix - iz) * s4**2),
        m34=-held(m_ry * w),
        m44=held(m * px2_pz2 + iy),
        a1_2=2.0 * m2 * r2,
        a3_12=2.0 * held(m_rx * w + (ix - iz) * (s4 * c4)),
        a3_16=held(m_ry * u),
        g1=G * (p.cylinder.mass * p.l1 + m2 * r2) * c1,
        g2=G * m2 * s1,
        g3=G * ((p.arm.mass * p.l3 + held(m_rx)) * c3 - held(m_ry) * s3),
        g4=G * held(m * w) * s3,
    )


def mass_matrix(
    p: FeederParameters, q: np.ndarray, payload: bool | np.ndarray = True
) -> np.ndarray:
    """M(q) of the feeder (corrected eq. 40, closed form; see the module docstring), (..., 4, 4).

    Args:
        p: Device parameters.
        q: [φ1, r2, φ3, φ4], shape (..., 4).
        payload: Whether the forearm holds the payload (body 5), bool or (...,) array of 0/1.
    """
    q = _coordinates("q", q)
    t = _terms(p, q, payload)
    m = np.zeros((*q.shape[:-1], 4, 4))
    m[..., 0, 0] = t.m11
    m[..., 1, 1] = p.piston.mass
    m[..., 2, 2] = t.m33
    m[..., 3, 3] = t.m44
    m[..., 2, 3] = m[..., 3, 2] = t.m34
    return m


def mass_matrix_derivative(
    p: FeederParameters, q: np.ndarray, payload: bool | np.ndarray = True
) -> np.ndarray:
    """∂M/∂q (eq. 4 layout: entry (i, 4 j + k) = ∂M_ij/∂q_k, 0-based), shape (..., 4, 16).

    Closed form: the derivatives of the entries of :func:`mass_matrix` (module docstring).
    """
    q = _coordinates("q", q)
    t = _terms(p, q, payload)
    d = np.zeros((*q.shape[:-1], 4, 4, 4))  # d[..., i, j, k] = ∂M_ij/∂q_k
    d[..., 0, 0, 1] = t.a1_2
    d[..., 2, 2, 3] = t.a3_12
    d[..., 2, 3, 3] = d[..., 3, 2, 3] = t.a3_16
    return d.reshape(*q.shape[:-1], 4, 16)


def coriolis_matrix(
    p: FeederParameters, q: np.ndarray, qd: np.ndarray, payload: bool | np.ndarray = True
) -> np.ndarray:
    """C(q, q̇) of eq. (27) (Kronecker-product form), shape (..., 4, 4)."""
    qd = _coordinates("qd", qd)
    return kronecker_coriolis(mass_matrix_derivative(p, q, payload), qd)


def potential_energy(
    p: FeederParameters, q: np.ndarray, payload: bool | np.ndarray = True
) -> np.ndarray:
    """Π = Σ_i m_i g y_i [J] (eq. 42, corrected: no ½; datum y = 0 at B), shape (...)."""
    q = _coordinates("q", q)
    flag = _payload_weight(payload, q.shape[:-1])[..., None]
    masses = body_masses(p) * np.concatenate([np.ones((*q.shape[:-1], 4)), flag], axis=-1)
    return G * np.sum(masses * body_positions(p, q)[..., 1], axis=-1)


def gravity_vector(
    p: FeederParameters, q: np.ndarray, payload: bool | np.ndarray = True
) -> np.ndarray:
    """g(q) = (∂Π/∂q)ᵀ (eq. 43, corrected, closed form), [N·m, N, N·m, N·m], shape (..., 4)."""
    q = _coordinates("q", q)
    t = _terms(p, q, payload)
    return np.stack([t.g1, t.g2, t.g3, t.g4], axis=-1)


def closure_residual(p: FeederParameters, q: np.ndarray) -> np.ndarray:
    """f(q) = P1 (c1, s1) − A − d3 (c3, s3) [m] (eq. 44, corrected), shape (..., 2)."""
    q = _coordinates("q", q)
    reach = q[..., 1] + p.d2
    return np.stack(
        [
            reach * np.cos(q[..., 0]) - p.d3 * np.cos(q[..., 2]) - p.L1,
            reach * np.sin(q[..., 0]) - p.d3 * np.sin(q[..., 2]) - p.L2,
        ],
        axis=-1,
    )


def closure_jacobian(p: FeederParameters, q: np.ndarray) -> np.ndarray:
    """J_f = ∂f/∂q (eq. 44, corrected), shape (..., 2, 4)."""
    q = _coordinates("q", q)
    reach = q[..., 1] + p.d2
    c1, s1, c3, s3 = np.cos(q[..., 0]), np.sin(q[..., 0]), np.cos(q[..., 2]), np.sin(q[..., 2])
    jac = np.zeros((*q.shape[:-1], 2, 4))
    jac[..., 0, 0], jac[..., 0, 1], jac[..., 0, 2] = -reach * s1, c1, p.d3 * s3
    jac[..., 1, 0], jac[..., 1, 1], jac[..., 1, 2] = reach * c1, s1, -p.d3 * c3
    return jac


def closure_bias(p: FeederParameters, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """J̇_f q̇ [m/s²], shape (..., 2): f̈ = J_f q̈ + J̇_f q̇."""
    q, qd = _coordinates("q", q), _coordinates("qd", qd)
    reach = q[..., 1] + p.d2
    c1, s1, c3, s3 = np.cos(q[..., 0]), np.sin(q[..., 0]), np.cos(q[..., 2]), np.sin(q[..., 2])
    cross, spin1, spin3 = 2.0 * qd[..., 0] * qd[..., 1], qd[..., 0] ** 2, qd[..., 2] ** 2
    return np.stack(
        [
            -s1 * cross - reach * c1 * spin1 + p.d3 * c3 * spin3,
            c1 * cross - reach * s1 * spin1 + p.d3 * s3 * spin3,
        ],
        axis=-1,
    )


def _generalized_forces(p: FeederParameters, q, qd, payload) -> np.ndarray:
    """C q̇ + g, shape (..., 4)."""
    c = coriolis_matrix(p, q, qd, payload)
    return np.einsum("...ij,...j->...i", c, qd) + gravity_vector(p, q, payload)


def forward_dynamics(
    p: FeederParameters,
    q: np.ndarray,
    qd: np.ndarray,
    tau: np.ndarray,
    payload: bool | np.ndarray = True,
) -> tuple[np.ndarray, np.ndarray]:
    """q̈ and λ from the generalized forces: eqs. (46)–(47) differentiated twice,

        [M  J_fᵀ; J_f  0] [q̈; λ] = [τ − C q̇ − g; −J̇_f q̇].

    Args:
        p: Device parameters.
        q, qd: Assembled state [φ1, r2, φ3, φ4] and its rates, (..., 4).
        tau: Generalized forces [N·m, N, N·m, N·m], (..., 4) (τ1 = τ3 = 0 for the real drive).
        payload: Payload held (bool or (...,) 0/1).

    Returns:
        q̈ (..., 4) and λ (..., 2) [N] (the force of the piston on the arm, world x, y).
    """
    q, qd, tau = _coordinates("q", q), _coordinates("qd", qd), _coordinates("tau", tau)
    shape = np.broadcast_shapes(q.shape, qd.shape, tau.shape)[:-1]
    jac = np.broadcast_to(closure_jacobian(p, q), (*shape, 2, 4))
    kkt = np.zeros((*shape, 6, 6))
    kkt[..., :4, :4] = mass_matrix(p, q, payload)
    kkt[..., :4, 4:] = np.swapaxes(jac, -1, -2)
    kkt[..., 4:, :4] = jac
    rhs = np.concatenate(
        [tau - _generalized_forces(p, q, qd, payload), -closure_bias(p, q, qd)], axis=-1
    )
    solution = np.linalg.solve(kkt, rhs[..., None])[..., 0]
    return solution[..., :4], solution[..., 4:]


def inverse_dynamics(
    p: FeederParameters,
    q: np.ndarray,
    qd: np.ndarray,
    qdd: np.ndarray,
    payload: bool | np.ndarray = True,
) -> tuple[np.ndarray, np.ndarray]:
    """Actuator loads and λ from the motion, φ1 and φ3 passive (eq. 46 solved for τ2, τ4, λ).

    Closed form, all samples at once (no matrices): h = M q̈ + C q̇ + g from the nonzero
    entries of M, ∂M/∂q and g, with C q̇ of eq. (27) written out (module docstring); then λ
    from rows 1 and 3 by Cramer's rule, τ2 and τ4 from rows 2 and 4.

    Args:
        p: Device parameters.
        q, qd, qdd: Assembled, consistent motion [φ1, r2, φ3, φ4] and derivatives, (..., 4).
        payload: Payload held (bool or (...,) 0/1).

    Returns:
        tau (..., 4) = [0, F, 0, τ4]: the piston force F [N] along ``piston_joint`` and the
        forearm moment τ4 [N·m] about ``forearm_joint``; λ (..., 2) [N].

    Raises:
        SingularPoseError: Piston axis along the arm lever (sin(φ1 − φ3) ≈ 0).
    """
    q, qd, qdd = _coordinates("q", q), _coordinates("qd", qd), _coordinates("qdd", qdd)
    t = _terms(p, q, payload)
    qd1, qd2, qd3, qd4 = np.moveaxis(qd, -1, 0)
    qdd1, qdd2, qdd3, qdd4 = np.moveaxis(qdd, -1, 0)
    h1 = t.m11 * qdd1 + t.a1_2 * (qd1 * qd2) + t.g1
    h2 = p.piston.mass * qdd2 - 0.5 * t.a1_2 * qd1**2 + t.g2
    h3 = t.m33 * qdd3 + t.m34 * qdd4 + (t.a3_12 * qd3 + t.a3_16 * qd4) * qd4 + t.g3
    h4 = t.m34 * qdd3 + t.m44 * qdd4 - 0.5 * t.a3_12 * qd3**2 + t.g4
    transmission = t.s1 * t.c3 - t.c1 * t.s3  # sin(φ1 − φ3)
    if np.any(np.abs(transmission) < TOGGLE_TOLERANCE):
        k = int(np.argmin(np.abs(transmission)))
        raise SingularPoseError(
            f"piston axis along the arm lever: sin(φ1 − φ3) = {np.ravel(transmission)[k]:.3e} "
            f"at q = {np.reshape(q, (-1, 4))[k]}; the pin force is not determined"
        )
    reach = q[..., 1] + p.d2
    d3_h1, reach_h3 = p.d3 * h1, reach * h3
    inverse_det = 1.0 / (p.d3 * reach * transmission)
    lam1 = (d3_h1 * t.c3 + reach_h3 * t.c1) * inverse_det
    lam2 = (d3_h1 * t.s3 + reach_h3 * t.s1) * inverse_det
    zero = np.zeros_like(lam1)
    tau = np.stack(np.broadcast_arrays(zero, h2 + t.c1 * lam1 + t.s1 * lam2, zero, h4), axis=-1)
    return tau, np.stack([lam1, lam2], axis=-1)


@dataclass(frozen=True)
class LagrangeLoads:
    """A cycle's actuator loads and multipliers from the hand-derived equations; arrays (N,).

    Attributes:
        piston_force: F [N], along ``piston_joint``'s axis.
        forearm_torque: τ4 [N·m], about ``forearm_joint``'s axis.
        lambda1, lambda2: λ [N] of the closure equations f1 (x), f2 (y) (eq. 44 corrected).
    """

    piston_force: np.ndarray
    forearm_torque: np.ndarray
    lambda1: np.ndarray
    lambda2: np.ndarray

    def columns(self) -> dict[str, np.ndarray]:
        """The contract's ``lagrange_*`` columns of ``cycle.csv`` by name."""
        return {
            "lagrange_piston_force": self.piston_force,
            "lagrange_forearm_torque": self.forearm_torque,
            "lagrange_lambda1": self.lambda1,
            "lagrange_lambda2": self.lambda2,
        }


def lagrange_cycle_loads(feeder: Feeder, cycle: CycleKinematics) -> LagrangeLoads:
    """Inverse dynamics of a whole cycle from the hand-derived equations (vectorised).

    The payload is held where ``cycle.payload`` is 1 (from the end of stage 1).
    """
    tau, lam = inverse_dynamics(feeder.params, cycle.q, cycle.v, cycle.a, cycle.payload)
    return LagrangeLoads(
        piston_force=tau[:, 1], forearm_torque=tau[:, 3], lambda1=lam[:, 0], lambda2=lam[:, 1]
    )
