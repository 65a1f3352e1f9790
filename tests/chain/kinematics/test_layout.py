"""The tree's layout (joints grouped by depth and kind, kept per model) against Pinocchio on a
branched tree, and its cache: kept with the model, found again when the model grows, never
holding what a caller may change in place (placements, masses)."""

from __future__ import annotations

import gc

import numpy as np
import pinocchio as pin

from feeder.chain.dynamics.newton_euler import generalized_forces, joint_wrenches
from feeder.chain.kinematics import layout as layout_module
from feeder.chain.kinematics.layout import tree_layout
from feeder.chain.kinematics.tree import tree_motion

from .test_tree import ROUND_OFF, _states, frame_jacobian

SAMPLES = 12


def branched_model() -> pin.Model:
    """A tree whose depths hold several joints of one kind on different parents (revolute,
    continuous, prismatic; the groups of the layout) beside joints of other kinds (a ball, a
    universal joint), tilted placements, off-centre bodies and a frame on a deep body."""
    model = pin.Model()
    model.gravity = pin.Motion(np.array([0.2, -9.81, 0.4]), np.zeros(3))
    rng = np.random.default_rng(3)

    def add(parent: int, joint: pin.JointModel, name: str) -> int:
        placement = pin.SE3(pin.exp3(rng.uniform(-1, 1, 3)), rng.uniform(-0.4, 0.4, 3))
        j = model.addJoint(parent, joint, placement, name)
        inertia = pin.Inertia(
            1.0 + rng.uniform(), rng.uniform(-0.1, 0.1, 3), np.diag([0.2, 0.3, 0.4])
        )
        model.appendBodyToJoint(j, inertia, pin.SE3.Identity())
        return j

    tops = [add(0, pin.JointModelRZ(), "r1"), add(0, pin.JointModelRUBX(), "c1")]
    tops.append(add(0, pin.JointModelPrismaticUnaligned(np.array([0.6, 0.0, 0.8])), "p1"))
    middle = [add(top, pin.JointModelRY(), f"r2_{i}") for i, top in enumerate(tops)]
    middle.append(add(tops[0], pin.JointModelSpherical(), "ball"))
    middle.append(add(tops[1], pin.JointModelPY(), "p2"))
    deep = add(
        middle[3], pin.JointModelUniversal(np.array([0, 0, 1.0]), np.array([0, 1.0, 0])), "u"
    )
    add(deep, pin.JointModelRUBZ(), "c3")
    frame = pin.SE3(pin.exp3(np.array([0.1, 0.2, 0.3])), np.array([0.1, -0.2, 0.05]))
    model.addFrame(pin.Frame("tip", model.njoints - 1, 0, frame, pin.FrameType.OP_FRAME))
    return model


def test_the_layout_groups_each_depth_by_kind():
    layout = tree_layout(branched_model())
    kinds = [sorted(group.kind for group in level) for level in layout.levels]
    assert kinds == [
        ["continuous", "prismatic", "revolute"],
        ["prismatic", "revolute", "spherical"],
        ["universal"],
        ["continuous"],
    ]
    sizes = {group.kind: group.joints.size for group in layout.levels[1]}
    assert sizes == {"revolute": 3, "prismatic": 1, "spherical": 1}


def test_a_branched_tree_matches_pinocchio(rng):
    """Placements, rates, the frame Jacobian and the Newton–Euler pass of the grouped recursion
    against Pinocchio's forward kinematics, frame Jacobian and RNEA, sample by sample."""
    model = branched_model()
    data = model.createData()
    q, v, a = _states(model, rng, SAMPLES)
    motion = tree_motion(model, q, v, a)
    frame = model.getFrameId("tip")
    jacobian = frame_jacobian(model, motion, frame)
    tau = generalized_forces(model, motion, *joint_wrenches(model, motion))
    for k in range(SAMPLES):
        pin.forwardKinematics(model, data, q[k], v[k], a[k])
        for j in range(1, model.njoints):
            world = pin.SE3(data.oMi[j].rotation, np.zeros(3))
            velocity, acceleration = world.act(data.v[j]), world.act(data.a[j])
            np.testing.assert_allclose(motion.rotation[j][k], data.oMi[j].rotation, atol=ROUND_OFF)
            np.testing.assert_allclose(
                motion.origin[j][k], data.oMi[j].translation, atol=ROUND_OFF
            )
            np.testing.assert_allclose(motion.omega[j][k], velocity.angular, atol=ROUND_OFF)
            np.testing.assert_allclose(motion.velocity[j][k], velocity.linear, atol=ROUND_OFF)
            np.testing.assert_allclose(motion.alpha[j][k], acceleration.angular, atol=ROUND_OFF)
            classical = acceleration.linear + np.cross(velocity.angular, velocity.linear)
            np.testing.assert_allclose(motion.acceleration[j][k], classical, atol=ROUND_OFF)
        pin.computeJointJacobians(model, data, q[k])
        pin.updateFramePlacements(model, data)
        expected = pin.getFrameJacobian(model, data, frame, pin.LOCAL_WORLD_ALIGNED)
        np.testing.assert_allclose(jacobian[k], expected, atol=ROUND_OFF)
        np.testing.assert_allclose(tau[k], pin.rnea(model, data, q[k], v[k], a[k]), atol=ROUND_OFF)


def test_a_frame_jacobian_on_some_columns_is_those_of_the_whole_one(rng):
    model = branched_model()
    q, _, _ = _states(model, rng, SAMPLES)
    motion = tree_motion(model, q)
    frame = model.getFrameId("tip")
    whole = frame_jacobian(model, motion, frame)
    columns = np.flatnonzero(np.abs(whole).max(axis=(0, 1)) > 0.0)
    columns = np.union1d(columns, [0])  # a column that does not move the frame: zero
    np.testing.assert_array_equal(
        frame_jacobian(model, motion, frame, columns), whole[:, :, columns]
    )


def test_the_layout_is_kept_per_model_and_found_again_when_the_model_grows(rng):
    model = branched_model()
    first = tree_layout(model)
    assert tree_layout(model) is first  # kept
    other = branched_model()
    assert tree_layout(other) is not first  # one per model, even an equal one
    q, v, a = _states(model, rng, SAMPLES)
    cached = tree_motion(model, q, v, a)
    layout_module._layouts.clear()  # noqa: SLF001 - the same values from a fresh layout
    fresh = tree_motion(model, q, v, a)
    for name in ("rotation", "origin", "omega", "alpha", "velocity", "acceleration"):
        np.testing.assert_array_equal(getattr(cached, name), getattr(fresh, name))
    grown = model.addJoint(model.njoints - 1, pin.JointModelRX(), pin.SE3.Identity(), "added")
    model.appendBodyToJoint(grown, pin.Inertia.Random(), pin.SE3.Identity())
    assert len(tree_layout(model).slices) == model.njoints  # found again for the new size
    q, v, a = _states(model, rng, 2)
    data = model.createData()
    pin.forwardKinematics(model, data, q[1], v[1], a[1])
    placed = tree_motion(model, q, v, a).origin[grown][1]
    np.testing.assert_allclose(placed, data.oMi[grown].translation, atol=ROUND_OFF)


def test_placements_and_masses_changed_in_place_are_read_again(rng):
    model = branched_model()
    q, v, a = _states(model, rng, SAMPLES)
    tree_motion(model, q, v, a)  # the layout is now kept
    model.jointPlacements[2] = pin.SE3(pin.exp3(np.array([0.3, -0.2, 0.1])), np.ones(3))
    model.inertias[3] = pin.Inertia(7.0, np.array([0.1, 0.2, 0.0]), np.diag([1.0, 2.0, 3.0]))
    motion = tree_motion(model, q, v, a)
    tau = generalized_forces(model, motion, *joint_wrenches(model, motion))
    data = model.createData()
    for k in range(SAMPLES):
        pin.forwardKinematics(model, data, q[k], v[k], a[k])
        np.testing.assert_allclose(motion.origin[5][k], data.oMi[5].translation, atol=ROUND_OFF)
        np.testing.assert_allclose(tau[k], pin.rnea(model, data, q[k], v[k], a[k]), atol=ROUND_OFF)


def test_the_layout_goes_with_its_model():
    model = branched_model()
    tree_layout(model)
    count = len(layout_module._layouts)  # noqa: SLF001
    del model
    gc.collect()
    assert len(layout_module._layouts) == count - 1  # noqa: SLF001


def test_a_row_sum_adds_repeated_rows_as_numpy_add_at(rng):
    """RowSum (the backward pass's sum into parents, found once per model) against numpy's own
    unbuffered ``np.add.at``, with and without a repeated index: the same sums of a few terms
    (round-off ~1e-16 of values of size 1, 1e-14 leaves room for the order of the sums)."""
    for index in (np.array([4, 1, 3]), np.array([2, 0, 2, 2, 5, 0])):
        target = rng.normal(size=(6, 7, 3))
        values = rng.normal(size=(index.size, 7, 3))
        expected = target.copy()
        np.add.at(expected, index, values)
        layout_module.RowSum.of(index).add(target, values)
        assert np.allclose(target, expected, rtol=0.0, atol=1e-14)
    assert layout_module.RowSum.of(np.array([4, 1, 3])).incidence is None
