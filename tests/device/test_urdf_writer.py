"""Generated URDF: shipped files equal the generator, names, and two parsers agree."""

from __future__ import annotations

import dataclasses

import numpy as np
import pinocchio as pin
import pytest
import yourdfpy

from feeder.device.builtin import DEVICES, PROJECTILE_FEEDER
from feeder.device.feeder import CLOSURE, PAPER_JOINTS, load_feeder
from feeder.device.urdf_writer import urdf_string, write_urdfs
from feeder.exceptions import InputError, UnreachablePoseError

from ..conftest import REPO

FK_TOLERANCE = 1e-12
"""[m] and [-]: both libraries compose the same few transforms in double precision."""


@pytest.mark.parametrize("name", sorted(DEVICES))
def test_shipped_urdf_equals_generator(name):
    """The files in urdf/ are what the generator writes today, byte for byte."""
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
    device = load_feeder(name)
    model, data = device.model, device.chain.data
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


def test_write_urdfs_writes_every_device(tmp_path):
    """One file per built-in device, equal to the generator, in a folder it creates."""
    folder = tmp_path / "new" / "urdf"
    paths = write_urdfs(folder)
    assert sorted(path.name for path in paths) == sorted(f"{n}_feeder.urdf" for n in DEVICES)
    for name, params in DEVICES.items():
        assert (folder / f"{name}_feeder.urdf").read_text(encoding="utf-8") == urdf_string(params)
    leftovers = {p.name for p in folder.iterdir()} - {p.name for p in paths}
    assert not leftovers  # no temporary file of the atomic write is left behind


def test_write_urdfs_into_a_file_is_refused(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder", encoding="utf-8")
    with pytest.raises(InputError, match="cannot write the URDF files"):
        write_urdfs(blocker)


def test_write_urdfs_replaces_only_urdf_files_it_wrote(tmp_path):
    """A user's own URDF under a device's file name is refused before anything is written."""
    write_urdfs(tmp_path)
    write_urdfs(tmp_path)  # its own files: replaced
    mine = tmp_path / "charge_feeder.urdf"
    mine.write_text('<robot name="mine"/>\n', encoding="utf-8")
    (tmp_path / "projectile_feeder.urdf").unlink()
    with pytest.raises(InputError, match="is not a URDF file that feeder urdf wrote"):
        write_urdfs(tmp_path)
    assert [p.name for p in tmp_path.iterdir()] == ["charge_feeder.urdf"]
    assert mine.read_text(encoding="utf-8") == '<robot name="mine"/>\n'


def test_generator_checks_the_whole_device_first():
    """No URDF for a parameter set whose arm travel cannot be assembled (check_device)."""
    with pytest.raises(UnreachablePoseError, match="outside the stroke"):
        urdf_string(dataclasses.replace(PROJECTILE_FEEDER, r2_max=0.4))
