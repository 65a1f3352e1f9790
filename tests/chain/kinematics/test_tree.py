"""Batched kinematics and Newton–Euler against Pinocchio, sample by sample: placements,
velocities, accelerations, frame Jacobians, the joints' wrenches and generalized forces, and the
closure rows of every kind."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from feeder.chain import ClosedChain, Closure, load_closed_chain
from feeder.chain.dynamics.newton_euler import generalized_forces, joint_wrenches
from feeder.chain.kinematics.joints import kind_of
from feeder.chain.kinematics.rows import closure_kinematics
from feeder.chain.kinematics.tree import frame_placements, point_jacobians, tree_motion
from feeder.device import load_feeder
from feeder.exceptions import InputError

from ...conftest import REPO

ROUND_OFF = 1e-11
"""Both sides add the same ~10 terms of size ≤ 1e3 (forces [N], with random rates of order 1):
round-off ~1e-13; 1e-11 would still catch any missing term (≥ 1e-3 here)."""

SAMPLES = 40


def frame_jacobian(model, motion, frame, columns=None):
    """The world-aligned Jacobian (N, 6, nv) of one frame on every velocity column, or on
    ``columns`` (sorted): :func:`point_jacobians` of that frame alone."""
    columns = np.arange(model.nv) if columns is None else columns
    _, origin = frame_placements(model, motion, frame)
    return point_jacobians(model, motion, [frame], [columns], origin[None])[0]


def every_joint_model() -> pin.Model:
    """A chain of every joint type the kinematics handle, with tilted placements and bodies whose
    centres of gravity lie off the joints, and a frame on the last body."""
    model = pin.Model()
    model.gravity = pin.Motion(np.array([0.3, -9.81, 0.5]), np.zeros(3))
    joints = [
        pin.JointModelRZ(),
        pin.JointModelRevoluteUnaligned(np.array([0.0, 0.6, 0.8])),
        pin.JointModelRUBX(),
        pin.JointModelRevoluteUnboundedUnaligned(),
        pin.JointModelPY(),
        pin.JointModelPrismaticUnaligned(np.array([0.6, 0.0, 0.8])),
        pin.JointModelUniversal(np.array([0.0, 0.0, 1.0]), np.array([0.0, 1.0, 0.0])),
        pin.JointModelSphericalZYX(),
        pin.JointModelSpherical(),
        pin.JointModelTranslation(),
        pin.JointModelPlanar(),
        pin.JointModelFreeFlyer(),
    ]
    rng = np.random.default_rng(7)
    parent = 0
    for i, joint in enumerate(joints):
        placement = pin.SE3(pin.exp3(rng.uniform(-1, 1, 3)), rng.uniform(-0.3, 0.3, 3))
        parent = model.addJoint(parent, joint, placement, f"j{i}")
        inertia = pin.Inertia(1.0 + i, rng.uniform(-0.1, 0.1, 3), np.diag([0.3, 0.4, 0.5]))
        model.appendBodyToJoint(parent, inertia, pin.SE3.Identity())
    frame = pin.SE3(pin.exp3(np.array([0.1, 0.2, 0.3])), np.array([0.1, -0.2, 0.05]))
    model.addFrame(pin.Frame("tip", parent, 0, frame, pin.FrameType.OP_FRAME))
    return model


@pytest.fixture(scope="module", params=["device", "every_joint"])
def device_model(request):
    if request.param == "every_joint":
        return every_joint_model()
    model = load_feeder("projectile").model
    model.gravity = pin.Motion(np.array([0.0, -9.81, 0.0]), np.zeros(3))
    return model


def _states(model, rng, n=SAMPLES):
    """Random configurations on the model's Lie groups (unit quaternions, cos/sin pairs),
    velocities and accelerations."""
    q = np.array(
        [
            pin.integrate(model, pin.neutral(model), rng.uniform(-1.5, 1.5, model.nv))
            for _ in range(n)
        ]
    )
    return q, rng.uniform(-1.0, 1.0, (n, model.nv)), rng.uniform(-1.0, 1.0, (n, model.nv))


def test_placements_and_motion_match_forward_kinematics(device_model, rng):
    model, data = device_model, device_model.createData()
    q, v, a = _states(model, rng)
    motion = tree_motion(model, q, v, a)
    for k in range(SAMPLES):
        pin.forwardKinematics(model, data, q[k], v[k], a[k])
        for j in range(1, model.njoints):
            placement = data.oMi[j]
            world = pin.SE3(placement.rotation, np.zeros(3))
            velocity = world.act(data.v[j])  # spatial velocity at the origin, world axes
            acceleration = world.act(data.a[j])
            np.testing.assert_allclose(motion.rotation[j][k], placement.rotation, atol=ROUND_OFF)
            np.testing.assert_allclose(motion.origin[j][k], placement.translation, atol=ROUND_OFF)
            np.testing.assert_allclose(motion.omega[j][k], velocity.angular, atol=ROUND_OFF)
            np.testing.assert_allclose(motion.velocity[j][k], velocity.linear, atol=ROUND_OFF)
            np.testing.assert_allclose(motion.alpha[j][k], acceleration.angular, atol=ROUND_OFF)
            classical = acceleration.linear + np.cross(velocity.angular, velocity.linear)
            np.testing.assert_allclose(motion.acceleration[j][k], classical, atol=ROUND_OFF)


def test_frame_jacobians_and_placements(device_model, rng):
    model, data = device_model, device_model.createData()
    q, _, _ = _states(model, rng)
    motion = tree_motion(model, q)
    names = ("piston_pin", "arm_pin", "projectile") if model.existFrame("arm_pin") else ("tip",)
    for name in names:
        frame = model.getFrameId(name)
        jacobian = frame_jacobian(model, motion, frame)
        rotation, origin = frame_placements(model, motion, frame)
        for k in range(SAMPLES):
            pin.computeJointJacobians(model, data, q[k])
            pin.updateFramePlacements(model, data)
            expected = pin.getFrameJacobian(model, data, frame, pin.LOCAL_WORLD_ALIGNED)
            np.testing.assert_allclose(jacobian[k], expected, atol=ROUND_OFF)
            np.testing.assert_allclose(rotation[k], data.oMf[frame].rotation, atol=ROUND_OFF)
            np.testing.assert_allclose(origin[k], data.oMf[frame].translation, atol=ROUND_OFF)


def test_newton_euler_is_rnea_with_external_forces(device_model, rng):
    model, data = device_model, device_model.createData()
    q, v, a = _states(model, rng)
    motion = tree_motion(model, q, v, a)
    frame = model.getFrameId("projectile" if model.existFrame("projectile") else "tip")
    wrench = rng.uniform(-50.0, 50.0, (SAMPLES, 6))  # world, about the frame's origin
    force, moment = joint_wrenches(model, motion, [(frame, wrench)])
    tau = generalized_forces(model, motion, force, moment)
    parent = model.frames[frame].parentJoint
    for k in range(SAMPLES):
        pin.framesForwardKinematics(model, data, q[k])
        joint, point = data.oMi[parent], data.oMf[frame].translation
        local = pin.Force(
            joint.rotation.T @ wrench[k, :3],
            joint.rotation.T
            @ (wrench[k, 3:] + np.cross(point - joint.translation, wrench[k, :3])),
        )
        fext = pin.StdVec_Force()
        for j in range(model.njoints):
            fext.append(local if j == parent else pin.Force.Zero())
        expected = pin.rnea(model, data, q[k], v[k], a[k], fext)
        np.testing.assert_allclose(tau[k], expected, atol=ROUND_OFF)
        for j in range(1, model.njoints):
            rotation = data.oMi[j].rotation
            np.testing.assert_allclose(force[j][k], rotation @ data.f[j].linear, atol=ROUND_OFF)
            np.testing.assert_allclose(moment[j][k], rotation @ data.f[j].angular, atol=ROUND_OFF)


def _assert_rows_are_the_chains(chain, rows, q, v, a) -> None:
    """The batched rows' residual, Jacobian, rate and acceleration (J q̈ + J̇ q̇) at every
    sample against :class:`ClosedChain`'s per-sample Pinocchio evaluation, to round-off."""
    for k in range(SAMPLES):
        jacobian = chain.jacobian(q[k])
        np.testing.assert_allclose(rows.residual[k], chain.residual(q[k]), atol=ROUND_OFF)
        np.testing.assert_allclose(rows.jacobian[k], jacobian, atol=ROUND_OFF)
        np.testing.assert_allclose(rows.rate[k], jacobian @ v[k], atol=ROUND_OFF)
        second = jacobian @ a[k] + chain.bias(q[k], v[k])
        np.testing.assert_allclose(rows.acceleration[k], second, atol=ROUND_OFF)


@pytest.mark.parametrize("kind", ["point", "weld", "revolute"])
def test_batched_closure_rows_match_the_chain(kind, rng):
    """Rows, Jacobian, rate and acceleration (J q̈ + J̇ q̇) of every closure kind, batched, against
    :class:`ClosedChain`'s per-sample Pinocchio evaluation (the four-bar at random states)."""
    chain = load_closed_chain(
        REPO / "examples" / "four_bar" / "four_bar.urdf",
        [Closure("coupler_tip", "rocker_tip", kind, axis=(0.2, 0.3, 0.9))],
    )
    q, v, a = _states(chain.model, rng)
    rows = closure_kinematics(chain, tree_motion(chain.model, q, v, a), v)
    _assert_rows_are_the_chains(chain, rows, q, v, a)


def test_cuts_of_one_kind_are_computed_together_with_the_others(rng):
    """Closure rows of many cuts at once (kinematics.rows: the cuts of one kind and axes in one
    set of array operations, each on its own columns, padded to the widest): two point cuts on
    bodies of different depths, two revolute cuts of one axis and one of another, a weld, in
    mixed order — rows, Jacobian, rate and acceleration against :class:`ClosedChain`'s
    per-sample Pinocchio evaluation, each cut's frames and hinge alignment in its own place."""
    from .test_layout import branched_model  # here: test_layout imports this module

    model = branched_model()
    frames = []
    for i, joint in enumerate((1, 2, 4, 5, 7, 8, model.njoints - 1, 3)):
        placement = pin.SE3(pin.exp3(rng.uniform(-1, 1, 3)), rng.uniform(-0.3, 0.3, 3))
        model.addFrame(pin.Frame(f"f{i}", joint, 0, placement, pin.FrameType.OP_FRAME))
        frames.append(f"f{i}")
    tilted = (0.2, 0.3, 0.9)
    closures = [
        Closure("f0", "f6", "point"),
        Closure("f1", "f2", "revolute", axis=tilted),
        Closure("f3", "f4", "weld"),
        Closure("f2", "f7", "point"),
        Closure("f5", "f0", "revolute", axis=tilted),
        Closure("f6", "f3", "revolute"),
    ]
    chain = ClosedChain(model, closures)
    q, v, a = _states(model, rng)
    rows = closure_kinematics(chain, tree_motion(model, q, v, a), v)
    assert list(rows.hinge_alignment) == [c.label for c in closures if c.kind == "revolute"]
    _assert_rows_are_the_chains(chain, rows, q, v, a)
    for k in range(SAMPLES):
        chain.residual(q[k])  # Pinocchio's placements of sample k in chain.data
        for cut, (fa, fb), kept in zip(chain.cuts, chain.frame_ids, rows.frames, strict=True):
            np.testing.assert_allclose(kept.origin_a[k], chain.data.oMf[fa].translation)
            np.testing.assert_allclose(kept.rotation_b[k], chain.data.oMf[fb].rotation)
            alignment = cut.alignment(chain._frames(fa, fb))
            if alignment is not None:
                assert abs(rows.hinge_alignment[cut.label][k] - alignment) <= ROUND_OFF


def test_unhandled_joint_types_are_named():
    with pytest.raises(InputError, match="JointModelHX"):
        kind_of(pin.JointModelHX(0.01))
