"""The paper's equations (30)–(47) as printed, and the errata table that compares them with ours.

:func:`printed_equations` evaluates the printed formulas literally (typos included) on a given
motion; :func:`errata_rows` measures each erratum on the reference cycle (projectile feeder,
elevation −4°, default :class:`~feeder.cycle.CycleSpec`) against the corrected equations of
:mod:`feeder.lagrange`; :func:`errata_markdown` renders the published table ``ERRATA.md``.
Regenerate it with ``python -m feeder.errata [path]``.

The printed equations use scalar moments I1 … I4 "about axes through the centres of gravity";
we read them as the moments about the axes each link turns about in the paper's own model:
I1 = I_cylinder,z, I2 = I_piston,z, I3 = I_arm,z (the pivot axis z) and I4 = I_forearm,y (the
forearm hinge, eq. 38). Lengths, masses and moments are the same :class:`FeederParameters` as
the corrected model uses, so every difference comes from the equations alone.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from . import lagrange
from .coriolis import kronecker_coriolis
from .cycle import CycleKinematics, feeding_cycle
from .device import Feeder, load_feeder
from .exceptions import InputError, SingularPoseError, check_finite
from .lagrange import G
from .parameters import FeederParameters

TABLE_I_PRINTED_MOMENTS = {
    "piston": (4.160e-2, 1.054e-2, 1.058e-2),
    "arm": (0.238e-2, 5.036e-2, 0.278e-2),
}
"""Table I's printed moments [kg·m²] of the two links whose tensors are not physical, in our
link-frame axes (the piston's table x/y exchanged, as in :mod:`feeder.parameters`)."""

REFERENCE_ELEVATION = math.radians(-4.0)
"""Elevation [rad] of the reference cycle: the longest arm travel (94°), paper Fig. 4."""


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
    array = np.atleast_2d(check_finite(name, value))
    if array.ndim != 2 or array.shape[1] != 4:
        raise InputError(f"{name} must have shape (N, 4) = [φ1, r2, φ3, φ4], got {array.shape}")
    return array


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


def solve_passive(h: np.ndarray, coefficients: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Solve h + Λ λ = τ with τ1 = τ3 = 0 (φ1, φ3 passive) for λ (N, 2) and τ (N, 4).

    Raises:
        SingularPoseError: Rows 1 and 3 do not determine λ.
    """
    passive = coefficients[:, [0, 2], :]
    det = np.linalg.det(passive)
    scale = np.abs(passive).max(axis=(1, 2)) ** 2
    if np.any(np.abs(det) <= 1e-12 * scale):
        k = int(np.argmin(np.abs(det) / scale))
        raise SingularPoseError(f"rows 1 and 3 of (46) do not determine λ at sample {k}")
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
    lam, tau = solve_passive(*printed_eq46_terms(p, q, qd, qdd))  # (46)
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


@dataclass(frozen=True)
class Erratum:
    """One row of the errata table (text in Markdown with Unicode maths)."""

    equation: str
    printed: str
    corrected: str
    why: str
    consequence: str


def _peak(x: np.ndarray) -> float:
    return float(np.max(np.abs(x)))


def _q(value: float, unit: str, scale: float = 0.0) -> str:
    """A measured value with 4 significant digits; non-zero round-off (≤ 1e-12 ``scale``) as
    "0 (to round-off)"."""
    if value != 0.0 and abs(value) <= 1e-12 * scale:
        return " ".join(filter(None, ("0", unit, "(to round-off)")))
    return f"{value:.4g} {unit}".rstrip()


def _loads(p: FeederParameters, cycle: CycleKinematics, payload) -> tuple[np.ndarray, ...]:
    tau, lam = lagrange.inverse_dynamics(p, cycle.q, cycle.v, cycle.a, payload)
    return tau[:, 1], tau[:, 3], lam


def errata_rows(feeder: Feeder, cycle: CycleKinematics) -> list[Erratum]:
    """Every erratum with its consequence measured on ``cycle`` (see the module docstring)."""
    p, q, qd, qdd, held = feeder.params, cycle.q, cycle.v, cycle.a, cycle.payload
    printed = printed_equations(p, q, qd, qdd)
    force, torque, lam = _loads(p, cycle, held)
    mass = lagrange.mass_matrix(p, q, held)
    d_mass = lagrange.mass_matrix_derivative(p, q, held)
    coriolis = lagrange.coriolis_matrix(p, q, qd, held)
    gravity = lagrange.gravity_vector(p, q, held)
    forearm = lagrange.body_positions(p, q)[:, 3]
    j_t4 = lagrange.translational_jacobians(p, q)[:, 3]
    j_r4 = lagrange.rotational_jacobians(p, q)[:, 3]
    deg = np.degrees

    table_i = replace(
        p, **{k: replace(getattr(p, k), moments=v) for k, v in TABLE_I_PRINTED_MOMENTS.items()}
    )
    force_t, torque_t, _ = _loads(table_i, cycle, held)
    gap = np.linalg.norm(printed.r4 - forearm, axis=-1)
    k_gap = int(np.argmax(gap))
    omega = np.einsum("nij,nj->ni", j_r4 - printed.j_r[:, 3], qd)
    moments = np.array([link.moments for link in list(p.links().values())[:4]])
    m39 = lagrange.mass_matrix_from_jacobians(
        lagrange.body_masses(p)[:4],
        printed.j_t,
        printed.j_r,
        np.stack([np.diag(m) for m in moments]),
    )
    c_q = np.einsum("nij,nj->ni", coriolis, qd)
    c_q_printed = np.einsum("nij,nj->ni", printed.coriolis, qd)
    kron_printed = kronecker_coriolis(printed.mass_matrix_derivative, qd)
    dg = np.abs(printed.gravity - gravity).max(axis=0)
    c3 = np.cos(q[:, 2])
    arm_term = p.arm.mass * G * p.l3 * c3 - (-0.5 * p.arm.mass * G * p.l3 * c3)
    jt_printed = np.einsum("nji,nj->ni", printed.closure_jacobian, lam)
    eq45 = printed_eq45(p, q, lam)

    h46, coefficients = printed_eq46_terms(p, q, qd, qdd)
    _, tau46 = solve_passive(h46, coefficients)
    sin_sum, sin_difference = np.sin(q[:, 0] + q[:, 2]), np.sin(q[:, 0] - q[:, 2])
    k_sum = int(np.argmin(np.abs(sin_sum)))
    h_row2 = h46.copy()
    m2q2 = p.piston.mass * q[:, 1]
    h_row2[:, 1] += 2 * m2q2 * qd[:, 0] * qd[:, 1] - m2q2 * qd[:, 0] ** 2
    _, tau_row2 = solve_passive(h_row2, coefficients)
    force_empty, torque_empty, _ = _loads(p, cycle, False)
    held_stage = held.astype(bool)

    return [
        Erratum(
            "Table I",
            "I2yy = 4.160e-2, I3yy = 5.036e-2 kg·m²",
            "I2yy = 4.160e-3, I3yy = 5.036e-3 kg·m² (one exponent digit)",
            "each exceeds the sum of its link's other two moments (I2yy > I2xx + I2zz, "
            "I3yy > I3xx + I3zz): no rigid body has such a tensor",
            "loads with the printed moments differ by "
            f"{_q(_peak(force_t - force), 'N', _peak(force))}"
            f" and {_q(_peak(torque_t - torque), 'N·m', _peak(torque))}: the piston and the arm "
            "turn only about z, so these moments never enter M",
        ),
        Erratum(
            "(30) x4, y4",
            "x4 = L1 + (a1 + e cos q4) cos q3; y4 = L2 − f − d + (a1 + e cos q4) sin q3",
            "x4 = L1 + (a1 + e cos q4) cos q3 + (f + d) sin q3; "
            "y4 = L2 + (a1 + e cos q4) sin q3 − (f + d) cos q3",
            "the offset f + d lies along the arm's y axis, which turns with the arm; the "
            "printed form holds only at q3 = 0",
            f"forearm CG misplaced by up to {_q(1e3 * gap[k_gap], 'mm')} "
            f"(at q3 = {deg(q[k_gap, 2]):.1f}°)",
        ),
        Erratum(
            "(42), (44) arm-angle sign",
            "(42): m3 g (L2 − l3 sin q3); (44): f2 = (q2 + d2) sin q1 + d3 sin q3 − L2, "
            "J_f row 2 = [(q2 + d2) cos q1, sin q1, d3 cos q3, 0]",
            "y3 = L2 + l3 sin q3 as in (30); pin at A + d3 (cos q3, sin q3): "
            "f2 = (q2 + d2) sin q1 − d3 sin q3 − L2, J_f row 2 = "
            "[(q2 + d2) cos q1, sin q1, −d3 cos q3, 0]",
            "(30) and f1 measure q3 counter-clockwise, (42) and f2 clockwise: the printed "
            "closure describes a mirrored arm",
            f"the real mechanism violates the printed closure f by up to "
            f"{_q(1e3 * _peak(printed.closure), 'mm')} along the cycle (corrected f: "
            f"{_q(1e3 * _peak(lagrange.closure_residual(p, q)), 'mm', 1.0)})",
        ),
        Erratum(
            "(34) J_T4",
            "column 4 = [(a1 − e sin q4) cos q3, (a1 − e sin q4) sin q3, −e cos q4]ᵀ",
            "column 4 = [−e sin q4 cos q3, −e sin q4 sin q3, −e cos q4]ᵀ; column 3 gains "
            "[(f + d) cos q3, (f + d) sin q3, 0]ᵀ from the corrected (30)",
            "a1 does not depend on q4: ∂x4/∂q4 of (30) itself is −e sin q4 cos q3",
            f"column 4 off by up to {_q(_peak(printed.j_t[:, 3, :, 3] - j_t4[:, :, 3]), 'm/rad')}",
        ),
        Erratum(
            "(38) J_R4",
            "w4 = [0, q̇4, 0]ᵀ",
            "w4 = q̇3 z + q̇4 (−sin q3, cos q3, 0)ᵀ; in the forearm frame "
            "(−q̇3 sin q4, q̇4, q̇3 cos q4)",
            "the forearm turns with the arm (q̇3) about an axis, the arm's y axis, that "
            "tilts with q3",
            f"forearm angular velocity off by up to {_q(_peak(omega), 'rad/s')}",
        ),
        Erratum(
            "(39)–(40) M33",
            "m3 l3² + m4 (a1 + e cos q4)² + I3",
            "I3z + m3 l3² + m4 [(a1 + e cos q4)² + (f + d)²] + I4x sin² q4 + I4z cos² q4 "
            "+ payload: m5 (ρx5² + ρy5²) + I5x sin² q4 + I5z cos² q4",
            "the offset f + d of (30), the forearm's rotation with the arm (38) and the "
            "payload (body 5, left out of the sum)",
            f"M33 off by up to {_q(_peak(printed.mass_matrix[:, 2, 2] - mass[:, 2, 2]), 'kg·m²')}"
            f" (corrected M33 up to {_q(_peak(mass[:, 2, 2]), 'kg·m²')})",
        ),
        Erratum(
            "(40) M44",
            "m4 e² cos² q4 + I4",
            "m4 e² + I4y + payload: m5 (e5² + z5²) + I5y (constant)",
            "the forearm CG moves on a circle of radius e about the hinge: |∂r4/∂q4| = e "
            "for every q4. (39) with the printed (34) gives yet another value, "
            "m4 [(a1 − e sin q4)² + e² cos² q4] + I4",
            f"M44 off by up to {_q(_peak(printed.mass_matrix[:, 3, 3] - mass[:, 3, 3]), 'kg·m²')}"
            f"; (39)+(34) and (40) disagree by up to "
            f"{_q(_peak(m39[:, 3, 3] - printed.mass_matrix[:, 3, 3]), 'kg·m²')}",
        ),
        Erratum(
            "(40) M34",
            "0",
            "M34 = M43 = −m4 e (f + d) sin q4 − m5 (h5 − f)(z5 cos q4 − e5 sin q4)",
            "the forearm and payload CGs lie below the arm axis (f + d, f − h5), which "
            "couples the arm and forearm rotations",
            f"|M34| up to {_q(_peak(mass[:, 2, 3]), 'kg·m²')}",
        ),
        Erratum(
            "(4) ∂M/∂q after (40)",
            "a3,12 = −2 m4 (a1 + e cos q4) sin q4; a4,16 = −2 m4 e² cos q4 sin q4; "
            "a3,16 = a4,12 = 0",
            "a3,12 = −2 m4 e (a1 + e cos q4) sin q4 + (I4x − I4z) sin 2q4 + payload; "
            "a4,16 = 0; a3,16 = a4,12 = −m4 e (f + d) cos q4 + payload",
            "∂(a1 + e cos q4)²/∂q4 = −2 e (a1 + e cos q4) sin q4: the factor e is missing; "
            "the rest follows from M. (The positions are right: a_{i,4(j−1)+k} = ∂M_ij/∂q_k.)",
            f"a3,12 off by up to "
            f"{_q(_peak(printed.mass_matrix_derivative[:, 2, 11] - d_mass[:, 2, 11]), 'kg·m²')}",
        ),
        Erratum(
            "(41) C",
            "C from (27) with the printed ∂M/∂q",
            "C from (27) with the corrected ∂M/∂q (eq. 27 itself is right; C is not the "
            "Christoffel matrix, see feeder.coriolis)",
            "(41) is (27) applied to the printed a_ij (largest entry difference: "
            f"{_q(_peak(kron_printed - printed.coriolis), '', _peak(printed.coriolis))}), so it "
            "inherits the errors of (40) and (4)",
            f"C q̇ off by up to {_q(_peak(c_q_printed[:, 2] - c_q[:, 2]), 'N·m')} (row 3) and "
            f"{_q(_peak(c_q_printed[:, 3] - c_q[:, 3]), 'N·m')} (row 4)",
        ),
        Erratum(
            "(42)–(43) Π, g",
            "Π = ½ m1 g l1 sin q1 + ½ m2 g q2 sin q1 + ½ m3 g (L2 − l3 sin q3) + ½ m4 g y4; "
            "g = ½ [...]",
            "Π = g Σ m_i y_i over the five bodies (no ½), y_i from the corrected (30); "
            "g as in feeder.lagrange",
            "the potential energy of a mass in uniform gravity is m g y; ½ belongs to the "
            "kinetic energy. With the sign of row 3, the arm's own gravity moment is "
            "−½ m3 g l3 cos q3 instead of m3 g l3 cos q3",
            f"g off by up to {_q(dg[0], 'N·m')}, {_q(dg[1], 'N')}, {_q(dg[2], 'N·m')}, "
            f"{_q(dg[3], 'N·m')} (rows 1–4); the arm term alone by "
            f"{_q(_peak(arm_term), 'N·m')}",
        ),
        Erratum(
            "(45)",
            "−J_fᵀ λ = [−(q2 + d2) λ1 sin q1 + (q2 + d2) λ2 cos q1, λ1 cos q1 + λ2 sin q1, "
            "d3 λ1 sin q3 + d3 λ2 cos q3, 0]ᵀ",
            "the printed vector is +J_fᵀ λ; −J_fᵀ λ with the corrected J_f = "
            "[(q2 + d2)(λ1 sin q1 − λ2 cos q1), −λ1 cos q1 − λ2 sin q1, "
            "−d3 (λ1 sin q3 − λ2 cos q3), 0]ᵀ",
            "sign: every entry is +(J_fᵀ λ) with (44)'s J_f",
            f"(45) − J_fᵀ λ = {_q(_peak(eq45 - jt_printed), 'N, N·m', _peak(jt_printed))}: a sign "
            "convention for λ only; τ is unaffected",
        ),
        Erratum(
            "(46) row 1",
            "… − (q2 + d2) λ1 sin q1 − (q2 + d2) λ2 cos q1 = τ1",
            "… + (q2 + d2) λ1 sin q1 − (q2 + d2) λ2 cos q1 = τ1 (rows 2–3 subtract (45); "
            "row 1 must too)",
            "row 1 subtracts (45)'s λ2 term but adds its λ1 term",
            "made consistent, rows 1 and 3 give λ through the determinant "
            "−(q2 + d2) d3 sin(q1 + q3), which passes through zero on the cycle "
            f"(|sin(q1 + q3)| down to {abs(sin_sum[k_sum]):.2g} at t = {cycle.t[k_sum]:.3f} s, "
            f"φ3 = {deg(q[k_sum, 2]):.1f}°): the slip cancels (44)'s mirrored arm. As printed the "
            f"determinant is (q2 + d2) d3 sin(q1 − q3), |sin(q1 − q3)| ≥ "
            f"{np.min(np.abs(sin_difference)):.3f}",
        ),
        Erratum(
            "(46) row 2",
            "m2 q̈2 − 2 m2 q2 q̇1 q̇2 + …",
            "m2 q̈2 − m2 q2 q̇1² + … (the centrifugal term of (41): C21 q̇1 = −m2 q2 q̇1²)",
            "(41) row 2 times q̇ is −m2 q2 q̇1²; (46) doubles it and replaces q̇1 by q̇2",
            f"piston force off by up to {_q(_peak(tau_row2[:, 1] - tau46[:, 1]), 'N')}",
        ),
        Erratum(
            "(46) rows 1–4 gravity",
            "rows 1–3: g without the ½ of (43); row 4: no gravity term",
            "g4 = g Σ_b m_b w_b sin q3 (forearm and payload), e.g. −m4 g e sin q3 sin q4 "
            "for the forearm alone",
            "(46) does not use (43) as printed; the forearm's gravity moment about its "
            "hinge, zero only while the arm is horizontal, is dropped",
            f"forearm torque misses up to {_q(_peak(gravity[:, 3]), 'N·m')} of gravity, "
            f"{_q(_peak(lagrange.gravity_vector(p, q, False)[:, 3]), 'N·m')} of it without the "
            "payload (the forearm's own term vanishes where q3 = 0 or q4 = 0)",
        ),
        Erratum(
            "(39), (46) payload",
            "sum over links 1–4 only",
            f"body 5, the {p.payload_name} ({p.payload.mass:g} kg), is part of the forearm "
            "from the end of stage 1",
            "the payload is carried by the forearm in stages 2–3 (Fig. 7)",
            f"without it the peak piston force in stages 2–3 drops from "
            f"{_q(_peak(force[held_stage]), 'N')} to "
            f"{_q(_peak(force_empty[held_stage]), 'N')}, the peak forearm torque from "
            f"{_q(_peak(torque[held_stage]), 'N·m')} to "
            f"{_q(_peak(torque_empty[held_stage]), 'N·m')}",
        ),
        Erratum(
            "(46)–(47) overall",
            "(46) as printed, τ1 = τ3 = 0",
            "M q̈ + C q̇ + g + J_fᵀ λ = τ with the corrected M, C, g, J_f (feeder.lagrange)",
            "all of the above",
            f"peak piston force {_q(_peak(printed.piston_force), 'N')} printed vs "
            f"{_q(_peak(force), 'N')} corrected; peak forearm torque "
            f"{_q(_peak(printed.forearm_torque), 'N·m')} vs {_q(_peak(torque), 'N·m')}; "
            f"peak |λ| {_q(_peak(np.linalg.norm(printed.lambdas, axis=-1)), 'N')} vs "
            f"{_q(_peak(np.linalg.norm(lam, axis=-1)), 'N')}",
        ),
        Erratum(
            "(12), (13), (26), (28)",
            "∂A/∂x = ∂A/∂x (I ⊗ ẋ); right-hand sides “− J_fᵀ” without λ",
            "Ȧ = ∂A/∂x (I_n ⊗ ẋ); − J_fᵀ λ",
            "typesetting",
            "none (typographical)",
        ),
    ]


def errata_markdown(feeder: Feeder | None = None, cycle: CycleKinematics | None = None) -> str:
    """The published errata table (``ERRATA.md``) as Markdown text.

    Args:
        feeder: Device (default: the projectile feeder).
        cycle: Reference motion (default: its cycle at −4°, default timing).
    """
    feeder = feeder or load_feeder("projectile")
    cycle = cycle or feeding_cycle(feeder, REFERENCE_ELEVATION)
    lines = [
        "# Errata to Balla & Duong, “Analysis of feeding device with two degrees of freedom”",
        "",
        "Generated by `python -m feeder.errata` (module `feeder/errata.py`); do not edit by "
        "hand. Every number below is computed on the reference cycle: the "
        f"{feeder.params.name} feeder, elevation {math.degrees(cycle.elevation):g}°, stage "
        f"durations {tuple(float(x) for x in cycle.spec.durations)} s, "
        f"{cycle.t.size} samples, payload held from the end of stage 1. “Printed” is the "
        "paper's formula evaluated as printed (`feeder.errata.printed_equations`), "
        "“corrected” the hand-derived equations of `feeder.lagrange`, which agree with "
        "Pinocchio to round-off (tests/test_lagrange.py). Both use the same parameters "
        "(`feeder.parameters`); the printed scalars I1, I2, I3 are the links' z moments and "
        "I4 the forearm's y moment. Notation: q = [φ1, r2, φ3, φ4], a1 = a + b; "
        "ρx5 = a1 + e5 cos q4 + z5 sin q4, ρy5 = h5 − f; body 5 is the payload.",
        "",
        "| # | Eq. | Printed | Corrected | Why | Consequence on the reference cycle |",
        "|---|---|---|---|---|---|",
    ]
    for i, row in enumerate(errata_rows(feeder, cycle), start=1):
        cells = (row.equation, row.printed, row.corrected, row.why, row.consequence)
        lines.append(f"| {i} | " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    return "\n".join(lines) + "\n"


def write_errata(path: str | Path) -> Path:
    """Write :func:`errata_markdown` to ``path`` (UTF-8) and return the path."""
    path = Path(path)
    path.write_text(errata_markdown(), encoding="utf-8")
    return path


def main(argv: list[str] | None = None) -> int:
    """``python -m feeder.errata [path]``: write the errata table (default ``ERRATA.md``)."""
    argv = sys.argv[1:] if argv is None else argv
    print(write_errata(argv[0] if argv else "ERRATA.md"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
