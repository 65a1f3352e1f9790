"""Fixtures of the forward-run tests."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from feeder.chain import ChainDynamics, Closure, load_closed_chain
from feeder.chain.assembly.partition import Partition

from ...conftest import REPO
from .delta import DELTA


@pytest.fixture(scope="module")
def delta():
    """The planar delta robot of the CAD exports, at rest at its assembled pose, undriven:
    its dynamics and that pose."""
    from feeder.study.analyze import mount_mechanism

    spec, chain, _, _, q0 = mount_mechanism(DELTA / "robot.yaml", DELTA / "robot.urdf", None)
    return ChainDynamics(chain, spec.actuated), q0


@pytest.fixture(scope="module")
def four_bar():
    """examples/four_bar closed by a revolute cut, gravity along −y: (chain, its partition with
    the crank independent, an assembled q at 40°)."""
    chain = load_closed_chain(
        REPO / "examples" / "four_bar" / "four_bar.urdf",
        [Closure("coupler_tip", "rocker_tip", "revolute")],
    )
    chain.model.gravity = pin.Motion(np.array([0.0, -9.81, 0.0]), np.zeros(3))
    partition = Partition(chain, ["crank_joint"])
    q0 = partition.assemble(np.array([math.radians(40.0), -0.35, 1.0]))
    return chain, partition, q0
