"""The hand-derived Lagrange equations (feeder.lagrange) against Pinocchio and finite differences.

Pinocchio is called directly here (crba, nonLinearEffects, computeGeneralizedGravity,
constraintDynamics, getConstraintsJacobian) on the two models of
:class:`feeder.dynamics.FeederDynamics` (with the payload merged into the forearm body, and
without it), so the two sides share only the parameter set; the actuator loads are compared with
the product's Pinocchio inverse dynamics, :func:`feeder.dynamics.inverse_dynamics`.

Closure forces: Pinocchio solves M a + b − τ = Jᵀ λ_c with J = R_c1ᵀ ∂(p_piston_pin −
p_arm_pin)/∂q (the CONTACT_3D in the LOCAL frame c1 of ``piston_pin``, rotation R_c1 = R_z(φ1)),
the paper M q̈ + C q̇ + g − τ = −J_fᵀ λ with J_f = ∂f/∂q the x, y rows of the same difference in
world axes (its z row is identically zero). Equating, J_fᵀ (−λ) = J_fᵀ (R_c1 λ_c)_{x,y} and J_f
has full row rank, so λ = −(R_c1 λ_c)_{x,y} = −R_c1[:2, :] λ_c. Likewise λ = −(the world-frame
force of the arm on the piston) of :class:`feeder.dynamics.ActuatorLoads`.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from feeder import lagrange
from feeder.cycle import feeding_cycle
from feeder.device import load_feeder
from feeder.dynamics import FeederDynamics, inverse_dynamics
from feeder.exceptions import InputError, SingularPoseError
from feeder.kinematics import arm_travel, dependent_coordinates

N_STATES = 200
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
FD_STEP = 1e-6
FD_RTOL = 1e-8
"""Central differences with h = 1e-6 [rad or m], error relative to the function's size |f|:
round-off ~10 ε |f| / h ≈ 2e-9 |f|, truncation h² |f‴| / 6 ≈ 2e-10 |f| for lengths ≳ 0.1 m."""
PROXIMAL = pin.ProximalSettings(1e-14, 1e-8, 50)
"""mu > 0: the planar loop's out-of-plane closure row is redundant (mu = 0 gives NaN)."""
ELEVATIONS = (-4.0, 30.0, 70.0)


def relative_error(value: np.ndarray, reference: np.ndarray, axes: tuple[int, ...]) -> np.ndarray:
    """max |value − reference| / max |reference| over ``axes``."""
    return np.max(np.abs(value - reference), axis=axes) / np.max(np.abs(reference), axis=axes)


class PinocchioReference:
    """Per-sample Pinocchio dynamics of the feeder, with and without the payload, paper order."""

    def __init__(self, feeder):
        self.feeder = feeder
        self.dynamics_models = FeederDynamics(feeder)
        self.models = {k: case.model for k, case in enumerate(self.dynamics_models.cases)}
        self.datas = {k: m.createData() for k, m in self.models.items()}
        self.cmodels = feeder.chain.constraint_models
        self.cdatas = {}
        for k, model in self.models.items():
            self.cdatas[k] = pin.StdVec_RigidConstraintData()
            self.cdatas[k].append(self.cmodels[0].createData())
            pin.initConstraintDynamics(model, self.datas[k], self.cmodels, self.cdatas[k])

    def _paper(self, matrix):
        return matrix[np.ix_(self.feeder.index, self.feeder.index)]

    def dynamics(self, q, v, held):
        """M (4, 4), C q̇ (4,), g (4,) in paper order."""
        f, model, data = self.feeder, self.models[held], self.datas[held]
        qp, vp = f.to_pinocchio(q), f.to_pinocchio(v)
        mass = self._paper(pin.crba(model, data, qp))
        gravity = pin.computeGeneralizedGravity(model, data, qp).copy()
        coriolis = pin.nonLinearEffects(model, data, qp, vp) - gravity
        return mass, f.to_paper(coriolis), f.to_paper(gravity)

    def forward(self, q, v, tau, held):
        """constraintDynamics: q̈ (4,) and λ (2,) in the paper's convention."""
        f, model, data = self.feeder, self.models[held], self.datas[held]
        a = pin.constraintDynamics(
            model,
            data,
            f.to_pinocchio(q),
            f.to_pinocchio(v),
            f.to_pinocchio(tau),
            self.cmodels,
            self.cdatas[held],
            PROXIMAL,
        )
        assert PROXIMAL.iter < PROXIMAL.max_iter
        return f.to_paper(a), -self.cdatas[held][0].oMc1.rotation[:2, :] @ data.lambda_c

    def inverse(self, q, v, a, payload):
        """The product's Pinocchio inverse dynamics: columns F, τ4, λ1, λ2, shape (N, 4)."""
        loads = inverse_dynamics(self.dynamics_models, q, v, a, payload)
        return np.column_stack(
            [loads.piston_force, loads.forearm_torque, -loads.closure_force[:, :2]]
        )


def matrix_inverse_dynamics(p, q, qd, qdd, payload):
    """Eq. (46) from the matrices: h = M q̈ + C q̇ + g with C by the Kronecker formula (27), then
    [e2  e4  −J_fᵀ] [F, τ4, λ1, λ2]ᵀ = h solved per sample by LAPACK; shape (N, 4)."""
    h = (
        np.einsum("nij,nj->ni", lagrange.mass_matrix(p, q, payload), qdd)
        + np.einsum("nij,nj->ni", lagrange.coriolis_matrix(p, q, qd, payload), qd)
        + lagrange.gravity_vector(p, q, payload)
    )
    system = np.zeros((q.shape[0], 4, 4))
    system[:, 1, 0] = system[:, 3, 1] = 1.0
    system[:, :, 2:] = -np.swapaxes(lagrange.closure_jacobian(p, q), 1, 2)
    return np.linalg.solve(system, h[..., None])[..., 0]


@pytest.fixture(scope="module", params=["projectile", "charge"])
def feeder(request):
    """Both devices: the charge feeder is mirrored (c, z5 < 0) with another payload."""
    return load_feeder(request.param)


@pytest.fixture(scope="module")
def reference(feeder):
    return PinocchioReference(feeder)


@pytest.fixture(scope="module")
def states(feeder):
    """N_STATES random assembled states: q, q̇ (J q̇ = 0), q̈ (closure-consistent), payload."""
    p = feeder.params
    rng = np.random.default_rng(20240614)
    phi3 = rng.uniform(p.phi3_load, p.phi3_load + arm_travel(p.elevation_min), N_STATES)
    phi4 = rng.uniform(-p.phi4_limit, p.phi4_limit, N_STATES)
    rates = rng.normal(0.0, 1.0, (N_STATES, 2))
    accelerations = rng.normal(0.0, 3.0, (N_STATES, 2))
    loop = dependent_coordinates(p, phi3, rates[:, 0], accelerations[:, 0])
    q = np.column_stack([loop.phi1, loop.r2, phi3, phi4])
    qd = np.column_stack([loop.dphi1, loop.dr2, rates[:, 0], rates[:, 1]])
    qdd = np.column_stack([loop.ddphi1, loop.ddr2, accelerations[:, 0], accelerations[:, 1]])
    payload = rng.integers(0, 2, N_STATES)
    tau = np.column_stack(
        [
            np.zeros(N_STATES),
            rng.normal(0, 3000, N_STATES),
            np.zeros(N_STATES),
            rng.normal(0, 30, N_STATES),
        ]
    )
    return q, qd, qdd, payload, tau


@pytest.fixture(scope="module", params=ELEVATIONS, ids=[f"{e:g}deg" for e in ELEVATIONS])
def cycle(request, feeder):
    return feeding_cycle(feeder, math.radians(request.param))


def assert_derivative(derivative, function, x, step=FD_STEP):
    """``derivative`` (..., *shape, 4) equals the central difference of ``function`` at x
    ((..., 4) → (..., *shape)) within FD_RTOL of the function's size."""
    columns = []
    for k in range(x.shape[-1]):
        dx = np.zeros(x.shape[-1])
        dx[k] = step
        columns.append((function(x + dx) - function(x - dx)) / (2.0 * step))
    scale = max(1.0, float(np.max(np.abs(function(x)))))
    np.testing.assert_allclose(
        derivative, np.stack(columns, axis=-1), rtol=0, atol=FD_RTOL * scale
    )


def test_positions_match_pinocchio(feeder, reference, states):
    q = states[0][:20]
    positions = lagrange.body_positions(feeder.params, q)
    empty, model = reference.models[0], feeder.model
    data = model.createData()
    names = ("cylinder_joint", "piston_joint", "arm_joint", "forearm_joint")
    for i in range(q.shape[0]):
        pin.framesForwardKinematics(model, data, feeder.to_pinocchio(q[i]))
        expected = [
            data.oMi[model.getJointId(n)].act(empty.inertias[model.getJointId(n)].lever)
            for n in names
        ]
        expected.append(data.oMf[model.getFrameId("projectile")].translation)
        np.testing.assert_allclose(positions[i], np.array(expected), rtol=0, atol=1e-14)


def test_translational_jacobians_are_position_derivatives(feeder, states):
    q = states[0][:20]
    assert_derivative(
        lagrange.translational_jacobians(feeder.params, q),
        lambda x: lagrange.body_positions(feeder.params, x),
        q,
    )


def test_rotational_jacobians_match_pinocchio(feeder, states):
    q = states[0][:20]
    jac = lagrange.rotational_jacobians(feeder.params, q)
    rotations = lagrange.body_rotations(feeder.params, q)
    model, data = feeder.model, feeder.model.createData()
    joints = ("cylinder_joint", "piston_joint", "arm_joint", "forearm_joint", "forearm_joint")
    for i in range(q.shape[0]):
        qp = feeder.to_pinocchio(q[i])
        pin.computeJointJacobians(model, data, qp)
        for body, name in enumerate(joints):
            j = model.getJointId(name)
            expected = pin.getJointJacobian(model, data, j, pin.LOCAL_WORLD_ALIGNED)[3:]
            np.testing.assert_allclose(jac[i, body], feeder.to_paper(expected), atol=1e-15)
            np.testing.assert_allclose(rotations[i, body], data.oMi[j].rotation, atol=1e-15)


def test_closed_form_mass_matrix_is_eq17(feeder, states):
    p, (q, _, _, payload, _) = feeder.params, states
    weights = np.column_stack([np.ones((q.shape[0], 4)), payload])
    eq17 = lagrange.mass_matrix_from_jacobians(
        lagrange.body_masses(p) * weights,
        lagrange.translational_jacobians(p, q),
        lagrange.rotational_jacobians(p, q),
        lagrange.central_inertias(p, q) * weights[..., None, None],
    )
    closed = lagrange.mass_matrix(p, q, payload)
    assert np.all(relative_error(closed, eq17, (1, 2)) <= DYNAMICS_RTOL)


def test_mass_matrix_coriolis_gravity_match_pinocchio(feeder, reference, states):
    p, (q, qd, _, payload, _) = feeder.params, states
    mass = lagrange.mass_matrix(p, q, payload)
    c_qd = np.einsum("nij,nj->ni", lagrange.coriolis_matrix(p, q, qd, payload), qd)
    gravity = lagrange.gravity_vector(p, q, payload)
    for i in range(q.shape[0]):
        m_ref, c_ref, g_ref = reference.dynamics(q[i], qd[i], payload[i])
        assert relative_error(mass[i], m_ref, (0, 1)) <= DYNAMICS_RTOL
        assert relative_error(c_qd[i], c_ref, (0,)) <= DYNAMICS_RTOL
        assert relative_error(gravity[i], g_ref, (0,)) <= DYNAMICS_RTOL


def test_mass_matrix_coriolis_gravity_along_cycles(feeder, reference, cycle):
    """The same agreement on every 4th sample of the cycles at −4°, 30°, 70°. Relative to the
    cycle's peak of each quantity (C q̇ vanishes at the stage boundaries, where q̇ = 0)."""
    p, step = feeder.params, 4
    q, qd, payload = cycle.q[::step], cycle.v[::step], cycle.payload[::step]
    mass = lagrange.mass_matrix(p, q, payload)
    c_qd = np.einsum("nij,nj->ni", lagrange.coriolis_matrix(p, q, qd, payload), qd)
    gravity = lagrange.gravity_vector(p, q, payload)
    refs = [reference.dynamics(q[i], qd[i], payload[i]) for i in range(q.shape[0])]
    for mine, theirs in zip((mass, c_qd, gravity), zip(*refs, strict=True), strict=True):
        theirs = np.array(theirs)
        assert np.abs(mine - theirs).max() <= DYNAMICS_RTOL * np.abs(theirs).max()


def test_mass_matrix_derivative_layout_and_values(feeder, reference, states):
    """Eq. (4) layout: entry (i, 4 j + k) = ∂M_ij/∂q_k, against finite differences of M and
    against Pinocchio's exact ∂M/∂q (feeder.coriolis)."""
    from feeder.coriolis import mass_matrix_derivative

    p, (q, _, _, payload, _) = feeder.params, states
    q, payload = q[:20], payload[:20]
    closed = lagrange.mass_matrix_derivative(p, q, payload)
    assert_derivative(
        closed.reshape(-1, 4, 4, 4), lambda x: lagrange.mass_matrix(p, x, payload), q
    )
    index = feeder.index
    for i in range(q.shape[0]):
        model = reference.models[payload[i]]
        exact = mass_matrix_derivative(model, model.createData(), feeder.to_pinocchio(q[i]))
        exact = exact.reshape(4, 4, 4)[np.ix_(index, index, index)].reshape(4, 16)
        assert relative_error(closed[i], exact, (0, 1)) <= DYNAMICS_RTOL


def test_gravity_is_gradient_of_potential(feeder, states):
    p, (q, _, _, payload, _) = feeder.params, states
    assert_derivative(
        lagrange.gravity_vector(p, q, payload),
        lambda x: lagrange.potential_energy(p, x, payload),
        q,
    )


def test_closure_residual_jacobian_and_bias(feeder, states):
    p, (q, qd, qdd, _, _) = feeder.params, states
    assert np.max(np.abs(lagrange.closure_residual(p, q))) <= 1e-15  # assembled to round-off
    jac = lagrange.closure_jacobian(p, q)
    assert_derivative(jac, lambda x: lagrange.closure_residual(p, x), q)
    for i in range(10):
        world = feeder.chain.jacobian(feeder.to_pinocchio(q[i]))
        np.testing.assert_allclose(jac[i], feeder.to_paper(world[:2]), atol=1e-15)
    # f̈ = J_f q̈ + J̇_f q̇ = 0 along the closure-consistent motion; J̇_f q̇ by differences in t.
    bias = lagrange.closure_bias(p, q, qd)
    np.testing.assert_allclose(np.einsum("nij,nj->ni", jac, qdd), -bias, atol=1e-12)
    jac_dot = (
        lagrange.closure_jacobian(p, q + FD_STEP * qd)
        - lagrange.closure_jacobian(p, q - FD_STEP * qd)
    ) / (2 * FD_STEP)
    scale = np.max(np.abs(jac)) * np.max(np.abs(qd)) ** 2
    np.testing.assert_allclose(
        np.einsum("nij,nj->ni", jac_dot, qd), bias, rtol=0, atol=FD_RTOL * scale
    )


def test_forward_dynamics_match_pinocchio(feeder, reference, states):
    p, (q, qd, _, payload, tau) = feeder.params, states
    qdd, lam = lagrange.forward_dynamics(p, q, qd, tau, payload)
    assert (
        np.max(
            np.abs(
                np.einsum("nij,nj->ni", lagrange.closure_jacobian(p, q), qdd)
                + lagrange.closure_bias(p, q, qd)
            )
        )
        <= 1e-10
    )
    for i in range(q.shape[0]):
        qdd_ref, lam_ref = reference.forward(q[i], qd[i], tau[i], payload[i])
        assert relative_error(qdd[i], qdd_ref, (0,)) <= SOLVE_RTOL
        assert relative_error(lam[i], lam_ref, (0,)) <= SOLVE_RTOL


def test_inverse_dynamics_match_pinocchio(feeder, reference, states):
    p, (q, qd, qdd, payload, _) = feeder.params, states
    tau, lam = lagrange.inverse_dynamics(p, q, qd, qdd, payload)
    assert np.all(tau[:, [0, 2]] == 0.0)
    expected = reference.inverse(q, qd, qdd, payload)
    assert np.all(relative_error(tau[:, [1, 3]], expected[:, :2], (1,)) <= SOLVE_RTOL)
    assert np.all(relative_error(lam, expected[:, 2:], (1,)) <= SOLVE_RTOL)
    # And back: the forward dynamics under these loads reproduce the motion.
    qdd_back, lam_back = lagrange.forward_dynamics(p, q, qd, tau, payload)
    assert np.all(relative_error(qdd_back, qdd, (1,)) <= SOLVE_RTOL)
    assert np.all(relative_error(lam_back, lam, (1,)) <= SOLVE_RTOL)


def test_cycle_loads_match_matrix_form_and_pinocchio(feeder, reference, cycle):
    """The closed-form cycle loads equal, to round-off of the cycle's peaks, the same equations
    in matrix form (M, Kronecker C, g, J_f, LAPACK) and Pinocchio's inverse dynamics."""
    loads = lagrange.lagrange_cycle_loads(feeder, cycle)
    columns = loads.columns()
    names = (
        "lagrange_piston_force",
        "lagrange_forearm_torque",
        "lagrange_lambda1",
        "lagrange_lambda2",
    )
    closed = np.column_stack([columns[name] for name in names])
    assert closed.shape == (cycle.t.size, 4)
    motion = (cycle.q, cycle.v, cycle.a, cycle.payload)
    for expected in (matrix_inverse_dynamics(feeder.params, *motion), reference.inverse(*motion)):
        assert np.all(relative_error(closed, expected, (0,)) <= CYCLE_RTOL)
    # Pinocchio's forward dynamics driven by the Lagrange loads reproduce the cycle's q̈.
    tau = np.column_stack(
        [np.zeros_like(cycle.t), loads.piston_force, np.zeros_like(cycle.t), loads.forearm_torque]
    )
    step = 10  # every 10th sample: the forward check costs a proximal solve each
    accelerations = np.array(
        [
            reference.forward(cycle.q[i], cycle.v[i], tau[i], held)[0]
            for i, held in list(enumerate(cycle.payload))[::step]
        ]
    )
    assert np.all(relative_error(accelerations, cycle.a[::step], (0,)) <= SOLVE_RTOL)


def test_power_balance_along_cycle(feeder, cycle):
    """d(T + Π)/dt = τ · q̇ in each stage (the pin force does no work: J_f q̇ = 0).

    np.gradient (2nd order) errs by h²/6 · |E‴| inside and h²/3 · |E‴| at the stage ends; |E‴|
    is bounded by the sampled third differences / h³ (margin 2). A missing term (≥ 1e-2 of the
    peak power) is far above that bound (≈ 1e-6 of it)."""
    p, payload = feeder.params, cycle.payload
    loads = lagrange.lagrange_cycle_loads(feeder, cycle)
    mass = lagrange.mass_matrix(p, cycle.q, payload)
    energy = 0.5 * np.einsum("ni,nij,nj->n", cycle.v, mass, cycle.v)
    energy += lagrange.potential_energy(p, cycle.q, payload)
    power = loads.piston_force * cycle.v[:, 1] + loads.forearm_torque * cycle.v[:, 3]
    h = 1.0 / cycle.spec.rate
    scale = np.max(np.abs(power))
    for stage in (1, 2, 3):
        inside = cycle.stage == stage
        rate = np.gradient(energy[inside], cycle.t[inside], edge_order=2)
        third = np.abs(np.diff(energy[inside], 3)).max() / h**3
        bound = 2 * h**2 / 3 * third + 1e-12 * scale
        assert bound < 1e-4 * scale  # the check is sharp enough to see a missing term
        assert np.max(np.abs(rate - power[inside])) <= bound, stage


def test_columns_are_the_contract_names(feeder):
    cycle = feeding_cycle(feeder, 0.0)
    assert set(lagrange.lagrange_cycle_loads(feeder, cycle).columns()) == {
        "lagrange_piston_force",
        "lagrange_forearm_torque",
        "lagrange_lambda1",
        "lagrange_lambda2",
    }


def test_bad_inputs_raise(feeder):
    p = feeder.params
    q = np.array([2.4, 0.3, 0.5, 0.1])
    with pytest.raises(InputError, match="shape"):
        lagrange.mass_matrix(p, q[:3])
    with pytest.raises(InputError, match="nan"):
        lagrange.gravity_vector(p, np.array([2.4, np.nan, 0.5, 0.1]))
    with pytest.raises(InputError, match="payload"):
        lagrange.mass_matrix(p, q, payload=0.5)
    with pytest.raises(InputError, match="payload"):
        lagrange.mass_matrix(p, np.stack([q, q]), payload=np.array([1, 0, 1]))
    toggle = np.array([0.5, 0.3, 0.5, 0.0])  # piston axis along the arm lever
    with pytest.raises(SingularPoseError, match="sin"):
        lagrange.inverse_dynamics(p, toggle, np.zeros(4), np.zeros(4))
