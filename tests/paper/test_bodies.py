"""The bodies of the hand-derived model (feeder.paper.bodies) against Pinocchio's forward
kinematics and finite differences, on random assembled states of both devices."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from feeder.paper import bodies

from . import cases

POSITION_ATOL = 1e-14
"""CG positions [m] of size < 1 m, composed from the same rotations and offsets in another order
by Pinocchio: a few ε · 1 m (measured ≲ 3e-16 m)."""
UNIT_ATOL = 1e-15
"""Rotation matrices and rotational Jacobians: entries are sines and cosines (|x| ≤ 1) of the
same angles, so agreement to a few ε."""
SAMPLES = 20
"""States of the per-sample Pinocchio loops (each a Python call per state)."""


def test_positions_match_pinocchio(device, reference, states):
    q = states.q[:SAMPLES]
    positions = bodies.body_positions(device.params, q)
    empty, model = reference.models[0], device.model
    data = model.createData()
    names = ("cylinder_joint", "piston_joint", "arm_joint", "forearm_joint")
    for i in range(q.shape[0]):
        pin.framesForwardKinematics(model, data, device.to_pinocchio(q[i]))
        expected = [
            data.oMi[model.getJointId(n)].act(empty.inertias[model.getJointId(n)].lever)
            for n in names
        ]
        expected.append(data.oMf[model.getFrameId("projectile")].translation)
        np.testing.assert_allclose(positions[i], np.array(expected), rtol=0, atol=POSITION_ATOL)


def test_translational_jacobians_are_position_derivatives(device, states):
    q = states.q[:SAMPLES]
    cases.assert_derivative(
        bodies.translational_jacobians(device.params, q),
        lambda x: bodies.body_positions(device.params, x),
        q,
    )


def test_rotational_jacobians_match_pinocchio(device, states):
    q = states.q[:SAMPLES]
    jac = bodies.rotational_jacobians(device.params, q)
    rotations = bodies.body_rotations(device.params, q)
    model, data = device.model, device.model.createData()
    joints = ("cylinder_joint", "piston_joint", "arm_joint", "forearm_joint", "forearm_joint")
    for i in range(q.shape[0]):
        qp = device.to_pinocchio(q[i])
        pin.computeJointJacobians(model, data, qp)
        for body, name in enumerate(joints):
            j = model.getJointId(name)
            expected = pin.getJointJacobian(model, data, j, pin.LOCAL_WORLD_ALIGNED)[3:]
            np.testing.assert_allclose(
                jac[i, body], device.to_paper(expected), rtol=0, atol=UNIT_ATOL
            )
            np.testing.assert_allclose(
                rotations[i, body], data.oMi[j].rotation, rtol=0, atol=UNIT_ATOL
            )
