"""The errata table: every slip of the printed equations, its correction and its consequence.

:func:`errata_rows` measures each erratum on a reference motion (the cycle's samples, given by
the caller: :func:`feeder.study.paper_errata` uses the projectile feeder at −4°) against the
corrected equations of :mod:`feeder.paper.lagrange`; :func:`errata_markdown` renders the
published table ``ERRATA.md`` (``feeder errata`` writes it). The printed equations themselves are
in :mod:`feeder.paper.printed`.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from types import SimpleNamespace

import numpy as np

from ..device.parameters import FeederParameters
from . import bodies, lagrange
from .bodies import G
from .coriolis import kronecker_coriolis
from .errata_rows import (
    Erratum,
    data_rows,
    equation46_rows,
    inertia_rows,
    kinematics_rows,
    potential_rows,
)
from .printed import printed_eq45, printed_eq46_terms, printed_equations, solve_passive

TABLE_I_PRINTED_MOMENTS = {
    "piston": (4.160e-2, 1.054e-2, 1.058e-2),
    "arm": (0.238e-2, 5.036e-2, 0.278e-2),
}
"""Table I's printed moments [kg·m²] of the two links whose tensors are not physical, in our
link-frame axes (the piston's table x/y exchanged, as in :mod:`feeder.device.builtin`)."""


@dataclass(frozen=True)
class ReferenceMotion:
    """The motion the errata are measured on; N samples, paper order.

    Attributes:
        t: Times [s], (N,).
        q, qd, qdd: [φ1, r2, φ3, φ4] and derivatives, closed loop, (N, 4).
        gripped: 1 where the payload is held, else 0, (N,).
        caption: What the motion is, for the table's introduction (device, elevation, timing).
    """

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    gripped: np.ndarray
    caption: str


def _loads(p: FeederParameters, samples: ReferenceMotion, gripped) -> tuple[np.ndarray, ...]:
    loads = lagrange.inverse_dynamics(p, samples.q, samples.qd, samples.qdd, gripped)
    return loads.piston_force, loads.forearm_torque, loads.lambdas


def _evaluate(p: FeederParameters, samples: ReferenceMotion) -> SimpleNamespace:
    """Every quantity the rows quote: the printed and the corrected equations on ``samples``."""
    q, qd, qdd, held = samples.q, samples.qd, samples.qdd, samples.gripped
    printed = printed_equations(p, q, qd, qdd)
    force, torque, lam = _loads(p, samples, held)
    mass = lagrange.mass_matrix(p, q, held)
    d_mass = lagrange.mass_matrix_gradient(p, q, held)
    coriolis = lagrange.coriolis_matrix(p, q, qd, held)
    gravity = lagrange.gravity_vector(p, q, held)
    forearm = bodies.body_positions(p, q)[:, 3]
    j_t4 = bodies.translational_jacobians(p, q)[:, 3]
    j_r4 = bodies.rotational_jacobians(p, q)[:, 3]

    table_i = replace(
        p, **{k: replace(getattr(p, k), moments=v) for k, v in TABLE_I_PRINTED_MOMENTS.items()}
    )
    force_t, torque_t, _ = _loads(table_i, samples, held)
    gap = np.linalg.norm(printed.r4 - forearm, axis=-1)
    k_gap = int(np.argmax(gap))
    omega = np.einsum("nij,nj->ni", j_r4 - printed.j_r[:, 3], qd)
    moments = np.array([link.moments for link in list(p.links().values())[:4]])
    m39 = bodies.mass_matrix_from_jacobians(
        bodies.body_masses(p)[:4],
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
    _, tau46 = solve_passive(h46, coefficients, q)
    sin_sum, sin_difference = np.sin(q[:, 0] + q[:, 2]), np.sin(q[:, 0] - q[:, 2])
    k_sum = int(np.argmin(np.abs(sin_sum)))
    h_row2 = h46.copy()
    m2q2 = p.piston.mass * q[:, 1]
    h_row2[:, 1] += 2 * m2q2 * qd[:, 0] * qd[:, 1] - m2q2 * qd[:, 0] ** 2
    _, tau_row2 = solve_passive(h_row2, coefficients, q)
    force_empty, torque_empty, _ = _loads(p, samples, False)
    held_stage = held.astype(bool)

    return SimpleNamespace(
        t=samples.t,
        arm_term=arm_term,
        c_q=c_q,
        c_q_printed=c_q_printed,
        d_mass=d_mass,
        dg=dg,
        eq45=eq45,
        force=force,
        force_empty=force_empty,
        force_t=force_t,
        gap=gap,
        gravity=gravity,
        held_stage=held_stage,
        j_t4=j_t4,
        jt_printed=jt_printed,
        k_gap=k_gap,
        k_sum=k_sum,
        kron_printed=kron_printed,
        lam=lam,
        m39=m39,
        mass=mass,
        omega=omega,
        p=p,
        printed=printed,
        q=q,
        sin_difference=sin_difference,
        sin_sum=sin_sum,
        tau46=tau46,
        tau_row2=tau_row2,
        torque=torque,
        torque_empty=torque_empty,
        torque_t=torque_t,
    )


def errata_rows(p: FeederParameters, samples: ReferenceMotion) -> list[Erratum]:
    """Every erratum with its consequence measured on ``samples`` (see the module docstring)."""
    e = _evaluate(p, samples)
    return [
        *data_rows(e),
        *kinematics_rows(e),
        *inertia_rows(e),
        *potential_rows(e),
        *equation46_rows(e),
    ]


def errata_markdown(p: FeederParameters, samples: ReferenceMotion) -> str:
    """The published errata table (``ERRATA.md``) as Markdown text, measured on ``samples``."""
    lines = [
        "# Errata to Balla & Duong, “Analysis of feeding device with two degrees of freedom”",
        "",
        "Generated by `feeder errata` (module `feeder/paper/errata.py`); do not edit by "
        f"hand. Every number below is computed on the reference cycle: {samples.caption}, "
        f"{samples.t.size} samples, payload held from the end of stage 1. “Printed” is the "
        "paper's formula evaluated as printed (`feeder.paper.printed.printed_equations`), "
        "“corrected” the hand-derived equations of `feeder.paper.lagrange`, which agree with "
        "Pinocchio to round-off (tests/paper/test_lagrange.py). Both use the same parameters "
        "(`feeder.device.parameters`); the printed scalars I1, I2, I3 are the links' z moments "
        "and I4 the forearm's y moment. Notation: q = [φ1, r2, φ3, φ4], a1 = a + b; "
        "ρx5 = a1 + e5 cos q4 + z5 sin q4, ρy5 = h5 − f; body 5 is the payload.",
        "",
        "| # | Eq. | Printed | Corrected | Why | Consequence on the reference cycle |",
        "|---|---|---|---|---|---|",
    ]
    for i, row in enumerate(errata_rows(p, samples), start=1):
        cells = (row.equation, row.printed, row.corrected, row.why, row.consequence)
        lines.append(f"| {i} | " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    return "\n".join(lines) + "\n"
