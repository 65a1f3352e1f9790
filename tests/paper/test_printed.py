"""The paper's equations as printed (feeder.paper.printed), checked against each other.

The printed formulas are checked against each other where the paper says they follow from one
another, so that the transcription is faithful and every erratum claimed in the table is a
property of the printed text, not of our transcription: (43) is the gradient of (42), J_f is the
Jacobian of f in (44), (41) is (27) applied to the printed ∂M/∂q, (46) is (40) q̈ + (41) q̇ +
(43) ∓ (45) except where the table says it is not.
"""

from __future__ import annotations

import numpy as np
import pytest

from feeder.device.parameters import SINGULAR_TRANSMISSION_DEG
from feeder.exceptions import InputError, SingularPoseError
from feeder.motion.cycle import feeding_cycle
from feeder.paper import bodies, lagrange, printed
from feeder.paper.coriolis import kronecker_coriolis
from feeder.study.errata import REFERENCE_ELEVATION

from .cases import pose_near_toggle

FD_STEP = 1e-6
FD_RTOL = 1e-8
"""Central differences, h = 1e-6: round-off ~10 ε |f| / h ≈ 2e-9 |f|, truncation ≈ 2e-10 |f|."""
EXACT_RTOL = 1e-13
"""Identities between printed formulas that hold term by term (round-off only)."""
SAME_FORMULA_RTOL = 1e-15
"""The printed and corrected M11, M22: the same terms summed in another order, a few ulps
apart."""
CONSTANT_RTOL = 1e-14
"""Entries that are constant or equal by algebra but computed from sines and cosines of
different angles: sin² + cos² = 1 to a few ε on terms of O(1)."""
POSITION_ATOL = 1e-15
"""The printed and corrected forearm CG [m] at q3 = 0: the same sums of lengths < 1 m."""
MISPLACED = 1e-2
"""[m] A forearm CG gap this large (1 cm) is the erratum, not round-off (~1e-16 m)."""
DIFFERENT = 1e-3
"""A relative difference this large is a real difference, not round-off."""
FD_STRIDE = 50
"""Every 50th sample of the cycle for the finite differences (each evaluates (30)–(46))."""
REFUSED_DEG = SINGULAR_TRANSMISSION_DEG - 1.0
"""Transmission angle [deg] 1° inside the refused band around the toggle (4°)."""
SOLVED_DEG = SINGULAR_TRANSMISSION_DEG + 1.0
"""Transmission angle [deg] 1° outside it (6°)."""


@pytest.fixture(scope="module")
def reference_cycle(feeder):
    """The errata's reference cycle: the projectile feeder at −4° (the longest arm travel)."""
    return feeding_cycle(feeder, REFERENCE_ELEVATION)


@pytest.fixture(scope="module")
def evaluated(feeder, reference_cycle):
    k = reference_cycle
    return printed.printed_equations(feeder.params, k.q, k.v, k.a)


def _central_difference(function, x):
    columns = []
    for k in range(4):
        dx = np.zeros(4)
        dx[k] = FD_STEP
        columns.append((function(x + dx) - function(x - dx)) / (2 * FD_STEP))
    return np.stack(columns, axis=-1)


def test_printed_gravity_and_closure_jacobian_follow_their_sources(
    feeder, reference_cycle, evaluated
):
    p, k = feeder.params, reference_cycle
    q, qd, qdd = k.q[::FD_STRIDE], k.v[::FD_STRIDE], k.a[::FD_STRIDE]
    potential = _central_difference(
        lambda x: printed.printed_equations(p, x, qd, qdd).potential, q
    )
    scale = np.max(np.abs(evaluated.potential))
    np.testing.assert_allclose(
        evaluated.gravity[::FD_STRIDE], potential, rtol=0, atol=FD_RTOL * scale
    )
    closure = _central_difference(lambda x: printed.printed_equations(p, x, qd, qdd).closure, q)
    np.testing.assert_allclose(
        evaluated.closure_jacobian[::FD_STRIDE], closure, rtol=0, atol=FD_RTOL
    )


def test_printed_coriolis_is_eq27_of_printed_derivative(reference_cycle, evaluated):
    kron = kronecker_coriolis(evaluated.mass_matrix_derivative, reference_cycle.v)
    scale = np.max(np.abs(evaluated.coriolis))
    np.testing.assert_allclose(kron, evaluated.coriolis, rtol=0, atol=EXACT_RTOL * scale)


def test_printed_eq45_is_plus_jf_transpose_lambda(feeder, reference_cycle, evaluated):
    lam = evaluated.lambdas
    expected = np.einsum("nji,nj->ni", evaluated.closure_jacobian, lam)
    scale = np.max(np.abs(expected))
    np.testing.assert_allclose(
        printed.printed_eq45(feeder.params, reference_cycle.q, lam),
        expected,
        rtol=0,
        atol=EXACT_RTOL * scale,
    )


def test_printed_eq46_against_its_components(feeder, reference_cycle, evaluated):
    """(46) = (40) q̈ + (41) q̇ + 2·(43) − (45), except: row 1's λ1 sign, row 2's Coriolis
    term, row 4's missing gravity — the errata rows 13–15."""
    p, k = feeder.params, reference_cycle
    q, qd, qdd = k.q, k.v, k.a
    h, coefficients = printed.printed_eq46_terms(p, q, qd, qdd)
    assembled = (
        np.einsum("nij,nj->ni", evaluated.mass_matrix, qdd)
        + np.einsum("nij,nj->ni", evaluated.coriolis, qd)
        + 2.0 * evaluated.gravity
    )
    m2q2 = p.piston.mass * q[:, 1]
    assembled[:, 1] += -2 * m2q2 * qd[:, 0] * qd[:, 1] + m2q2 * qd[:, 0] ** 2
    assembled[:, 3] -= 2.0 * evaluated.gravity[:, 3]
    np.testing.assert_allclose(h, assembled, rtol=0, atol=EXACT_RTOL * np.max(np.abs(h)))
    minus_eq45 = -np.swapaxes(evaluated.closure_jacobian, 1, 2)  # −(45) = −J_fᵀ (printed J_f)
    minus_eq45[:, 0, 0] *= -1.0  # row 1 adds (45)'s λ1 term
    np.testing.assert_array_equal(coefficients, minus_eq45)


def test_printed_and_corrected_agree_where_the_errata_say(feeder, reference_cycle, evaluated):
    """Stages 1–2 keep the arm horizontal (q3 = 0): there the printed forearm CG is right, and
    M11, M22 and the cylinder–piston rows never had errors."""
    p, q, held = feeder.params, reference_cycle.q, reference_cycle.gripped
    level = reference_cycle.stage < 3
    corrected = bodies.body_positions(p, q)[:, 3]
    np.testing.assert_allclose(evaluated.r4[level], corrected[level], rtol=0, atol=POSITION_ATOL)
    assert np.max(np.abs(evaluated.r4[~level] - corrected[~level])) > MISPLACED
    mass = lagrange.mass_matrix(p, q, held)
    np.testing.assert_allclose(
        evaluated.mass_matrix[:, :2, :2], mass[:, :2, :2], rtol=SAME_FORMULA_RTOL
    )
    # M44 is constant, whatever q4 (the forearm CG moves on a circle about the hinge).
    m44 = lagrange.mass_matrix(p, q, True)[:, 3, 3]
    np.testing.assert_allclose(m44, m44[0], rtol=CONSTANT_RTOL)


def test_derivative_layout_matches_printed_positions(feeder, reference_cycle, evaluated):
    """The one a_ij the paper got right, a_{1,2} = ∂M11/∂q2 = 2 m2 q2, sits where our layout
    (i, 4 j + k) puts it; a_{3,12} and a_{4,16} are ∂M33/∂q4 and ∂M44/∂q4 there too."""
    corrected = lagrange.mass_matrix_gradient(
        feeder.params, reference_cycle.q, reference_cycle.gripped
    )
    np.testing.assert_array_equal(corrected[:, 0, 1], evaluated.mass_matrix_derivative[:, 0, 1])
    nonzero = {(0, 1), (2, 11), (3, 15)}
    assert {tuple(ix) for ix in np.argwhere(np.any(evaluated.mass_matrix_derivative, 0))} <= (
        nonzero
    )
    np.testing.assert_array_equal(corrected[:, 3, 15], 0.0)  # M44 is constant


def test_m44_from_eq39_with_printed_eq34(feeder, reference_cycle, evaluated):
    p, q = feeder.params, reference_cycle.q
    c4, s4 = np.cos(q[:, 3]), np.sin(q[:, 3])
    moments = [link.moments for link in list(p.links().values())[:4]]
    m39 = bodies.mass_matrix_from_jacobians(
        bodies.body_masses(p)[:4],
        evaluated.j_t,
        evaluated.j_r,
        np.stack([np.diag(m) for m in moments]),
    )
    expected = p.forearm.mass * ((p.a1 - p.e * s4) ** 2 + p.e**2 * c4**2) + p.forearm.moments[1]
    np.testing.assert_allclose(m39[:, 3, 3], expected, rtol=CONSTANT_RTOL)
    np.testing.assert_allclose(m39[:, 2, 2], evaluated.mass_matrix[:, 2, 2], rtol=CONSTANT_RTOL)


def test_printed_loads_are_finite_and_differ(feeder, reference_cycle, evaluated):
    k = reference_cycle
    loads = lagrange.lagrange_loads(feeder.params, k.q, k.v, k.a, k.gripped)
    assert np.all(np.isfinite(evaluated.piston_force))
    assert np.all(np.isfinite(evaluated.forearm_torque))
    peak = np.max(np.abs(loads.piston_force))
    assert np.max(np.abs(evaluated.piston_force - loads.piston_force)) > DIFFERENT * peak


def test_bad_inputs_raise(feeder):
    with pytest.raises(InputError, match="shape"):
        printed.printed_equations(feeder.params, np.zeros(3), np.zeros(4), np.zeros(4))
    with pytest.raises(InputError, match="nan"):
        printed.printed_equations(feeder.params, np.zeros(4), np.full(4, np.nan), np.zeros(4))


def test_printed_equations_refuse_the_toggle(feeder):
    """The printed (46) has the same passive rows' determinant ∝ sin(φ1 − φ3): refused at the
    toggle and 4° from it (the package's 5° threshold)."""
    p = feeder.params
    toggle = np.array([0.5, 0.3, 0.5, 0.0])  # piston axis along the arm lever
    with pytest.raises(SingularPoseError, match="sin"):
        printed.printed_equations(p, toggle, np.zeros(4), np.zeros(4))
    with pytest.raises(SingularPoseError, match="sin"):
        printed.printed_equations(p, *pose_near_toggle(p, REFUSED_DEG))


def test_printed_equations_solve_6_degrees_from_the_toggle(feeder):
    """6° from the toggle the passive rows give λ, and τ1 = τ3 = 0: h + Λ λ = τ holds."""
    p = feeder.params
    q, qd, qdd = pose_near_toggle(p, SOLVED_DEG)
    h, coefficients = printed.printed_eq46_terms(p, q, qd, qdd)
    lam, tau = printed.solve_passive(h, coefficients, q)
    assert np.all(np.isfinite(lam)) and np.all(np.isfinite(tau))
    assert np.all(tau[:, [0, 2]] == 0.0)
    terms = np.stack([h, np.einsum("nij,nj->ni", coefficients, lam), -tau])
    np.testing.assert_allclose(
        terms.sum(axis=0), 0.0, rtol=0, atol=EXACT_RTOL * np.abs(terms).max()
    )
    evaluated = printed.printed_equations(p, q, qd, qdd)
    np.testing.assert_array_equal(evaluated.lambdas, lam)
