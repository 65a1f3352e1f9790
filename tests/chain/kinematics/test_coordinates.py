"""Every joint kind's named coordinates (feeder.chain.kinematics.coordinates) against Pinocchio:
the shown values are the joint's placement read independently (its translation, its rotation's
log, its angle), they give q back, the units say which velocity components are lengths, and a
pose reads as one line of labelled values."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from feeder.chain.kinematics.coordinates import (
    COORDINATES,
    coordinates,
    length_rates,
    pose_text,
    pose_values,
)

ROUND_OFF = 1e-12
"""[m, rad] Pinocchio's placement and our shown coordinates from the same q: a few ulps."""

JOINTS = {
    "revolute": pin.JointModelRZ(),
    "continuous": pin.JointModelRUBZ(),
    "prismatic": pin.JointModelPX(),
    "universal": pin.JointModelUniversal(np.array([0.0, 0.0, 1.0]), np.array([0.0, 1.0, 0.0])),
    "spherical_zyx": pin.JointModelSphericalZYX(),
    "translation": pin.JointModelTranslation(),
    "spherical": pin.JointModelSpherical(),
    "planar": pin.JointModelPlanar(),
    "free_flyer": pin.JointModelFreeFlyer(),
}


@pytest.fixture(scope="module")
def model() -> pin.Model:
    """One joint of every kind, each on the world, named after its kind."""
    model = pin.Model()
    for kind, joint in JOINTS.items():
        model.addJoint(0, joint, pin.SE3.Identity(), kind)
    return model


def test_every_kind_is_covered():
    assert set(COORDINATES) == set(JOINTS)


def _random_pose(model: pin.Model, rng: np.random.Generator) -> np.ndarray:
    return pin.integrate(model, pin.neutral(model), rng.uniform(-2.0, 2.0, model.nv))


def _placements(model: pin.Model, q: np.ndarray) -> dict[str, pin.SE3]:
    data = model.createData()
    pin.forwardKinematics(model, data, q)
    return {model.names[j]: data.oMi[j] for j in range(1, model.njoints)}


def test_shown_coordinates_are_the_placements(model, rng):
    q = _random_pose(model, rng)
    placed = _placements(model, q)
    shown = {(name, suffix): value for name, suffix, value, _ in pose_values(model, q)}
    for kind in ("translation", "free_flyer", "planar"):
        for k, axis in enumerate("xy" if kind == "planar" else "xyz"):
            assert abs(shown[kind, axis] - placed[kind].translation[k]) <= ROUND_OFF
    for kind in ("spherical", "free_flyer"):
        rotation = pin.log3(placed[kind].rotation)
        for k, axis in enumerate("xyz"):
            assert abs(shown[kind, f"r{axis}"] - rotation[k]) <= ROUND_OFF
    planar_angle = pin.log3(placed["planar"].rotation)[2]
    assert abs(shown["planar", "theta"] - planar_angle) <= ROUND_OFF
    assert abs(shown["continuous", ""] - pin.log3(placed["continuous"].rotation)[2]) <= ROUND_OFF
    assert abs(shown["prismatic", ""] - placed["prismatic"].translation[0]) <= ROUND_OFF


def test_shown_coordinates_give_q_back(model, rng):
    q = np.array([_random_pose(model, rng) for _ in range(5)])
    for j in range(1, model.njoints):
        joint, table = model.joints[j], coordinates(model, j)
        part = q[:, joint.idx_q : joint.idx_q + joint.nq]
        shown = table.show(part)
        assert shown.shape == (5, len(table.shown)) and joint.nv == len(table.rates)
        np.testing.assert_allclose(table.store(shown), part, rtol=0.0, atol=ROUND_OFF)


def test_lengths_are_the_linear_velocity_components(model):
    """A unit velocity component moves the joint's origin (a length's rate) or turns its frame
    (an angle's): read from Pinocchio's joint Jacobian, independently of the table."""
    data = model.createData()
    q = pin.neutral(model)
    pin.computeJointJacobians(model, data, q)
    expected = np.zeros(model.nv, dtype=bool)
    for j in range(1, model.njoints):
        jac = pin.getJointJacobian(model, data, j, pin.LOCAL)
        joint = model.joints[j]
        for k in range(joint.idx_v, joint.idx_v + joint.nv):
            expected[k] = np.abs(jac[3:, k]).max() == 0.0  # no turn: a slide
    np.testing.assert_array_equal(length_rates(model), expected)


def test_a_pose_reads_as_labelled_values_with_units(model):
    q = pin.neutral(model)
    text = pose_text(model, q, [model.getJointId("free_flyer"), model.getJointId("prismatic")])
    assert text == (
        "prismatic = 0 m, free_flyer x = 0 m, free_flyer y = 0 m, free_flyer z = 0 m, "
        "free_flyer rx = 0 rad, free_flyer ry = 0 rad, free_flyer rz = 0 rad, free_flyer qx = 0, "
        "free_flyer qy = 0, free_flyer qz = 0, free_flyer qw = 1"
    )
