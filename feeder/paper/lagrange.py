"""The paper's Lagrange equations of the feeder (sections III–IV), corrected, vectorised.

Generalized coordinates q = [φ1, r2, φ3, φ4] = [q1, q2, q3, q4] (eq. 29); every function takes
arrays of shape (..., 4) (one state or N time samples) and returns arrays with the same leading
shape. World frame: x horizontal, y up, z along the pivots; gravity −y, g = 9.81 m/s².
Abbreviations: c_i = cos q_i, s_i = sin q_i, A = (L1, L2) the arm pivot, P1 = q2 + d2.

The bodies, their Jacobians and inertias are in :mod:`feeder.paper.bodies`.

**Inertia matrix** (eq. 17 = eq. 39 summed over the five bodies; corrected eq. 40), with
(I_bx, I_by, I_bz) the central moments of body b in its link frame, sums over b ∈ {4, 5}
(5 only while the payload is held):

    M11 = I1z + I2z + m1 l1² + m2 q2²,        M22 = m2,
    M33 = I3z + m3 l3² + Σ_b [m_b (ρx_b² + ρy_b²) + I_bx s4² + I_bz c4²],
    M44 = Σ_b [m_b (p_bx² + p_bz²) + I_by],   M34 = M43 = −Σ_b m_b ρy_b w_b,

all other entries zero. **∂M/∂q** (eq. 4 layout, entry (i, 4 (j−1) + k) = ∂M_ij/∂q_k, 1-based):
a_{1,2} = 2 m2 q2, a_{3,12} = Σ_b [2 m_b ρx_b w_b + (I_bx − I_bz) sin 2q4],
a_{3,16} = a_{4,12} = Σ_b m_b ρy_b u_b, every other a_ij = 0 (a_{4,16} = 0: M44 is constant).
**C** from the Kronecker formula (27) (:func:`.coriolis.kronecker_coriolis`). Written out
with these a_ij, (C q̇)_i = Σ_jk ∂M_ij/∂q_k q̇_j q̇_k − ½ Σ_jk ∂M_jk/∂q_i q̇_j q̇_k is

    C q̇ = [a_{1,2} q̇1 q̇2,  −½ a_{1,2} q̇1²,  a_{3,12} q̇3 q̇4 + a_{3,16} q̇4²,  −½ a_{3,12} q̇3²]

(in row 4 the a_{4,12} q̇3 q̇4 of the first sum and the a_{3,16} q̇3 q̇4 of the second cancel).

**Gravity** (Π = Σ m_i g y_i, eq. 42 corrected; g = (∂Π/∂q)ᵀ, eq. 43 corrected):

    g1 = g (m1 l1 + m2 q2) c1,   g2 = g m2 s1,
    g3 = g [m3 l3 c3 + Σ_b m_b (ρx_b c3 − ρy_b s3)],   g4 = g Σ_b m_b w_b s3.

**Closure** (eq. 44 corrected: the pin P = A + d3 (c3, s3) = P1 (c1, s1), as in
:mod:`feeder.device.loop`, written independently in :mod:`feeder.paper.closure`):

    f = [P1 c1 − d3 c3 − L1;  P1 s1 − d3 s3 − L2],
    J_f = [−P1 s1  c1  d3 s3  0;  P1 c1  s1  −d3 c3  0],
    J̇_f q̇ = [−2 s1 q̇1 q̇2 − P1 c1 q̇1² + d3 c3 q̇3²;  2 c1 q̇1 q̇2 − P1 s1 q̇1² + d3 s3 q̇3²].

**Equations of motion** (eqs. 28, 46–47): M q̈ + C q̇ + g = τ − J_fᵀ λ, J_f q̈ = −J̇_f q̇.
Since f = p_piston_pin − p_arm_pin, the pin force that the arm exerts on the piston is −λ
(world x, y) [N]: λ is the force of the piston on the arm. The actuators are the piston force
τ2 = F [N] on ``piston_joint`` and the rack moment τ4 [N·m] on ``forearm_joint``; φ1 and φ3 are
passive (τ1 = τ3 = 0). Inverse dynamics (:func:`lagrange_loads`: these closed forms, every
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

from ..device.parameters import SINGULAR_TRANSMISSION_DEG, FeederParameters
from ..exceptions import SingularPoseError
from .bodies import (
    G,
    coordinates,
    grip_weight,
    held_geometry,
    held_points,
    per_body,
)
from .coriolis import kronecker_coriolis


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


def _terms(p: FeederParameters, q: np.ndarray, gripped: bool | np.ndarray) -> _Terms:
    """Every formula of M, ∂M/∂q and g (module docstring), each trigonometric function of q
    evaluated once, for checked q of shape (..., 4) and grip flags (bool or (...) 0/1)."""
    flag = grip_weight(gripped, q.shape[:-1])
    r2 = q[..., 1]
    c1, s1 = np.cos(q[..., 0]), np.sin(q[..., 0])
    c3, s3 = np.cos(q[..., 2]), np.sin(q[..., 2])
    c4, s4 = np.cos(q[..., 3]), np.sin(q[..., 3])
    points, masses, moments = held_points(p)
    m, ix, iy, iz, px2_pz2 = (
        per_body(x, c4.ndim) for x in (masses, *moments.T, points[:, 0] ** 2 + points[:, 2] ** 2)
    )
    u, w, rx, ry = held_geometry(p, c4, s4)

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
    p: FeederParameters, q: np.ndarray, gripped: bool | np.ndarray = True
) -> np.ndarray:
    """M(q) of the feeder (corrected eq. 40, closed form; see the module docstring), (..., 4, 4).

    Args:
        p: Device parameters.
        q: [φ1, r2, φ3, φ4], shape (..., 4).
        gripped: Whether the forearm holds the payload (body 5), bool or (...,) array of 0/1.
    """
    q = coordinates("q", q)
    t = _terms(p, q, gripped)
    m = np.zeros((*q.shape[:-1], 4, 4))
    m[..., 0, 0] = t.m11
    m[..., 1, 1] = p.piston.mass
    m[..., 2, 2] = t.m33
    m[..., 3, 3] = t.m44
    m[..., 2, 3] = m[..., 3, 2] = t.m34
    return m


def mass_matrix_gradient(
    p: FeederParameters, q: np.ndarray, gripped: bool | np.ndarray = True
) -> np.ndarray:
    """∂M/∂q (eq. 4 layout: entry (i, 4 j + k) = ∂M_ij/∂q_k, 0-based), shape (..., 4, 16).

    Closed form: the derivatives of the entries of :func:`mass_matrix` (module docstring).
    """
    q = coordinates("q", q)
    t = _terms(p, q, gripped)
    d = np.zeros((*q.shape[:-1], 4, 4, 4))  # d[..., i, j, k] = ∂M_ij/∂q_k
    d[..., 0, 0, 1] = t.a1_2
    d[..., 2, 2, 3] = t.a3_12
    d[..., 2, 3, 3] = d[..., 3, 2, 3] = t.a3_16
    return d.reshape(*q.shape[:-1], 4, 16)


def coriolis_matrix(
    p: FeederParameters, q: np.ndarray, qd: np.ndarray, gripped: bool | np.ndarray = True
) -> np.ndarray:
    """C(q, q̇) of eq. (27) (Kronecker-product form), shape (..., 4, 4)."""
    qd = coordinates("qd", qd)
    return kronecker_coriolis(mass_matrix_gradient(p, q, gripped), qd)


def gravity_vector(
    p: FeederParameters, q: np.ndarray, gripped: bool | np.ndarray = True
) -> np.ndarray:
    """g(q) = (∂Π/∂q)ᵀ (eq. 43, corrected, closed form), [N·m, N, N·m, N·m], shape (..., 4)."""
    q = coordinates("q", q)
    t = _terms(p, q, gripped)
    return np.stack([t.g1, t.g2, t.g3, t.g4], axis=-1)


@dataclass(frozen=True)
class LagrangeLoads:
    """Actuator loads and multipliers from the hand-derived equations (eq. 46 solved).

    Attributes:
        tau: Generalized forces [0, F, 0, τ4], shape (..., 4): the piston force F [N] along
            ``piston_joint``'s axis and the forearm moment τ4 [N·m] about ``forearm_joint``'s.
        lambdas: λ [N] of the closure equations f1 (x), f2 (y) (eq. 44 corrected), (..., 2):
            the force of the piston on the arm, world x, y.
    """

    tau: np.ndarray
    lambdas: np.ndarray

    @property
    def piston_force(self) -> np.ndarray:
        """F [N], shape (...)."""
        return self.tau[..., 1]

    @property
    def forearm_torque(self) -> np.ndarray:
        """τ4 [N·m], shape (...)."""
        return self.tau[..., 3]


def lagrange_loads(
    p: FeederParameters,
    q: np.ndarray,
    qd: np.ndarray,
    qdd: np.ndarray,
    gripped: bool | np.ndarray = True,
) -> LagrangeLoads:
    """Actuator loads and λ from the motion, φ1 and φ3 passive (eq. 46 solved for τ2, τ4, λ).

    Closed form, all samples at once (no matrices): h = M q̈ + C q̇ + g from the nonzero
    entries of M, ∂M/∂q and g, with C q̇ of eq. (27) written out (module docstring); then λ
    from rows 1 and 3 by Cramer's rule, τ2 and τ4 from rows 2 and 4.

    Args:
        p: Device parameters.
        q, qd, qdd: Assembled, consistent motion [φ1, r2, φ3, φ4] and derivatives, (..., 4).
        gripped: Payload held (bool or (...,) 0/1).

    Raises:
        SingularPoseError: A pose within
            :data:`~feeder.device.parameters.SINGULAR_TRANSMISSION_DEG` of the toggle, where
            rows 1 and 3 cannot give λ (|sin(φ1 − φ3)| < sin 5°).
    """
    q, qd, qdd = coordinates("q", q), coordinates("qd", qd), coordinates("qdd", qdd)
    t = _terms(p, q, gripped)
    qd1, qd2, qd3, qd4 = np.moveaxis(qd, -1, 0)
    qdd1, qdd2, qdd3, qdd4 = np.moveaxis(qdd, -1, 0)
    h1 = t.m11 * qdd1 + t.a1_2 * (qd1 * qd2) + t.g1
    h2 = p.piston.mass * qdd2 - 0.5 * t.a1_2 * qd1**2 + t.g2
    h3 = t.m33 * qdd3 + t.m34 * qdd4 + (t.a3_12 * qd3 + t.a3_16 * qd4) * qd4 + t.g3
    h4 = t.m34 * qdd3 + t.m44 * qdd4 - 0.5 * t.a3_12 * qd3**2 + t.g4
    transmission = t.s1 * t.c3 - t.c1 * t.s3  # sin(φ1 − φ3)
    check_passive_rows(transmission, q)
    reach = q[..., 1] + p.d2
    d3_h1, reach_h3 = p.d3 * h1, reach * h3
    inverse_det = 1.0 / (p.d3 * reach * transmission)
    lam1 = (d3_h1 * t.c3 + reach_h3 * t.c1) * inverse_det
    lam2 = (d3_h1 * t.s3 + reach_h3 * t.s1) * inverse_det
    zero = np.zeros_like(lam1)
    tau = np.stack(np.broadcast_arrays(zero, h2 + t.c1 * lam1 + t.s1 * lam2, zero, h4), axis=-1)
    return LagrangeLoads(tau=tau, lambdas=np.stack([lam1, lam2], axis=-1))


def check_passive_rows(sine: np.ndarray, q: np.ndarray) -> None:
    """Raise :class:`SingularPoseError` where the passive rows 1 and 3 of eq. (46) do not
    determine λ well: ``sine`` (...), the sine of the angle between the two rows' λ
    coefficients (for the feeder sin(φ1 − φ3), the transmission angle's), below sin 5°
    (:data:`~feeder.device.parameters.SINGULAR_TRANSMISSION_DEG`, the package's one toggle
    threshold); q (..., 4) for the message."""
    sine = np.abs(np.ravel(sine))
    if np.any(sine < np.sin(np.radians(SINGULAR_TRANSMISSION_DEG))):
        k = int(np.argmin(sine))
        raise SingularPoseError(
            f"piston axis within {SINGULAR_TRANSMISSION_DEG:g}° of the arm lever: |sin(φ1 − φ3)| "
            f"= {sine[k]:.3e} at q = {np.reshape(q, (-1, 4))[k]}; the pin force is not determined"
        )
