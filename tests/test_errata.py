"""The printed equations (feeder.errata) and the published errata table ERRATA.md.

The printed formulas are checked against each other where the paper says they follow from one
another, so that the transcription is faithful and every erratum claimed in the table is a
property of the printed text, not of our transcription: (43) is the gradient of (42), J_f is the
Jacobian of f in (44), (41) is (27) applied to the printed ∂M/∂q, (46) is (40) q̈ + (41) q̇ +
(43) ∓ (45) except where the table says it is not.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from feeder import errata, lagrange
from feeder.coriolis import kronecker_coriolis
from feeder.cycle import feeding_cycle
from feeder.device import load_feeder
from feeder.exceptions import InertiaError, InputError

ERRATA_MD = Path(__file__).resolve().parents[1] / "ERRATA.md"
FD_STEP = 1e-6
FD_RTOL = 1e-8
"""Central differences, h = 1e-6: round-off ~10 ε |f| / h ≈ 2e-9 |f|, truncation ≈ 2e-10 |f|."""
EXACT_RTOL = 1e-13
"""Identities between printed formulas that hold term by term (round-off only)."""


@pytest.fixture(scope="module")
def feeder():
    return load_feeder("projectile")


@pytest.fixture(scope="module")
def cycle(feeder):
    return feeding_cycle(feeder, errata.REFERENCE_ELEVATION)


@pytest.fixture(scope="module")
def printed(feeder, cycle):
    return errata.printed_equations(feeder.params, cycle.q, cycle.v, cycle.a)


def _central_difference(function, x):
    columns = []
    for k in range(4):
        dx = np.zeros(4)
        dx[k] = FD_STEP
        columns.append((function(x + dx) - function(x - dx)) / (2 * FD_STEP))
    return np.stack(columns, axis=-1)


def test_published_table_is_current(feeder, cycle):
    assert ERRATA_MD.read_text(encoding="utf-8") == errata.errata_markdown(feeder, cycle)


def test_main_writes_the_table(tmp_path):
    path = tmp_path / "ERRATA.md"
    assert errata.main([str(path)]) == 0
    assert path.read_text(encoding="utf-8") == ERRATA_MD.read_text(encoding="utf-8")


def test_every_row_is_complete(feeder, cycle):
    rows = errata.errata_rows(feeder, cycle)
    assert len(rows) >= 15
    for row in rows:
        assert all(
            text.strip()
            for text in (row.equation, row.printed, row.corrected, row.why, row.consequence)
        )


def test_printed_gravity_and_closure_jacobian_follow_their_sources(feeder, cycle, printed):
    p, q = feeder.params, cycle.q[::50]
    potential = _central_difference(
        lambda x: errata.printed_equations(p, x, cycle.v[::50], cycle.a[::50]).potential, q
    )
    scale = np.max(np.abs(printed.potential))
    np.testing.assert_allclose(printed.gravity[::50], potential, rtol=0, atol=FD_RTOL * scale)
    closure = _central_difference(
        lambda x: errata.printed_equations(p, x, cycle.v[::50], cycle.a[::50]).closure, q
    )
    np.testing.assert_allclose(printed.closure_jacobian[::50], closure, rtol=0, atol=FD_RTOL)


def test_printed_coriolis_is_eq27_of_printed_derivative(cycle, printed):
    kron = kronecker_coriolis(printed.mass_matrix_derivative, cycle.v)
    scale = np.max(np.abs(printed.coriolis))
    np.testing.assert_allclose(kron, printed.coriolis, rtol=0, atol=EXACT_RTOL * scale)


def test_printed_eq45_is_plus_jf_transpose_lambda(feeder, cycle, printed):
    lam = printed.lambdas
    expected = np.einsum("nji,nj->ni", printed.closure_jacobian, lam)
    scale = np.max(np.abs(expected))
    np.testing.assert_allclose(
        errata.printed_eq45(feeder.params, cycle.q, lam), expected, rtol=0, atol=EXACT_RTOL * scale
    )


def test_printed_eq46_against_its_components(feeder, cycle, printed):
    """(46) = (40) q̈ + (41) q̇ + 2·(43) − (45), except: row 1's λ1 sign, row 2's Coriolis
    term, row 4's missing gravity — the errata rows 13–15."""
    p, q, qd, qdd = feeder.params, cycle.q, cycle.v, cycle.a
    h, coefficients = errata.printed_eq46_terms(p, q, qd, qdd)
    assembled = (
        np.einsum("nij,nj->ni", printed.mass_matrix, qdd)
        + np.einsum("nij,nj->ni", printed.coriolis, qd)
        + 2.0 * printed.gravity
    )
    m2q2 = p.piston.mass * q[:, 1]
    assembled[:, 1] += -2 * m2q2 * qd[:, 0] * qd[:, 1] + m2q2 * qd[:, 0] ** 2
    assembled[:, 3] -= 2.0 * printed.gravity[:, 3]
    np.testing.assert_allclose(h, assembled, rtol=0, atol=EXACT_RTOL * np.max(np.abs(h)))
    minus_eq45 = -np.swapaxes(printed.closure_jacobian, 1, 2)  # −(45) = −J_fᵀ (printed J_f)
    minus_eq45[:, 0, 0] *= -1.0  # row 1 adds (45)'s λ1 term
    np.testing.assert_array_equal(coefficients, minus_eq45)


def test_printed_and_corrected_agree_where_the_errata_say(feeder, cycle, printed):
    """Stages 1–2 keep the arm horizontal (q3 = 0): there the printed forearm CG is right, and
    M11, M22 and the cylinder–piston rows never had errors."""
    p, q, held = feeder.params, cycle.q, cycle.payload
    level = cycle.stage < 3
    corrected = lagrange.body_positions(p, q)[:, 3]
    np.testing.assert_allclose(printed.r4[level], corrected[level], rtol=0, atol=1e-15)
    assert np.max(np.abs(printed.r4[~level] - corrected[~level])) > 1e-2  # [m]
    mass = lagrange.mass_matrix(p, q, held)
    np.testing.assert_allclose(printed.mass_matrix[:, :2, :2], mass[:, :2, :2], rtol=1e-15)
    # M44 is constant, whatever q4 (the forearm CG moves on a circle about the hinge).
    m44 = lagrange.mass_matrix(p, q, True)[:, 3, 3]
    np.testing.assert_allclose(m44, m44[0], rtol=1e-14)


def test_derivative_layout_matches_printed_positions(feeder, cycle, printed):
    """The one a_ij the paper got right, a_{1,2} = ∂M11/∂q2 = 2 m2 q2, sits where our layout
    (i, 4 j + k) puts it; a_{3,12} and a_{4,16} are ∂M33/∂q4 and ∂M44/∂q4 there too."""
    corrected = lagrange.mass_matrix_derivative(feeder.params, cycle.q, cycle.payload)
    np.testing.assert_array_equal(corrected[:, 0, 1], printed.mass_matrix_derivative[:, 0, 1])
    nonzero = {(0, 1), (2, 11), (3, 15)}
    assert {tuple(ix) for ix in np.argwhere(np.any(printed.mass_matrix_derivative, 0))} <= nonzero
    np.testing.assert_array_equal(corrected[:, 3, 15], 0.0)  # M44 is constant


def test_m44_from_eq39_with_printed_eq34(feeder, cycle, printed):
    p, c4, s4 = feeder.params, np.cos(cycle.q[:, 3]), np.sin(cycle.q[:, 3])
    moments = [link.moments for link in list(p.links().values())[:4]]
    m39 = lagrange.mass_matrix_from_jacobians(
        lagrange.body_masses(p)[:4],
        printed.j_t,
        printed.j_r,
        np.stack([np.diag(m) for m in moments]),
    )
    expected = p.forearm.mass * ((p.a1 - p.e * s4) ** 2 + p.e**2 * c4**2) + p.forearm.moments[1]
    np.testing.assert_allclose(m39[:, 3, 3], expected, rtol=1e-14)
    np.testing.assert_allclose(m39[:, 2, 2], printed.mass_matrix[:, 2, 2], rtol=1e-14)


def test_bad_inputs_raise(feeder):
    with pytest.raises(InputError, match="shape"):
        errata.printed_equations(feeder.params, np.zeros(3), np.zeros(4), np.zeros(4))
    with pytest.raises(InputError, match="nan"):
        errata.printed_equations(feeder.params, np.zeros(4), np.full(4, np.nan), np.zeros(4))


def test_table_i_printed_moments_are_not_physical(feeder):
    p = feeder.params
    for link, moments in errata.TABLE_I_PRINTED_MOMENTS.items():
        with pytest.raises(InertiaError, match=link):
            replace(getattr(p, link), moments=moments).check(link)


def test_printed_loads_are_finite_and_differ(feeder, cycle, printed):
    loads = lagrange.lagrange_cycle_loads(feeder, cycle)
    assert np.all(np.isfinite(printed.piston_force))
    assert np.all(np.isfinite(printed.forearm_torque))
    assert math.isclose(cycle.elevation, math.radians(-4.0))
    assert np.max(np.abs(printed.piston_force - loads.piston_force)) > 100.0  # [N]
