"""The generic assembly refuses partitions whose dependent coordinates the closure does not
determine (the closed form and the Newton assembly agree: tests/device/test_loop.py)."""

from __future__ import annotations

import numpy as np
import pytest

from feeder.chain import Closure, load_closed_chain
from feeder.chain.assembly.partition import Partition
from feeder.chain.assembly.tracking import track
from feeder.device.feeder import INDEPENDENT_JOINTS
from feeder.exceptions import InputError, SingularPoseError

from ...conftest import REPO


@pytest.fixture
def closed_pose(feeder):
    """A closed configuration of the feeder (Pinocchio order), φ3 = 0.3 rad, φ4 = 0.2 rad."""
    return Partition(feeder.chain, INDEPENDENT_JOINTS).assemble(
        feeder.to_pinocchio([2.4, 0.35, 0.3, 0.2])
    )


def test_too_few_independent_joints(feeder, closed_pose):
    """With φ3 alone given, φ4 is free: no minimum-norm answer, an error."""
    partition = Partition(feeder.chain, ["arm_joint"])
    with pytest.raises(SingularPoseError, match="does not determine the 3 dependent .* rank 2"):
        partition.assemble(closed_pose)
    with pytest.raises(SingularPoseError, match="too few independent joints"):
        partition.velocity(closed_pose, np.ones(1))


def test_too_many_independent_joints(feeder, closed_pose):
    """With r2 given as well, φ1 alone cannot keep the pin closed: the device has 2 degrees of
    freedom, 3 joints cannot be independent."""
    partition = Partition(feeder.chain, [*INDEPENDENT_JOINTS, "piston_joint"])
    with pytest.raises(InputError, match="has 2 degrees of freedom; 3 independent joints given"):
        partition.velocity(closed_pose, np.ones(3))


def test_two_independent_joints_on_a_four_bar_are_one_too_many():
    chain = load_closed_chain(
        REPO / "examples" / "four_bar" / "four_bar.urdf",
        [Closure("coupler_tip", "rocker_tip", "revolute")],
    )
    closed = Partition(chain, ["crank_joint"]).mount(np.array([0.7, 0.0, 1.5]))
    partition = Partition(chain, ["crank_joint", "rocker_joint"])
    with pytest.raises(
        InputError,
        match=r"^this mechanism has 1 degree of freedom; 2 independent joints given "
        r"\(crank_joint, rocker_joint\): make 1 of them independent",
    ):
        track(partition, closed, np.array([[0.7, 1.5], [0.8, 1.5]]))


def test_fourbar_without_independent_joints(fourbar_urdf):
    """A four-bar has one degree of freedom: with no joint given, its 3 coordinates are free."""
    chain = load_closed_chain(fourbar_urdf, [("rocker_tip", "ground_pin")])
    closed = Partition(chain, ["joint1"]).assemble(np.array([0.3, 1.0, 1.0]))
    with pytest.raises(SingularPoseError, match="3 dependent coordinates .* rank 2"):
        Partition(chain, []).velocity(closed, np.zeros(0))
