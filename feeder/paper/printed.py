"""The paper's equations (30)–(46) as printed, typos included, evaluated on a motion.

The printed equations use scalar moments I1 … I4 "about axes through the centres of gravity";
we read them as the moments about the axes each link turns about in the paper's own model:
I1 = I_cylinder,z, I2 = I_piston,z, I3 = I_arm,z (the pivot axis z) and I4 = I_forearm,y (the
forearm hinge, eq. 38). Lengths, masses and moments are the same
:class:`~feeder.device.parameters.FeederParameters` as the corrected model uses
(:mod:`feeder.paper.lagrange`), so every difference comes from the equations alone.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..device.parameters import FeederParameters
from ..validation import check_finite, check_samples
from .bodies import G
from .lagrange import check_passive_rows


@dataclass(frozen=True)
class PrintedEquations:
    """The paper's equations as printed, evaluated on N samples (arrays with leading shape N).

    Attributes:
        r4: Forearm CG (30) [m], (N, 3).
        j_t: J_T1 … J_T4 (31)–(34), (N, 4, 3, 4).
        j_r: J_R1 … J_R4 (35)–(38), (N, 4, 3, 4).
        mass_matrix: M (40), (N, 4, 4).
        mass_matrix_derivative: ∂M/∂q, the a_ij listed after (40), (N, 4, 16).
        coriolis: C (41), (N, 4, 4).
        potential: Π (42) [J], (N,).
        gravity: g (43), (N, 4).
        closure: f (44) [m], (N, 2).
        closure_jacobian: J_f (44), (N, 2, 4).
        piston_force, forearm_torque: τ2 [N] and τ4 [N·m] solved from (46) with τ1 = τ3 = 0,
            (N,).
        lambdas: λ solved from (46) [N], (N, 2).
    """

    r4: np.ndarray
    j_t: np.ndarray
    j_r: np.ndarray
    mass_matrix: np.ndarray
    mass_matrix_derivative: np.ndarray
    coriolis: np.ndarray
    potential: np.ndarray
    gravity: np.ndarray
    closure: np.ndarray
    closure_jacobian: np.ndarray
    piston_force: np.ndarray
    forearm_torque: np.ndarray
    lambdas: np.ndarray


def _samples(name: str, value: np.ndarray) -> np.ndarray:
    """``value`` as a finite (N, 4) array of [φ1, r2, φ3, φ4] (one state may be given as (4,))."""
    return check_samples(name, np.atleast_2d(check_finite(name, value)), 4, "[φ1, r2, φ3, φ4]")


def _symbols(p: FeederParameters, q: np.ndarray) -> dict[str, np.ndarray | float]:
    q = _samples("q", q)
    return {
        "m1": p.cylinder.mass,
        "m2": p.piston.mass,
        "m3": p.arm.mass,
        "m4": p.forearm.mass,
        "I1": p.cylinder.moments[2],
        "I2": p.piston.moments[2],
        "I3": p.arm.moments[2],
        "I4": p.forearm.moments[1],
        "q2": q[:, 1],
        "c1": np.cos(q[:, 0]),
        "s1": np.sin(q[:, 0]),
        "c3": np.cos(q[:, 2]),
        "s3": np.sin(q[:, 2]),
        "c4": np.cos(q[:, 3]),
        "s4": np.sin(q[:, 3]),
        "P1": q[:, 1] + p.d2,
    }


def printed_eq45(p: FeederParameters, q: np.ndarray, lam: np.ndarray) -> np.ndarray:
    """The vector printed in (45) (labelled −J_fᵀ λ) [N·m, N, N·m, N·m], (N, 4)."""
    s = _symbols(p, q)
    lam = np.atleast_2d(lam)
    l1, l2 = lam[:, 0], lam[:, 1]
    return np.stack(
        [
            -s["P1"] * l1 * s["s1"] + s["P1"] * l2 * s["c1"],
            l1 * s["c1"] + l2 * s["s1"],
            p.d3 * l1 * s["s3"] + p.d3 * l2 * s["c3"],
            np.zeros_like(l1),
        ],
        axis=-1,
    )


def printed_eq46_terms(
    p: FeederParameters, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Eq. (46) as printed, split as h + Λ λ = τ: h (N, 4) and the λ coefficients Λ (N, 4, 2)."""
    s = _symbols(p, q)
    qd, qdd = _samples("qd", qd), _samples("qdd", qdd)
    m1, m2, m3, m4, q2 = s["m1"], s["m2"], s["m3"], s["m4"], s["q2"]
    c1, s1, c3, s3, c4, s4 = s["c1"], s["s1"], s["c3"], s["s3"], s["c4"], s["s4"]
    reach = p.a1 + p.e * c4
    h = np.stack(
        [
            (s["I1"] + s["I2"] + m1 * p.l1**2 + m2 * q2**2) * qdd[:, 0]
            + 2 * m2 * q2 * qd[:, 1] * qd[:, 0]
            + (m1 * G * p.l1 + m2 * G * q2) * c1,
            m2 * qdd[:, 1] - 2 * m2 * q2 * qd[:, 0] * qd[:, 1] + m2 * G * s1,
            (s["I3"] + m3 * p.l3**2 + m4 * reach**2) * qdd[:, 2]
            - 2 * m4 * reach * s4 * qd[:, 3] * qd[:, 2]
            - (m3 * G * p.l3 - m4 * G * reach) * c3,
            (s["I4"] + m4 * p.e**2 * c4**2) * qdd[:, 3]
            + m4 * reach * s4 * qd[:, 2] ** 2
            - m4 * p.e**2 * c4 * s4 * qd[:, 3] ** 2,
        ],
        axis=-1,
    )
    zero = np.zeros_like(c1)
    coefficients = np.stack(
        [
            np.stack([-s["P1"] * s1, -s["P1"] * c1], -1),
            np.stack([-c1, -s1], -1),
            np.stack([-p.d3 * s3, -p.d3 * c3], -1),
            np.stack([zero, zero], -1),
        ],
        axis=-2,
    )
    return h, coefficients


def solve_passive(
    h: np.ndarray, coefficients: np.ndarray, q: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Solve h + Λ λ = τ with τ1 = τ3 = 0 (φ1, φ3 passive) for λ (N, 2) and τ (N, 4).

    Raises:
        SingularPoseError: Rows 1 and 3 do not determine λ: the angle between their λ
            coefficients is within 5° of 0° or 180°
            (:func:`~feeder.paper.lagrange.check_passive_rows`); q (N, 4) for the message.
    """
    passive = coefficients[:, [0, 2], :]
    row_norms = np.linalg.norm(passive, axis=2)
    check_passive_rows(np.linalg.det(passive) / (row_norms[:, 0] * row_norms[:, 1]), q)
    lam = np.linalg.solve(passive, -h[:, [0, 2], None])[..., 0]
    tau = h + np.einsum("nij,nj->ni", coefficients, lam)
    tau[:, [0, 2]] = 0.0
    return lam, tau


def printed_equations(
    p: FeederParameters, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray
) -> PrintedEquations:
    """Evaluate the paper's (30)–(46) exactly as printed on samples q, q̇, q̈ of shape (N, 4)."""
    s = _symbols(p, q)
    m2, m4, q2 = s["m2"], s["m4"], s["q2"]
    c1, s1, c3, s3, c4, s4 = s["c1"], s["s1"], s["c3"], s["s3"], s["c4"], s["s4"]
    qd = _samples("qd", qd)
    n = c1.size
    reach = p.a1 + p.e * c4
    r4 = np.stack(
        [p.L1 + reach * c3, p.L2 - p.f - p.d + reach * s3, p.c - p.e * s4], axis=-1
    )  # (30)
    j_t = np.zeros((n, 4, 3, 4))
    j_t[:, 0, 0, 0], j_t[:, 0, 1, 0] = -p.l1 * s1, p.l1 * c1  # (31)
    j_t[:, 1, 0, 0], j_t[:, 1, 1, 0] = -q2 * s1, q2 * c1  # (32)
    j_t[:, 1, 0, 1], j_t[:, 1, 1, 1] = c1, s1
    j_t[:, 2, 0, 2], j_t[:, 2, 1, 2] = -p.l3 * s3, p.l3 * c3  # (33)
    j_t[:, 3, 0, 2], j_t[:, 3, 1, 2] = -reach * s3, reach * c3  # (34)
    j_t[:, 3, 0, 3] = (p.a1 - p.e * s4) * c3
    j_t[:, 3, 1, 3] = (p.a1 - p.e * s4) * s3
    j_t[:, 3, 2, 3] = -p.e * c4
    j_r = np.zeros((n, 4, 3, 4))
    j_r[:, 0, 2, 0] = j_r[:, 1, 2, 0] = j_r[:, 2, 2, 2] = j_r[:, 3, 1, 3] = 1.0  # (35)–(38)
    mass = np.zeros((n, 4, 4))  # (40)
    mass[:, 0, 0] = s["m1"] * p.l1**2 + m2 * q2**2 + s["I1"] + s["I2"]
    mass[:, 1, 1] = m2
    mass[:, 2, 2] = s["m3"] * p.l3**2 + m4 * reach**2 + s["I3"]
    mass[:, 3, 3] = m4 * p.e**2 * c4**2 + s["I4"]
    d_mass = np.zeros((n, 4, 16))  # the a_ij after (40), 1-based a_{1,2}, a_{3,12}, a_{4,16}
    d_mass[:, 0, 1] = 2 * m2 * q2
    d_mass[:, 2, 11] = -2 * m4 * reach * s4
    d_mass[:, 3, 15] = -2 * m4 * p.e**2 * c4 * s4
    coriolis = np.zeros((n, 4, 4))  # (41)
    coriolis[:, 0, 0] = 2 * m2 * q2 * qd[:, 1]
    coriolis[:, 1, 0] = -m2 * q2 * qd[:, 0]
    coriolis[:, 2, 2] = -2 * m4 * reach * s4 * qd[:, 3]
    coriolis[:, 3, 2] = m4 * reach * s4 * qd[:, 2]
    coriolis[:, 3, 3] = -m4 * p.e**2 * c4 * s4 * qd[:, 3]
    potential = (
        0.5
        * G
        * (  # (42)
            s["m1"] * p.l1 * s1
            + m2 * q2 * s1
            + s["m3"] * (p.L2 - p.l3 * s3)
            + m4 * (p.L2 - p.f - p.d + (p.a + p.b + p.e * c4) * s3)
        )
    )
    gravity = 0.5 * np.stack(  # (43)
        [
            (s["m1"] * G * p.l1 + m2 * G * q2) * c1,
            m2 * G * s1,
            -(s["m3"] * G * p.l3 - m4 * G * reach) * c3,
            -m4 * G * p.e * s3 * s4,
        ],
        axis=-1,
    )
    closure = np.stack(  # (44)
        [s["P1"] * c1 - p.d3 * c3 - p.L1, s["P1"] * s1 + p.d3 * s3 - p.L2], axis=-1
    )
    closure_jacobian = np.zeros((n, 2, 4))
    closure_jacobian[:, 0] = np.stack([-s["P1"] * s1, c1, p.d3 * s3, np.zeros(n)], -1)
    closure_jacobian[:, 1] = np.stack([s["P1"] * c1, s1, p.d3 * c3, np.zeros(n)], -1)
    lam, tau = solve_passive(*printed_eq46_terms(p, q, qd, qdd), q)  # (46)
    return PrintedEquations(
        r4=r4,
        j_t=j_t,
        j_r=j_r,
        mass_matrix=mass,
        mass_matrix_derivative=d_mass,
        coriolis=coriolis,
        potential=potential,
        gravity=gravity,
        closure=closure,
        closure_jacobian=closure_jacobian,
        piston_force=tau[:, 1],
        forearm_torque=tau[:, 3],
        lambdas=lam,
    )
