"""The rows of the errata table, one function per group of equations.

Each function takes the quantities that :func:`feeder.paper.errata.errata_rows` evaluated on the
reference motion (printed and corrected equations side by side) and writes its rows' text with
the measured consequences.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np

from . import lagrange
from .closure import closure_residual


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


def data_rows(e: SimpleNamespace) -> list[Erratum]:
    """Row 1: Table I's two non-physical moments."""
    force, force_t, torque, torque_t = e.force, e.force_t, e.torque, e.torque_t
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
    ]


def kinematics_rows(e: SimpleNamespace) -> list[Erratum]:
    """Rows 2–5: positions, the arm angle's sign, the Jacobians ((30), (42)/(44), (34), (38))."""
    gap, j_t4, k_gap, omega, p, printed, q = e.gap, e.j_t4, e.k_gap, e.omega, e.p, e.printed, e.q
    return [
        Erratum(
            "(30) x4, y4",
            "x4 = L1 + (a1 + e cos q4) cos q3; y4 = L2 − f − d + (a1 + e cos q4) sin q3",
            "x4 = L1 + (a1 + e cos q4) cos q3 + (f + d) sin q3; "
            "y4 = L2 + (a1 + e cos q4) sin q3 − (f + d) cos q3",
            "the offset f + d lies along the arm's y axis, which turns with the arm; the "
            "printed form holds only at q3 = 0",
            f"forearm CG misplaced by up to {_q(1e3 * gap[k_gap], 'mm')} "
            f"(at q3 = {np.degrees(q[k_gap, 2]):.1f}°)",
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
            f"{_q(1e3 * _peak(closure_residual(p, q)), 'mm', 1.0)})",
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
    ]


def inertia_rows(e: SimpleNamespace) -> list[Erratum]:
    """Rows 6–10: the inertia matrix, its derivative and C ((39)–(41), (4))."""
    c_q, c_q_printed, d_mass, kron_printed, m39, mass, printed = (
        e.c_q,
        e.c_q_printed,
        e.d_mass,
        e.kron_printed,
        e.m39,
        e.mass,
        e.printed,
    )
    return [
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
            "Christoffel matrix, see feeder.paper.coriolis)",
            "(41) is (27) applied to the printed a_ij (largest entry difference: "
            f"{_q(_peak(kron_printed - printed.coriolis), '', _peak(printed.coriolis))}), so it "
            "inherits the errors of (40) and (4)",
            f"C q̇ off by up to {_q(_peak(c_q_printed[:, 2] - c_q[:, 2]), 'N·m')} (row 3) and "
            f"{_q(_peak(c_q_printed[:, 3] - c_q[:, 3]), 'N·m')} (row 4)",
        ),
    ]


def potential_rows(e: SimpleNamespace) -> list[Erratum]:
    """Rows 11–12: the potential energy and gravity vector, the multipliers' sign ((42)–(45))."""
    arm_term, dg, eq45, jt_printed = e.arm_term, e.dg, e.eq45, e.jt_printed
    return [
        Erratum(
            "(42)–(43) Π, g",
            "Π = ½ m1 g l1 sin q1 + ½ m2 g q2 sin q1 + ½ m3 g (L2 − l3 sin q3) + ½ m4 g y4; "
            "g = ½ [...]",
            "Π = g Σ m_i y_i over the five bodies (no ½), y_i from the corrected (30); "
            "g as in feeder.paper.lagrange",
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
    ]


def equation46_rows(e: SimpleNamespace) -> list[Erratum]:
    """Rows 13–18: eq. (46) row by row, the payload, the overall loads, typography."""
    (
        force,
        force_empty,
        gravity,
        held_stage,
        k_sum,
        lam,
        p,
        printed,
        q,
        sin_difference,
        sin_sum,
        tau46,
        tau_row2,
        torque,
        torque_empty,
    ) = (
        e.force,
        e.force_empty,
        e.gravity,
        e.held_stage,
        e.k_sum,
        e.lam,
        e.p,
        e.printed,
        e.q,
        e.sin_difference,
        e.sin_sum,
        e.tau46,
        e.tau_row2,
        e.torque,
        e.torque_empty,
    )
    return [
        Erratum(
            "(46) row 1",
            "… − (q2 + d2) λ1 sin q1 − (q2 + d2) λ2 cos q1 = τ1",
            "… + (q2 + d2) λ1 sin q1 − (q2 + d2) λ2 cos q1 = τ1 (rows 2–3 subtract (45); "
            "row 1 must too)",
            "row 1 subtracts (45)'s λ2 term but adds its λ1 term",
            "made consistent, rows 1 and 3 give λ through the determinant "
            "−(q2 + d2) d3 sin(q1 + q3), which passes through zero on the cycle "
            f"(|sin(q1 + q3)| down to {abs(sin_sum[k_sum]):.2g} at t = {e.t[k_sum]:.3f} s, "
            f"φ3 = {np.degrees(q[k_sum, 2]):.1f}°): the slip cancels (44)'s mirrored arm. As "
            "printed the "
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
            "M q̈ + C q̇ + g + J_fᵀ λ = τ with the corrected M, C, g, J_f (feeder.paper.lagrange)",
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
