"""Loop closures on any URDF: world-frame residual, Jacobian and bias against finite differences
and against Pinocchio's own constraint model; the four-bar from example-robot-data."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from feeder.chain import ClosedChain, Closure, load_closed_chain
from feeder.chain.assembly.partition import POSITION_TOLERANCE, Partition
from feeder.chain.readers.urdf import build_model
from feeder.exceptions import ClosureFrameError, InputError, UnreachablePoseError

from ...conftest import FOURBAR_COUPLER, FOURBAR_CRANK, FOURBAR_GROUND, FOURBAR_ROCKER, REPO

FD_STEP = 1e-6
"""Central-difference step [rad or m]: truncation O(h²) ~ 1e-12, round-off ~ 1e-16/h ~ 1e-10."""
FD_TOLERANCE = 1e-8
"""Agreement of analytic and central-difference derivatives, above both error terms."""
ROUND_OFF = 1e-12
"""Identities evaluated in double precision on a ~1 m mechanism."""
PROXIMAL_ACCURACY, PROXIMAL_MU, PROXIMAL_ITERATIONS = 1e-14, 1e-10, 20
"""constraintDynamics' proximal solver: stop at |Δλ| ≤ 1e-14 with regularisation mu = 1e-10."""
KKT_CONDITIONING = 100
"""Head-room over the rounding of J q̈ + J̇ q̇ for the conditioning of the KKT factorisation."""


@pytest.fixture(scope="module")
def fourbar(fourbar_urdf):
    """The four-bar of conftest, closed at the rocker tip on the ground pin."""
    return load_closed_chain(fourbar_urdf, [("rocker_tip", "ground_pin")])


def chains(feeder, fourbar):
    """The two closed chains under test, by name."""
    return {"feeder": feeder.chain, "fourbar": fourbar}


@pytest.mark.parametrize("which", ["feeder", "fourbar"])
def test_jacobian_and_bias_match_finite_differences(which, feeder, fourbar, rng):
    chain = chains(feeder, fourbar)[which]
    model = chain.model
    for _ in range(5):
        q = rng.uniform(
            np.maximum(model.lowerPositionLimit, -3), np.minimum(model.upperPositionLimit, 3)
        )
        v = rng.normal(size=model.nv)
        jac = chain.jacobian(q)
        numeric = np.column_stack(
            [
                (chain.residual(q + FD_STEP * e) - chain.residual(q - FD_STEP * e)) / (2 * FD_STEP)
                for e in np.eye(model.nv)
            ]
        )
        np.testing.assert_allclose(jac, numeric, atol=FD_TOLERANCE)
        # J̇ v = d/dt (J(q) v) along q(t) = q + t v.
        jdot_v = (
            (chain.jacobian(q + FD_STEP * v) - chain.jacobian(q - FD_STEP * v)) @ v / (2 * FD_STEP)
        )
        np.testing.assert_allclose(chain.bias(q, v), jdot_v, atol=FD_TOLERANCE * (1 + v @ v))


@pytest.mark.parametrize("which", ["feeder", "fourbar"])
def test_pinocchio_constraint_is_the_same_closure(which, feeder, fourbar, rng):
    """Pinocchio's CONTACT_3D Jacobian (LOCAL frame of frame_a) is the world one, rotated."""
    chain = chains(feeder, fourbar)[which]
    model, data = chain.model, chain.data
    q = rng.uniform(
        np.maximum(model.lowerPositionLimit, -3), np.minimum(model.upperPositionLimit, 3)
    )
    pin.computeJointJacobians(model, data, q)
    for cmodel, cdata in zip(chain.constraint_models, chain.constraint_datas, strict=True):
        cmodel.calc(model, data, cdata)
    local = pin.getConstraintsJacobian(
        model, data, chain.constraint_models, chain.constraint_datas
    )
    pin.framesForwardKinematics(model, data, q)
    rotation = data.oMf[chain.frame_ids[0][0]].rotation
    np.testing.assert_allclose(rotation @ local, chain.jacobian(q), atol=ROUND_OFF)


def fourbar_analytic(crank: float) -> np.ndarray:
    """Joint angles [θ1, θ2, θ3] of the four-bar from circle intersection (open branch).

    Planar in (y, z) about x; angles from +z towards −y... obtained from Pinocchio's convention:
    a link along +z turned by θ about +x points along (−sin θ, cos θ) in (y, z).
    """

    def direction(angle):
        return np.array([-np.sin(angle), np.cos(angle)])

    knee = FOURBAR_CRANK * direction(crank)
    ground = np.array([FOURBAR_GROUND, 0.0])
    gap = ground - knee
    dist = np.linalg.norm(gap)
    # Coupler end P with |P − knee| = coupler, |P − ground| = rocker: circle intersection.
    along = (FOURBAR_COUPLER**2 - FOURBAR_ROCKER**2 + dist**2) / (2 * dist)
    height = np.sqrt(FOURBAR_COUPLER**2 - along**2)
    normal = np.array([-gap[1], gap[0]]) / dist
    elbow = knee + along * gap / dist + height * normal
    absolute2 = np.arctan2(-(elbow - knee)[0], (elbow - knee)[1])
    absolute3 = np.arctan2(-(ground - elbow)[0], (ground - elbow)[1])
    return np.array([crank, absolute2 - crank, absolute3 - absolute2])


def test_fourbar_assembles_as_the_analytic_four_bar(fourbar):
    """Newton stops at a closure residual ≤ POSITION_TOLERANCE [m]; its angles then err by at
    most g · POSITION_TOLERANCE, g = 1/σ_min of the dependent Jacobian (≤ 10 rad/m here)."""
    partition = Partition(fourbar, ["joint1"])
    for crank in np.linspace(-np.pi, np.pi, 13):
        expected = fourbar_analytic(crank)
        guess = expected + np.array([0.0, 0.05, -0.05])  # near the branch, not on it
        q = partition.assemble(guess)
        assert np.linalg.norm(fourbar.residual(q)) <= POSITION_TOLERANCE
        jac_dep = fourbar.jacobian(q)[:, partition.dependent]
        gain = 1.0 / np.linalg.svd(jac_dep, compute_uv=False).min()
        difference = np.angle(np.exp(1j * (q - expected)))  # equal modulo 2π
        np.testing.assert_allclose(difference, 0.0, atol=gain * POSITION_TOLERANCE + ROUND_OFF)


def test_fourbar_constraint_is_ready_for_constrained_dynamics(fourbar):
    """constraintDynamics on the loaded closure keeps J q̈ + J̇ q̇ = 0."""
    model, data = fourbar.model, fourbar.data
    partition = Partition(fourbar, ["joint1"])
    q = partition.assemble(fourbar_analytic(0.3) + 0.01)
    v = partition.velocity(q, [1.5])
    settings = pin.ProximalSettings(PROXIMAL_ACCURACY, PROXIMAL_MU, PROXIMAL_ITERATIONS)
    pin.initConstraintDynamics(model, data, fourbar.constraint_models, fourbar.constraint_datas)
    a = pin.constraintDynamics(
        model,
        data,
        q,
        v,
        np.zeros(model.nv),
        fourbar.constraint_models,
        fourbar.constraint_datas,
        settings,
    )
    jac, bias = fourbar.jacobian(q), fourbar.bias(q, v)
    residual = jac @ a + bias
    # Each proximal iteration solves (G + mu) λ_k = rhs + mu λ_(k−1), so the constraint error
    # G λ_k − rhs = mu (λ_(k−1) − λ_k) ≤ 1e-10 · 1e-14 when it stops (|Δλ| ≤ 1e-14): nothing
    # but the rounding of J q̈ + J̇ q̇ is left, ~eps (|J| |q̈| + |J̇ q̇|) ≈ 2e-15 here (q̈ ≈ 40
    # rad/s²); the factor 100 covers the KKT factorisation's conditioning. Measured 9e-16.
    rounding = (
        KKT_CONDITIONING
        * np.finfo(float).eps
        * (np.linalg.norm(jac, 2) * np.linalg.norm(a) + np.linalg.norm(bias))
    )
    assert np.linalg.norm(residual) <= rounding


def test_the_corrected_constraints_pull_an_open_loop_shut(fourbar):
    """Baumgarte's copies (ClosedChain.corrected_constraints): constraintDynamics then meets
    J q̈ + J̇ q̇ = −K_d J q̇ − K_p r with K_p = ω², K_d = 2ω at a pose off the loop and rates
    that open it; the chain's own models keep no corrector (what the inverse dynamics and
    another run's copies start from)."""
    model, data = fourbar.model, fourbar.data
    partition = Partition(fourbar, ["joint1"])
    q = partition.assemble(fourbar_analytic(0.3)) + 1e-3  # the loop open by ~1 mm
    v = np.array([1.5, -0.7, 0.4])[: model.nv]
    omega = 7.0
    models, datas = fourbar.corrected_constraints(data, omega)
    settings = pin.ProximalSettings(PROXIMAL_ACCURACY, PROXIMAL_MU, PROXIMAL_ITERATIONS)
    a = pin.constraintDynamics(model, data, q, v, np.zeros(model.nv), models, datas, settings)
    jac, bias, r = fourbar.jacobian(q), fourbar.bias(q, v), fourbar.residual(q)
    pull = -2.0 * omega * (jac @ v) - omega**2 * r
    assert np.abs(pull).max() > 1e-2  # the corrector acts
    # the loop's rows are points (3 per cut, world axes), where Pinocchio's LOCAL rows are the
    # same rows turned: the rows agree to the rounding of the KKT solve (as the test above)
    rounding = (
        KKT_CONDITIONING
        * np.finfo(float).eps
        * (
            np.linalg.norm(jac, 2) * np.linalg.norm(a)
            + np.linalg.norm(bias)
            + np.linalg.norm(pull)
        )
    )
    assert np.linalg.norm(jac @ a + bias - pull) <= rounding
    for constraint in fourbar.constraint_models:
        assert constraint.m_baumgarte_parameters.Kp == 0.0
        assert constraint.m_baumgarte_parameters.Kd == 0.0


def test_closures_must_be_pairs_of_frames_on_two_bodies(fourbar_urdf, fourbar):
    for bad in (None, "rocker_tip", [("rocker_tip", "ground_pin", "link1")], [("rocker_tip",)]):
        with pytest.raises(InputError, match="pair|sequence") as info:
            load_closed_chain(fourbar_urdf, bad)
        assert repr(bad if bad is None or isinstance(bad, str) else bad[0]) in str(info.value)
    with pytest.raises(InputError, match="same body"):
        load_closed_chain(fourbar_urdf, [("rocker_tip", "rocker_tip")])
    with pytest.raises(InputError, match=r"same body \(joint 'joint3'\)"):
        load_closed_chain(fourbar_urdf, [("rocker", "rocker_tip")])  # tip: fixed to the rocker
    with pytest.raises(ClosureFrameError, match="'nowhere'"):
        load_closed_chain(fourbar_urdf, [("rocker_tip", "nowhere")])
    assert fourbar.frame_id("rocker_tip") == fourbar.model.getFrameId("rocker_tip")
    with pytest.raises(InputError, match="no frame 'nope'"):
        fourbar.frame_id("nope")


@pytest.mark.parametrize(
    "second",
    [
        ("ground_pin", "rocker_tip"),
        Closure("rocker_tip", "ground_pin", "weld", name="again"),
        Closure("ground_pin", "rocker_tip", "revolute", name="reversed"),
    ],
    ids=["reversed-pair", "renamed-weld", "renamed-reversed-hinge"],
)
def test_the_same_cut_twice_is_refused(fourbar_urdf, second):
    """One loop listed twice, in either order, whatever its kind and name, is not two cuts: the
    message names both entries."""
    match = r"closures #1 \(rocker_tip-ground_pin\) and #2 \(.+\) join the same frames"
    with pytest.raises(InputError, match=match):
        load_closed_chain(fourbar_urdf, [("rocker_tip", "ground_pin"), second])


def _link(name: str) -> str:
    inertia = '<inertia ixx="0.01" iyy="0.02" izz="0.02" ixy="0" ixz="0" iyz="0"/>'
    return f'<link name="{name}"><inertial><mass value="1"/>{inertia}</inertial></link>'


def _joint(name, kind, parent, child, xyz, rpy, axis=None) -> str:
    limit = '<limit lower="-9" upper="9" effort="1" velocity="1"/>' if axis else ""
    axis = f'<axis xyz="{axis}"/>' if axis else ""
    return (
        f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        f'<origin xyz="{xyz}" rpy="{rpy}"/>{axis}{limit}</joint>'
    )


SPATIAL = (
    '<robot name="spatial"><link name="base"/><link name="tip"/><link name="tip2"/>'
    + "".join(_link(f"l{i}") for i in range(1, 6))
    + _joint("j1", "revolute", "base", "l1", "0 0 0", "0 0 0", "0 0 1")
    + _joint("j2", "revolute", "l1", "l2", "0.3 0 0", "0.1 0 0", "0 1 0")
    + _joint("j3", "revolute", "l2", "l3", "0.3 0 0", "0 0.2 0", "1 0 0")
    + _joint("j4", "revolute", "base", "l4", "0.5 0.2 0", "0 0 0.3", "0 0 1")
    + _joint("j5", "prismatic", "l4", "l5", "0.1 0 0", "0 0 0", "0.6 0.8 0")
    + _joint("tip_joint", "fixed", "l3", "tip", "0.2 0.05 0", "0.3 0.1 0.2")
    + _joint("tip2_joint", "fixed", "l5", "tip2", "0.3 0 0.1", "0 0.4 0")
    + "</robot>"
)
"""Two spatial branches (revolute joints about z, y, x and a slanted prismatic one) whose tips
can be cut with any closure kind: the rows' derivatives are checked away from any plane."""

STEP = 1e-6
"""Central-difference step [rad, m]: truncation error ~h² ≈ 1e-12 for unit curvatures, round-off
~ε/h ≈ 1e-10; the comparisons allow 1e-8."""


@pytest.mark.parametrize("kind", ["point", "weld", "revolute"])
def test_spatial_rows_are_the_derivatives_of_the_residual(kind, rng):
    chain = ClosedChain(
        build_model(SPATIAL, "<spatial>"), [Closure("tip", "tip2", kind, axis=(0.2, 0.3, 0.9))]
    )
    n = chain.model.nv
    for _ in range(5):
        q, v = rng.uniform(-1.0, 1.0, n), rng.uniform(-1.0, 1.0, n)
        exact = chain.residual_jacobian(q)
        differences = np.column_stack(
            [
                (chain.residual(q + STEP * e) - chain.residual(q - STEP * e)) / (2 * STEP)
                for e in np.eye(n)
            ]
        )
        np.testing.assert_allclose(exact, differences, atol=1e-8)
        # J̇ q̇ along the straight path q + t v (q̈ = 0): d/dt [J(q + t v)] v.
        rate = (chain.jacobian(q + STEP * v) - chain.jacobian(q - STEP * v)) @ v / (2 * STEP)
        np.testing.assert_allclose(chain.bias(q, v), rate, atol=1e-8)
        if kind != "weld":  # the weld's velocity rows equal its residual's only at closure
            np.testing.assert_allclose(chain.jacobian(q), exact, atol=1e-12)


def test_a_hinge_assembled_upside_down_is_not_closed():
    """The example four-bar cut with hinge axes declared opposite (+z on the coupler, −z on the
    rocker): its hinge rows vanish at every pose (all axes are parallel), but the hinge would be
    upside down everywhere, which assembly and the dynamics both refuse."""
    from feeder.chain.dynamics.inverse import ChainDynamics, inverse_dynamics

    closure = Closure("coupler_tip", "rocker_tip", "revolute", axis_b=(0.0, 0.0, -1.0))
    chain = load_closed_chain(REPO / "examples" / "four_bar" / "four_bar.urdf", [closure])
    with pytest.raises(UnreachablePoseError):
        Partition(chain, ["crank_joint"]).assemble(np.array([0.7, -0.35, 1.0]))
    upright = load_closed_chain(
        REPO / "examples" / "four_bar" / "four_bar.urdf", [("coupler_tip", "rocker_tip")]
    )
    q = Partition(upright, ["crank_joint"]).assemble(np.array([0.7, -0.35, 1.0]))
    with pytest.raises(UnreachablePoseError, match="upside down"):
        inverse_dynamics(
            ChainDynamics(chain, ["crank_joint"]), q[None], np.zeros((1, 3)), np.zeros((1, 3))
        )


@pytest.mark.parametrize(
    "names, match",
    [
        ("mot1", "must be a list of names"),
        (["mot1", "mot1"], "must be distinct"),
        (["no_such_joint"], "no joint 'no_such_joint'"),
        (["right_spherical_foot_1"], "has 3 coordinates"),  # a ball joint (YAML override)
        (["left_spherical_ankle_1"], "has 2 coordinates"),  # a universal joint
    ],
)
def test_prescribed_and_actuated_joints_have_one_coordinate(names, match):
    """One check for the partition's independent joints and the dynamics' actuated ones."""
    import warnings

    from feeder.chain import ChainDynamics, Partition, load_mechanism, read_spec
    from feeder.exceptions import FeederWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FeederWarning)
        chain = load_mechanism(read_spec(REPO / "examples" / "cad" / "battobot_6d" / "robot.yaml"))
    with pytest.raises(InputError, match=match):
        Partition(chain, names)
    with pytest.raises(InputError, match=match):
        ChainDynamics(chain, names)
