"""The planar delta robot of the CAD exports (examples/cad/robot_delta), released undriven,
for the tests of forward runs that reach its dead centre: the fixture ``delta`` is in this
folder's conftest.py."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from ...conftest import REPO

DELTA = REPO / "examples" / "cad" / "robot_delta"


def rod3_angle(chain, q: np.ndarray) -> float:
    """The signed angle [rad] between the two links of the delta's third rod (free1_rod3 →
    free2_rod3 → closedloop1_A, the elbow of rod 2), in the plane of motion (y, z): zero at its
    dead centre, where they line up."""
    model, data = chain.model, chain.model.createData()
    pin.forwardKinematics(model, data, q)
    names = ("free1_rod3", "free2_rod3", "closedloop1_A")
    a, b, c = (data.oMi[model.getJointId(name)].translation[1:] for name in names)
    u, w = b - a, c - b
    return math.atan2(u[0] * w[1] - u[1] * w[0], u @ w)
