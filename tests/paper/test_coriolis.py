"""Eq. (27), the Kronecker-product Coriolis matrix (feeder.paper.coriolis), on robots from
example-robot-data, with ∂M/∂q of any Pinocchio model (feeder.chain.dynamics.derivatives).

Checks, per robot and random state: ∂M/∂q (exact, from Pinocchio's Christoffel C) against
finite differences of crba; C q̇ against Pinocchio's Coriolis–centrifugal term
nonLinearEffects − computeGeneralizedGravity; the Christoffel matrix against
computeCoriolisMatrix; and the relations between Ṁ and C that the paper's convention implies.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from feeder.chain.dynamics.derivatives import mass_matrix_derivative
from feeder.exceptions import InputError
from feeder.paper.coriolis import christoffel_coriolis, kronecker_coriolis

from ..conftest import robots_dir

ROBOTS = {
    "ur5": "ur_description/urdf/ur5_robot.urdf",
    "panda": "panda_description/urdf/panda.urdf",
    "double_pendulum": "double_pendulum_description/urdf/double_pendulum.urdf",
}
"""example-robot-data models with nq = nv (revolute and prismatic joints only)."""

STATES_PER_ROBOT = 10
RTOL = 1e-10
"""C q̇, Christoffel C vs Pinocchio: a few hundred flops on O(1) numbers (measured ≲ 1e-14)."""
FD_STEP = 1e-6
FD_RTOL = 1e-7
"""∂M/∂q by central differences of crba with h = 1e-6 rad: round-off ~10 ε |M| / h ≈ 2e-9 |M|,
truncation h² |M‴| / 6 ≈ 1e-12 |M|; measured ≲ 3e-10 relative to max |∂M/∂q|."""
IDENTITY_RTOL = 1e-12
"""q̇ᵀ (Ṁ − 2 C) q̇ = 0 and C = Ṁ − ½ Nᵀ: exact identities evaluated in double precision."""
EMPTY_RANGE = 1e-9
"""A joint range narrower than this [rad] is a URDF's unset [0, 0] limit, not a real one."""
SCALE_FLOOR = 1e-300
"""Smallest error scale: at q̇ = 0 the tolerance is then ~0 (both sides are exactly 0)."""
DIFFERENT = 1e-3
"""A relative difference this large is a real difference, not round-off."""


@pytest.fixture(scope="module", params=sorted(ROBOTS))
def robot(request):
    model = pin.buildModelFromUrdf(str(robots_dir() / ROBOTS[request.param]))
    rng = np.random.default_rng(7)
    low = np.where(np.isfinite(model.lowerPositionLimit), model.lowerPositionLimit, -np.pi)
    high = np.where(np.isfinite(model.upperPositionLimit), model.upperPositionLimit, np.pi)
    # The double pendulum's limits are [0, 0]: sample a full turn wherever a range is empty.
    empty = high - low < EMPTY_RANGE
    low, high = np.where(empty, -np.pi, low), np.where(empty, np.pi, high)
    q = rng.uniform(low, high, (STATES_PER_ROBOT, model.nq))
    v = rng.normal(0.0, 1.0, (STATES_PER_ROBOT, model.nv))
    return request.param, model, model.createData(), q, v


def _identity_terms(d_mass: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Ṁ and N = ∂M/∂q (q̇ ⊗ I) written with Kronecker products, as in eqs. (12), (23)."""
    n = v.size
    m_dot = d_mass @ np.kron(np.eye(n), v[:, None])
    n_matrix = d_mass @ np.kron(v[:, None], np.eye(n))
    return m_dot, n_matrix


def test_mass_matrix_derivative_matches_finite_differences(robot):
    _, model, data, qs, _ = robot
    n = model.nv
    for q in qs:
        exact = mass_matrix_derivative(model, data, q).reshape(n, n, n)
        for k in range(n):
            step = np.zeros(n)
            step[k] = FD_STEP
            fd = pin.crba(model, data, q + step) - pin.crba(model, data, q - step)
            fd /= 2 * FD_STEP
            scale = np.max(np.abs(pin.crba(model, data, q)))
            np.testing.assert_allclose(exact[:, :, k], fd, rtol=0, atol=FD_RTOL * scale)


def test_kronecker_coriolis_times_velocity_is_pinocchio_term(robot):
    _, model, data, qs, vs = robot
    for q, v in zip(qs, vs, strict=True):
        c = kronecker_coriolis(mass_matrix_derivative(model, data, q), v)
        expected = pin.nonLinearEffects(model, data, q, v) - pin.computeGeneralizedGravity(
            model, data, q
        )
        np.testing.assert_allclose(c @ v, expected, rtol=0, atol=RTOL * np.max(np.abs(expected)))


def test_christoffel_matrix_is_pinocchio_coriolis_matrix(robot):
    _, model, data, qs, vs = robot
    for q, v in zip(qs, vs, strict=True):
        d_mass = mass_matrix_derivative(model, data, q)
        expected = pin.computeCoriolisMatrix(model, data, q, v)
        np.testing.assert_allclose(
            christoffel_coriolis(d_mass, v), expected, rtol=0, atol=RTOL * np.max(np.abs(expected))
        )


def test_paper_convention_relations(robot):
    """C_paper = Ṁ − ½ Nᵀ ≠ C_chr; Ṁ − 2 C_paper is not skew but q̇ᵀ (Ṁ − 2 C_paper) q̇ = 0;
    Ṁ − 2 C_chr is skew-symmetric."""
    _, model, data, qs, vs = robot
    for q, v in zip(qs, vs, strict=True):
        d_mass = mass_matrix_derivative(model, data, q)
        c_paper = kronecker_coriolis(d_mass, v)
        c_chr = christoffel_coriolis(d_mass, v)
        m_dot, n_matrix = _identity_terms(d_mass, v)
        scale = np.max(np.abs(m_dot))
        np.testing.assert_allclose(
            c_paper, m_dot - 0.5 * n_matrix.T, rtol=0, atol=IDENTITY_RTOL * scale
        )
        np.testing.assert_allclose(m_dot, c_chr + c_chr.T, rtol=0, atol=IDENTITY_RTOL * scale)
        assert np.max(np.abs(c_paper - c_chr)) > DIFFERENT * scale
        s_paper, s_chr = m_dot - 2 * c_paper, m_dot - 2 * c_chr
        assert np.max(np.abs(s_paper + s_paper.T)) > DIFFERENT * scale
        np.testing.assert_allclose(s_chr + s_chr.T, 0.0, rtol=0, atol=IDENTITY_RTOL * scale)
        assert abs(v @ s_paper @ v) <= IDENTITY_RTOL * scale * (v @ v)


@settings(max_examples=40, deadline=None)
@given(
    q=st.lists(st.floats(-np.pi, np.pi), min_size=2, max_size=2),
    v=st.lists(st.floats(-5.0, 5.0), min_size=2, max_size=2),
)
def test_double_pendulum_power_identity_property(q, v):
    """For any state: C q̇ is Pinocchio's term and q̇ᵀ (Ṁ − 2 C) q̇ = 0 (power balance).

    Gravity is switched off so that nonLinearEffects is the Coriolis–centrifugal term itself:
    nle − g would carry Pinocchio's round-off ε |g|, larger than C q̇ near q2 = 0, where M of
    this pendulum is nearly constant. Errors are measured against |M| |q̇|², the size of the
    terms that make up C q̇ (∂M/∂q itself can cancel to ~1e-11 while its round-off is ε |M|)."""
    model = pin.buildModelFromUrdf(str(robots_dir() / ROBOTS["double_pendulum"]))
    model.gravity = pin.Motion.Zero()
    data = model.createData()
    q, v = np.array(q), np.array(v)
    d_mass = mass_matrix_derivative(model, data, q)
    c = kronecker_coriolis(d_mass, v)
    expected = pin.nonLinearEffects(model, data, q, v)
    scale = max(np.max(np.abs(pin.crba(model, data, q))) * (v @ v), SCALE_FLOOR)
    np.testing.assert_allclose(c @ v, expected, rtol=0, atol=RTOL * scale)
    m_dot, _ = _identity_terms(d_mass, v)
    assert abs(v @ (m_dot - 2 * c) @ v) <= IDENTITY_RTOL * scale * max(1.0, np.abs(v).max())


def test_bad_inputs_raise():
    """∂M/∂q checks its model and q (kronecker_coriolis, numpy only, checks nothing)."""
    continuous = pin.buildModelFromUrdf(
        str(robots_dir() / "double_pendulum_description/urdf/double_pendulum_continuous.urdf")
    )
    with pytest.raises(InputError, match="nq = 4"):
        mass_matrix_derivative(continuous, continuous.createData(), np.zeros(4))
    model = pin.buildModelFromUrdf(str(robots_dir() / ROBOTS["double_pendulum"]))
    with pytest.raises(InputError, match="shape"):
        mass_matrix_derivative(model, model.createData(), np.zeros(3))
    with pytest.raises(InputError, match="finite"):
        mass_matrix_derivative(model, model.createData(), np.array([0.0, np.inf]))
