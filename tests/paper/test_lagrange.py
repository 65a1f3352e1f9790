"""The hand-derived Lagrange equations (feeder.paper.lagrange) against Pinocchio and finite
differences.

Pinocchio is called directly (crba, nonLinearEffects, computeGeneralizedGravity,
constraintDynamics: :class:`tests.paper.cases.PinocchioReference`) on the two models of
:class:`feeder.dynamics.models.FeederDynamics` (with the payload merged into the forearm body,
and without it), so the two sides share only the parameter set; the actuator loads are compared
with the product's Pinocchio inverse dynamics, :func:`feeder.dynamics.inverse.actuator_loads`.
The convention linking Pinocchio's λ_c to the paper's λ is in :mod:`tests.paper.cases`.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder.chain.dynamics.derivatives import mass_matrix_derivative
from feeder.device.parameters import SINGULAR_TRANSMISSION_DEG
from feeder.exceptions import InputError, SingularPoseError
from feeder.motion.cycle import feeding_cycle
from feeder.paper import bodies, closure, lagrange
from feeder.paper.lagrange import LagrangeLoads

from . import cases, helpers
from .cases import relative_error

DYNAMICS_RTOL = 1e-10
"""M, C q̇, g vs Pinocchio: a few hundred flops on O(1) numbers, expected ~1e-14."""
SOLVE_RTOL = 1e-8
"""q̈, λ, actuator loads: solves of 6×6 / 2×2 systems (condition ≲ 1e4) on top of the above, and
Pinocchio's proximal solver run to 1e-14 — the brief's bound, measured ~1e-13."""
CYCLE_RTOL = 1e-12
"""Whole-cycle loads and λ, closed form vs the matrix form and vs Pinocchio, relative to the
cycle's peak: each side sums a few dozen products of terms no larger than the peak and solves a
2×2 or 3×3 system with |sin μ| ≥ 0.68, i.e. ~1e-15 of the peak (measured ≤ 1e-15); any missing
or wrong term would be ≥ 1e-3 of it."""
CLOSURE_RATE_ATOL = 1e-10
"""|J_f q̈ + J̇_f q̇| [m/s²] of the forward dynamics' q̈: the 6×6 KKT solve (condition ≲ 1e4)
with right-hand sides up to ~1e3 leaves ~1e4 · ε · 1e3 ≈ 1e-9 at worst (measured ~1e-12)."""
EOM_RTOL = 1e-12
"""Residual of M q̈ + C q̇ + g − τ + J_fᵀ λ relative to its largest term: Cramer's rule with
|sin μ| ≥ sin 5° amplifies round-off ≲ 12×, so ~1e-14 (a wrong load would leave O(1))."""
ENERGY_ROUND_OFF = 1e-12
"""Round-off of dE/dt relative to the peak power: energies of O(1e2) J differenced at 1 kHz."""
SHARP = 1e-4
"""The power-balance bound must stay below this fraction of the peak power, so that a missing
term (≥ 1e-2 of the peak) cannot hide under it."""
REFUSED_DEG = SINGULAR_TRANSMISSION_DEG - 1.0
"""Transmission angle [deg] 1° inside the refused band around the toggle (4°)."""
SOLVED_DEG = SINGULAR_TRANSMISSION_DEG + 1.0
"""Transmission angle [deg] 1° outside it (6°)."""
ELEVATIONS = (-4.0, 30.0, 70.0)
PINOCCHIO_SAMPLES = 20
"""States of the per-sample Pinocchio loops (each a Python call per state)."""
CYCLE_STEP = 4
"""Every 4th cycle sample in the per-sample Pinocchio comparisons along a cycle."""
FORWARD_STEP = 10
"""Every 10th cycle sample for the forward check: each costs a proximal solve."""


@pytest.fixture(scope="module", params=ELEVATIONS, ids=[f"{e:g}deg" for e in ELEVATIONS])
def device_cycle(request, device):
    """The cycles of both devices (conftest's ``cycle`` is the projectile feeder's only)."""
    return feeding_cycle(device, math.radians(request.param))


def matrix_inverse_dynamics(p, q, qd, qdd, gripped):
    """Eq. (46) from the matrices: h = M q̈ + C q̇ + g with C by the Kronecker formula (27), then
    [e2  e4  −J_fᵀ] [F, τ4, λ1, λ2]ᵀ = h solved per sample by LAPACK; shape (N, 4)."""
    h = (
        np.einsum("nij,nj->ni", lagrange.mass_matrix(p, q, gripped), qdd)
        + np.einsum("nij,nj->ni", lagrange.coriolis_matrix(p, q, qd, gripped), qd)
        + lagrange.gravity_vector(p, q, gripped)
    )
    system = np.zeros((q.shape[0], 4, 4))
    system[:, 1, 0] = system[:, 3, 1] = 1.0
    system[:, :, 2:] = -np.swapaxes(closure.closure_jacobian(p, q), 1, 2)
    return np.linalg.solve(system, h[..., None])[..., 0]


def equation_of_motion_terms(p, q, qd, qdd, gripped, loads: LagrangeLoads):
    """The terms of M q̈ + C q̇ + g − τ + J_fᵀ λ (= 0), stacked on a leading axis (5, ..., 4)."""
    return np.stack(
        [
            np.einsum("...ij,...j->...i", lagrange.mass_matrix(p, q, gripped), qdd),
            np.einsum("...ij,...j->...i", lagrange.coriolis_matrix(p, q, qd, gripped), qd),
            lagrange.gravity_vector(p, q, gripped),
            -loads.tau,
            np.einsum("...ji,...j->...i", closure.closure_jacobian(p, q), loads.lambdas),
        ]
    )


def test_closed_form_mass_matrix_is_eq17(device, states):
    p, q, gripped = device.params, states.q, states.gripped
    weights = np.column_stack([np.ones((q.shape[0], 4)), gripped])
    eq17 = bodies.mass_matrix_from_jacobians(
        bodies.body_masses(p) * weights,
        bodies.translational_jacobians(p, q),
        bodies.rotational_jacobians(p, q),
        helpers.central_inertias(p, q) * weights[..., None, None],
    )
    closed = lagrange.mass_matrix(p, q, gripped)
    assert np.all(relative_error(closed, eq17, (1, 2)) <= DYNAMICS_RTOL)


def test_mass_matrix_coriolis_gravity_match_pinocchio(device, reference, states):
    p, (q, qd, _, gripped, _) = device.params, states
    mass = lagrange.mass_matrix(p, q, gripped)
    c_qd = np.einsum("nij,nj->ni", lagrange.coriolis_matrix(p, q, qd, gripped), qd)
    gravity = lagrange.gravity_vector(p, q, gripped)
    for i in range(q.shape[0]):
        m_ref, c_ref, g_ref = reference.dynamics(q[i], qd[i], gripped[i])
        assert relative_error(mass[i], m_ref, (0, 1)) <= DYNAMICS_RTOL
        assert relative_error(c_qd[i], c_ref, (0,)) <= DYNAMICS_RTOL
        assert relative_error(gravity[i], g_ref, (0,)) <= DYNAMICS_RTOL


def test_mass_matrix_coriolis_gravity_along_cycles(device, reference, device_cycle):
    """The same agreement on every 4th sample of the cycles at −4°, 30°, 70°. Relative to the
    cycle's peak of each quantity (C q̇ vanishes at the stage boundaries, where q̇ = 0)."""
    p, k = device.params, device_cycle
    q, qd = k.q[::CYCLE_STEP], k.v[::CYCLE_STEP]
    gripped = k.gripped[::CYCLE_STEP]
    mass = lagrange.mass_matrix(p, q, gripped)
    c_qd = np.einsum("nij,nj->ni", lagrange.coriolis_matrix(p, q, qd, gripped), qd)
    gravity = lagrange.gravity_vector(p, q, gripped)
    refs = [reference.dynamics(q[i], qd[i], gripped[i]) for i in range(q.shape[0])]
    for mine, theirs in zip((mass, c_qd, gravity), zip(*refs, strict=True), strict=True):
        theirs = np.array(theirs)
        assert np.abs(mine - theirs).max() <= DYNAMICS_RTOL * np.abs(theirs).max()


def test_mass_matrix_gradient_layout_and_values(device, reference, states):
    """Eq. (4) layout: entry (i, 4 j + k) = ∂M_ij/∂q_k, against finite differences of M and
    against Pinocchio's exact ∂M/∂q (feeder.chain.dynamics.derivatives)."""
    p = device.params
    q, gripped = states.q[:PINOCCHIO_SAMPLES], states.gripped[:PINOCCHIO_SAMPLES]
    closed = lagrange.mass_matrix_gradient(p, q, gripped)
    cases.assert_derivative(
        closed.reshape(-1, 4, 4, 4), lambda x: lagrange.mass_matrix(p, x, gripped), q
    )
    index = device.index
    for i in range(q.shape[0]):
        model = reference.models[gripped[i]]
        exact = mass_matrix_derivative(model, model.createData(), device.to_pinocchio(q[i]))
        exact = exact.reshape(4, 4, 4)[np.ix_(index, index, index)].reshape(4, 16)
        assert relative_error(closed[i], exact, (0, 1)) <= DYNAMICS_RTOL


def test_gravity_is_gradient_of_potential(device, states):
    p, q, gripped = device.params, states.q, states.gripped
    cases.assert_derivative(
        lagrange.gravity_vector(p, q, gripped),
        lambda x: helpers.potential_energy(p, x, gripped),
        q,
    )


def test_forward_dynamics_match_pinocchio(device, reference, states):
    p, (q, qd, _, gripped, tau) = device.params, states
    qdd, lam = helpers.forward_dynamics(p, q, qd, tau, gripped)
    closure_rate = np.einsum(
        "nij,nj->ni", closure.closure_jacobian(p, q), qdd
    ) + closure.closure_bias(p, q, qd)
    assert np.max(np.abs(closure_rate)) <= CLOSURE_RATE_ATOL
    for i in range(q.shape[0]):
        qdd_ref, lam_ref = reference.forward(q[i], qd[i], tau[i], gripped[i])
        assert relative_error(qdd[i], qdd_ref, (0,)) <= SOLVE_RTOL
        assert relative_error(lam[i], lam_ref, (0,)) <= SOLVE_RTOL


def test_inverse_dynamics_match_pinocchio(device, reference, states):
    p, (q, qd, qdd, gripped, _) = device.params, states
    loads = lagrange.lagrange_loads(p, q, qd, qdd, gripped)
    assert isinstance(loads, LagrangeLoads)
    assert loads.tau.shape == q.shape and loads.lambdas.shape == (q.shape[0], 2)
    assert np.all(loads.tau[:, [0, 2]] == 0.0)
    np.testing.assert_array_equal(loads.piston_force, loads.tau[:, 1])
    np.testing.assert_array_equal(loads.forearm_torque, loads.tau[:, 3])
    expected = reference.inverse(q, qd, qdd, gripped)
    assert np.all(relative_error(loads.tau[:, [1, 3]], expected[:, :2], (1,)) <= SOLVE_RTOL)
    assert np.all(relative_error(loads.lambdas, expected[:, 2:], (1,)) <= SOLVE_RTOL)
    # And back: the forward dynamics under these loads reproduce the motion.
    qdd_back, lam_back = helpers.forward_dynamics(p, q, qd, loads.tau, gripped)
    assert np.all(relative_error(qdd_back, qdd, (1,)) <= SOLVE_RTOL)
    assert np.all(relative_error(lam_back, loads.lambdas, (1,)) <= SOLVE_RTOL)


def test_cycle_loads_match_matrix_form_and_pinocchio(device, reference, device_cycle):
    """The closed-form cycle loads equal, to round-off of the cycle's peaks, the same equations
    in matrix form (M, Kronecker C, g, J_f, LAPACK) and Pinocchio's inverse dynamics."""
    k = device_cycle
    motion = (k.q, k.v, k.a, k.gripped)
    loads = lagrange.lagrange_loads(device.params, *motion)
    closed = np.column_stack([loads.piston_force, loads.forearm_torque, loads.lambdas])
    assert closed.shape == (k.t.size, 4)
    for expected in (matrix_inverse_dynamics(device.params, *motion), reference.inverse(*motion)):
        assert np.all(relative_error(closed, expected, (0,)) <= CYCLE_RTOL)
    # Pinocchio's forward dynamics driven by the Lagrange loads reproduce the cycle's q̈.
    accelerations = np.array(
        [
            reference.forward(k.q[i], k.v[i], loads.tau[i], held)[0]
            for i, held in list(enumerate(k.gripped))[::FORWARD_STEP]
        ]
    )
    assert np.all(relative_error(accelerations, k.a[::FORWARD_STEP], (0,)) <= SOLVE_RTOL)


def test_power_balance_along_cycle(device, device_cycle):
    """d(T + Π)/dt = τ · q̇ in each stage (the pin force does no work: J_f q̇ = 0).

    np.gradient (2nd order) errs by h²/6 · |E‴| inside and h²/3 · |E‴| at the stage ends; |E‴|
    is bounded by the sampled third differences / h³ (margin 2). A missing term (≥ 1e-2 of the
    peak power) is far above that bound (≈ 1e-6 of it)."""
    p, k = device.params, device_cycle
    loads = lagrange.lagrange_loads(p, k.q, k.v, k.a, k.gripped)
    mass = lagrange.mass_matrix(p, k.q, k.gripped)
    energy = 0.5 * np.einsum("ni,nij,nj->n", k.v, mass, k.v)
    energy += helpers.potential_energy(p, k.q, k.gripped)
    power = loads.piston_force * k.v[:, 1] + loads.forearm_torque * k.v[:, 3]
    h = 1.0 / k.spec.rate
    scale = np.max(np.abs(power))
    for stage in (1, 2, 3):
        inside = k.stage == stage
        rate = np.gradient(energy[inside], k.t[inside], edge_order=2)
        third = np.abs(np.diff(energy[inside], 3)).max() / h**3
        bound = 2 * h**2 / 3 * third + ENERGY_ROUND_OFF * scale
        assert bound < SHARP * scale  # the check is sharp enough to see a missing term
        assert np.max(np.abs(rate - power[inside])) <= bound, stage


def test_pose_just_inside_the_toggle_band_is_refused(device):
    """1° inside the band (4° from the toggle): |sin(φ1 − φ3)| < sin 5°, λ is not determined
    well, and the pipeline's threshold applies."""
    q, qd, qdd = cases.pose_near_toggle(device.params, REFUSED_DEG)
    with pytest.raises(SingularPoseError, match="sin"):
        lagrange.lagrange_loads(device.params, q, qd, qdd)


def test_pose_just_outside_the_toggle_band_is_solved(device):
    """6° from the toggle: loads and λ solve eq. (46) — M q̈ + C q̇ + g = τ − J_fᵀ λ with
    τ1 = τ3 = 0 — to round-off of its largest term, gripped or not."""
    p = device.params
    q, qd, qdd = cases.pose_near_toggle(p, SOLVED_DEG)
    for gripped in (False, True):
        loads = lagrange.lagrange_loads(p, q, qd, qdd, gripped)
        assert np.all(np.isfinite(loads.tau)) and np.all(np.isfinite(loads.lambdas))
        assert loads.tau[0] == loads.tau[2] == 0.0
        terms = equation_of_motion_terms(p, q, qd, qdd, gripped, loads)
        residual = np.abs(terms.sum(axis=0)).max()
        assert residual <= EOM_RTOL * np.abs(terms).max()


def test_bad_inputs_raise(device):
    p = device.params
    q = np.array([2.4, 0.3, 0.5, 0.1])
    with pytest.raises(InputError, match="shape"):
        lagrange.mass_matrix(p, q[:3])
    with pytest.raises(InputError, match="nan"):
        lagrange.gravity_vector(p, np.array([2.4, np.nan, 0.5, 0.1]))
    with pytest.raises(InputError, match="gripped"):
        lagrange.mass_matrix(p, q, gripped=0.5)
    with pytest.raises(InputError, match="gripped"):
        lagrange.mass_matrix(p, np.stack([q, q]), gripped=np.array([1, 0, 1]))
    toggle = np.array([0.5, 0.3, 0.5, 0.0])  # piston axis along the arm lever
    with pytest.raises(SingularPoseError, match="sin"):
        lagrange.lagrange_loads(p, toggle, np.zeros(4), np.zeros(4))
