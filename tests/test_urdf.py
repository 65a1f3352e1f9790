"""Generated URDF: shipped files equal the generator, names, and two parsers agree."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
import yourdfpy

from feeder import CLOSURE, DEVICES, PAPER_JOINTS, load_feeder, urdf_string

from .conftest import REPO

FK_TOLERANCE = 1e-12
"""[m] and [-]: both libraries compose the same few transforms in double precision."""


@pytest.mark.parametrize("name", sorted(DEVICES))
def test_shipped_urdf_equals_generator(name):
    shipped = (REPO / "urdf" / f"{name}_feeder.urdf").read_text(encoding="utf-8")
    assert shipped == urdf_string(DEVICES[name]), "run `feeder urdf` to regenerate"


def test_names(feeder):
    model = feeder.model
    for joint in PAPER_JOINTS:
        assert model.existJointName(joint)
    for frame in (
        "frame",
        "cylinder",
        "piston",
        "arm",
        "forearm",
        "projectile",
        "projectile_joint",
        *CLOSURE,
    ):
        assert model.existFrame(frame), frame
    assert model.frames[model.getFrameId("projectile_joint")].type == pin.FrameType.FIXED_JOINT


def test_inertials_come_from_the_parameters(feeder):
    robot = yourdfpy.URDF.load(
        str(REPO / "urdf" / "projectile_feeder.urdf"), build_scene_graph=False, load_meshes=False
    )
    for link, inertia in feeder.params.links().items():
        inertial = robot.link_map[link].inertial
        assert inertial.mass == inertia.mass
        np.testing.assert_array_equal(np.diag(inertial.inertia), inertia.moments)


@pytest.mark.parametrize("name", sorted(DEVICES))
def test_pinocchio_and_yourdfpy_forward_kinematics_agree(name, rng):
    feeder = load_feeder(name)
    model, data = feeder.model, feeder.chain.data
    robot = yourdfpy.URDF.load(
        str(REPO / "urdf" / f"{name}_feeder.urdf"), build_scene_graph=True, load_meshes=False
    )
    links = ("cylinder", "piston", "piston_pin", "arm", "arm_pin", "forearm", "projectile")
    for _ in range(20):
        q = rng.uniform(model.lowerPositionLimit, model.upperPositionLimit)
        robot.update_cfg(
            {joint: q[model.joints[model.getJointId(joint)].idx_q] for joint in PAPER_JOINTS}
        )
        pin.framesForwardKinematics(model, data, q)
        for link in links:
            expected = robot.get_transform(frame_to=link, frame_from="frame")
            np.testing.assert_allclose(
                data.oMf[model.getFrameId(link)].homogeneous, expected, atol=FK_TOLERANCE
            )


def test_joint_positions_are_the_paper_coordinates(feeder, rng):
    """φ1 is the cylinder axis angle, r2 the distance B–S, φ3 the arm angle, φ4 the swing."""
    model, data = feeder.model, feeder.chain.data
    p = feeder.params
    q_paper = np.array([2.1, 0.3, 0.7, 0.4])
    pin.framesForwardKinematics(model, data, feeder.to_pinocchio(q_paper))
    piston = data.oMf[feeder.frame_id("piston")].translation
    np.testing.assert_allclose(
        piston[:2], 0.3 * np.array([np.cos(2.1), np.sin(2.1)]), atol=FK_TOLERANCE
    )
    arm = data.oMf[feeder.frame_id("arm")]
    np.testing.assert_allclose(arm.rotation[:2, 0], [np.cos(0.7), np.sin(0.7)], atol=FK_TOLERANCE)
    np.testing.assert_allclose(arm.translation, [p.L1, p.L2, 0.0], atol=FK_TOLERANCE)
    forearm = data.oMf[feeder.frame_id("forearm")].rotation
    relative = arm.rotation.T @ forearm
    np.testing.assert_allclose(relative, pin.utils.rotate("y", 0.4), atol=FK_TOLERANCE)
