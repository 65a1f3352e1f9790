"""The pose object and the pose check (feeder.chain.kinematics.pose, feeder.chain.assembly.check):
a pose keeps what its kinematics computed whatever the chain computes afterwards, its point rows
are the points' velocities (central differences), a check's tangent is the closure's (central
differences of the assembly) and its rates and gain are the partition's, a check passed on vouches
for the idle motions, and a Partition keeps no state."""

from __future__ import annotations

import ast
import dataclasses
import warnings

import numpy as np
import pinocchio as pin
import pytest

from feeder.chain import Closure, Partition, load_closed_chain, load_mechanism, read_spec, track
from feeder.chain.assembly.newton import POSITION_TOLERANCE
from feeder.chain.results import ChainPose, PoseCheck, Trajectory
from feeder.exceptions import FeederWarning, InputError, UnreachablePoseError

from ...conftest import REPO

DIFFERENCE = 1e-6
"""[rad] Central-difference step: truncation h² × curvature (links ≤ 0.2 m) ~1e-13, round-off
1e-16 / h ~1e-10."""

AGAINST_DIFFERENCES = 1e-8
"""[m, rad per unit rate] Analytic rates against central differences (the two errors above)."""


@pytest.fixture(scope="module")
def four_bar():
    chain = load_closed_chain(
        REPO / "examples" / "four_bar" / "four_bar.urdf",
        [Closure("coupler_tip", "rocker_tip", "revolute")],
    )
    partition = Partition(chain, ["crank_joint"])
    return chain, partition, partition.assemble(np.array([0.7, -0.35, 1.0]))


def test_a_pose_keeps_its_kinematics_whatever_the_chain_computes_next(four_bar):
    chain, _, q = four_bar
    given = q.copy()
    pose = ChainPose(chain, given)
    given[0] += 1.0  # the pose holds a copy
    chain.jacobian(q + 0.3)  # the chain's data now hold another configuration
    chain.residual(q - 0.2)
    np.testing.assert_array_equal(pose.q, q)
    np.testing.assert_array_equal(pose.jacobian, chain.jacobian(q))
    np.testing.assert_array_equal(pose.residual, chain.residual(q))
    assert pose.gap <= POSITION_TOLERANCE and pose.reversed_hinges == ()
    for array in (pose.q, pose.jacobian, pose.residual):
        with pytest.raises(ValueError, match="read-only"):
            array[0] = 0.0


def test_a_pose_names_a_hinge_assembled_upside_down():
    """The four-bar cut with its hinge axes declared opposite: the rows vanish, the hinge is
    upside down (tests/chain/model/test_closure.py refuses it in assembly)."""
    closure = Closure("coupler_tip", "rocker_tip", "revolute", axis_b=(0.0, 0.0, -1.0))
    chain = load_closed_chain(REPO / "examples" / "four_bar" / "four_bar.urdf", [closure])
    assert ChainPose(chain, np.array([0.7, -0.35, 1.0])).reversed_hinges == (closure.label,)


def test_point_rows_are_the_points_velocities(four_bar):
    """Every joint origin, centre of gravity and frame origin: the rows times a rate direction
    against central differences of the positions."""
    chain, _, q = four_bar
    model = chain.model
    data = model.createData()

    def points(config: np.ndarray) -> np.ndarray:
        pin.forwardKinematics(model, data, config)
        pin.updateFramePlacements(model, data)
        out = []
        for j in range(1, model.njoints):
            out.append(data.oMi[j].translation.copy())
            if model.inertias[j].mass > 0.0:
                out.append(data.oMi[j].act(model.inertias[j].lever))
        moving = [f for f in range(1, model.nframes) if model.frames[f].parentJoint > 0]
        out += [data.oMf[f].translation.copy() for f in moving]  # the ground's do not move
        return np.concatenate(out)

    rows = ChainPose(chain, q).point_rows()
    for direction in np.random.default_rng(7).normal(size=(3, model.nv)):
        plus = points(pin.integrate(model, q, DIFFERENCE * direction))
        minus = points(pin.integrate(model, q, -DIFFERENCE * direction))
        expected = (plus - minus) / (2.0 * DIFFERENCE)
        np.testing.assert_allclose(rows @ direction, expected, atol=AGAINST_DIFFERENCES)


def test_a_check_holds_the_partitions_rates_and_the_closures_tangent(four_bar):
    chain, partition, q = four_bar
    checked = partition.check_pose(ChainPose(chain, q))
    assert isinstance(checked, PoseCheck)
    np.testing.assert_array_equal(checked.jacobian, chain.jacobian(q))
    assert checked.gain == partition.gain(q)
    np.testing.assert_array_equal(checked.velocity(np.array([1.5])), partition.velocity(q, [1.5]))
    v = checked.velocity(np.array([1.5]))
    np.testing.assert_array_equal(
        checked.acceleration(v, np.array([2.0])), partition.acceleration(q, v, [2.0])
    )
    assert checked.idle_count == 0 and checked.idle_motions().shape == (0, chain.model.nv)
    x = partition.independent_values(q)
    ahead, behind = (
        partition.assemble(partition.with_independent(q, x + sign * DIFFERENCE))
        for sign in (1.0, -1.0)
    )
    expected = (ahead - behind)[partition.dependent] / (2.0 * DIFFERENCE)
    np.testing.assert_allclose(checked.tangent()[:, 0], expected, atol=AGAINST_DIFFERENCES)
    step = checked.step(np.array([0.01]))
    assert step[partition.independent] == 0.01
    np.testing.assert_allclose(
        step[partition.dependent], 0.01 * checked.tangent()[:, 0], rtol=1e-12
    )
    with pytest.raises(dataclasses.FrozenInstanceError):
        checked.gain = 0.0


def test_a_check_passed_on_vouches_for_the_idle_motions(monkeypatch):
    """The 5-bar's coaxial hinges turn together with the motors locked (one idle motion): the
    first check tests that it moves no point; a later one handed the first check does not test
    again, and finds the same motion."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FeederWarning)
        spec = read_spec(REPO / "examples" / "cad" / "5bar_linkage" / "robot.yaml")
        chain = load_mechanism(spec)
    partition = Partition(chain, spec.independent)
    q0 = partition.mount(pin.neutral(chain.model))
    x = partition.independent_values(q0)
    q1 = partition.assemble(partition.with_independent(q0, x + 0.05))
    tests = []
    rows = ChainPose.point_rows
    monkeypatch.setattr(ChainPose, "point_rows", lambda pose: tests.append(1) or rows(pose))
    first = partition.check_pose(ChainPose(chain, q0))
    assert len(tests) == 1 and first.idle_count == 1
    second = partition.check_pose(ChainPose(chain, q1), previous=first)
    assert len(tests) == 1
    assert second.idle_count == 1
    np.testing.assert_array_equal(second.idle_motions(), partition.idle_motions(q1))
    partition.check_pose(ChainPose(chain, q1))  # nothing handed on: tested again
    assert len(tests) == 3


def test_a_partition_keeps_no_state(four_bar):
    """Everything a Partition holds is set at construction: checks, rates and a tracked motion
    (batched, then the sequential way) leave it as it was, and it refuses new attributes."""
    chain, _, q = four_bar
    partition = Partition(chain, ["crank_joint"])
    before = {name: np.copy(value) for name, value in vars(partition).items()}
    identity = {name: id(value) for name, value in vars(partition).items()}
    x = partition.independent_values(q) + np.linspace(0.0, 1.0, 100)[:, None]
    assert track(partition, q, x).batched
    assert not track(partition, q, x[:10]).batched
    partition.check_pose(ChainPose(chain, q))
    partition.velocity(q, [1.0])
    assert {name: id(value) for name, value in vars(partition).items()} == identity
    for name, value in vars(partition).items():
        if isinstance(value, np.ndarray):
            np.testing.assert_array_equal(value, before[name])
    with pytest.raises(AttributeError, match="immutable"):
        partition.max_gain = 10.0
    with pytest.raises(ValueError, match="read-only"):
        partition.dependent[0] = 0


def test_a_trajectory_is_read_only_and_of_one_length(four_bar):
    chain, partition, q = four_bar
    x = partition.independent_values(q) + np.linspace(0.0, 0.5, 5)[:, None]
    motion = track(partition, q, x, t=np.linspace(0.0, 1.0, 5))
    assert len(motion) == 5 and motion.q.shape == (5, chain.model.nq)
    for array in (motion.q, motion.v, motion.a, motion.gain):
        with pytest.raises(ValueError, match="read-only"):
            array[0] = 0.0
    with pytest.raises(InputError, match="one row per sample"):
        Trajectory(motion.q, motion.v[:4], motion.a, motion.gain)


def test_the_assembly_reaches_no_other_modules_private_names():
    """The modules of the assembly, the mobility report and the analysis call one another's
    public methods only: no ``obj._name`` but on ``self``."""
    modules = [
        *sorted((REPO / "feeder" / "chain" / "assembly").glob("*.py")),
        REPO / "feeder" / "chain" / "mobility.py",
        REPO / "feeder" / "chain" / "kinematics" / "pose.py",
        REPO / "feeder" / "study" / "analyze.py",
    ]
    found = []
    for path in modules:
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if (
                isinstance(node, ast.Attribute)
                and node.attr.startswith("_")
                and not node.attr.startswith("__")
                and not (isinstance(node.value, ast.Name) and node.value.id in ("self", "cls"))
            ):
                found.append(f"{path.name}:{node.lineno} {ast.unparse(node)}")
    assert not found


def test_one_pose_and_a_batch_are_refused_alike_outside_the_limits(four_bar):
    """The joint limits (±4π here): one pose (a continuation step's scalar test) and the same
    pose among others (the batched test) name the same joint, its role, value and range."""
    chain, partition, q = four_bar
    model = chain.model
    for joint, role, tail in (
        ("crank_joint", "prescribed", "]$"),
        ("rocker_joint", "dependent", "] where the loops close$"),
    ):
        outside = q.copy()
        outside[model.joints[model.getJointId(joint)].idx_q] = 13.0
        pattern = (
            rf"^the {role} joint {joint} = 13 is outside its limits \[-12.5664, 12.5664{tail}"
        )
        for poses in (outside, np.stack([q, outside, q])):
            with pytest.raises(UnreachablePoseError, match=pattern):
                partition.check_limits(poses)
    partition.check_limits(q)
    partition.check_limits(np.stack([q, q]))
