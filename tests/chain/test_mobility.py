"""Assembly that works and says why when it cannot: mobility reports, branches, continuation,
singular poses, random guesses, angle ranges."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder.chain import Closure, load_closed_chain
from feeder.chain.assembly.partition import POSITION_TOLERANCE, Partition
from feeder.chain.assembly.tracking import track
from feeder.chain.mobility import mobility
from feeder.exceptions import SingularPoseError

from ..conftest import REPO

A, B, C, D = 0.040, 0.120, 0.080, 0.100

WELL_CONDITIONED = 10.0
"""Velocity gain of the crank-driven crank-rocker anywhere on its turn: the rocker and coupler
move at most ~2 times the crank's speed (1.2–1.95 measured); far below MAX_GAIN (1000)."""


@pytest.fixture(scope="module")
def four_bar():
    return load_closed_chain(
        REPO / "examples" / "four_bar" / "four_bar.urdf",
        [Closure("coupler_tip", "rocker_tip", "revolute")],
    )


def test_planar_four_bar_mobility(four_bar):
    q = Partition(four_bar, ["crank_joint"]).assemble(np.array([0.7, -0.35, 1.0]))
    report = mobility(four_bar, q, ["crank_joint"])
    assert (report.dof, report.constraints, report.kutzbach) == (3, 5, -2)  # spatial count
    assert (report.rank, report.mobility) == (2, 1)  # a planar loop: 2 independent rows
    assert {row.split(":")[1] for row in report.indeterminate_rows} == {"fz", "m1", "m2"}
    assert report.admissible == (("crank_joint",), ("coupler_joint",), ("rocker_joint",))
    assert 0.0 < report.gain < WELL_CONDITIONED
    assert "actual mobility 3 − 2 = 1" in report.text()


def test_random_guesses_all_assemble_on_both_branches(four_bar, rng):
    """The issue's test: random guesses (here 200 in ±10 rad) all converge (restarts from seeded
    random guesses leave Newton's local minima) and land on both branches."""
    partition = Partition(four_bar, ["crank_joint"])
    branches = set()
    for _ in range(200):
        guess = np.array([math.radians(40.0), *rng.uniform(-10.0, 10.0, 2)])
        q = partition.assemble(guess)
        assert np.linalg.norm(four_bar.residual(q)) <= POSITION_TOLERANCE
        assert q[0] == guess[0]  # the independent coordinate is kept
        branches.add(bool(math.remainder(q[2], 2 * math.pi) > 0))  # rocker up: open branch
    assert branches == {True, False}


def test_a_branch_condition_picks_the_branch(four_bar):
    partition = Partition(four_bar, ["crank_joint"])
    guess = np.array([math.radians(40.0), -0.35, 1.0])  # near the open branch
    open_branch = partition.assemble(guess)
    crossed = partition.assemble(guess, branch=lambda q: math.remainder(q[2], 2 * math.pi) < 0)
    assert (
        math.remainder(crossed[2], 2 * math.pi) < 0 < math.remainder(open_branch[2], 2 * math.pi)
    )
    np.testing.assert_allclose(four_bar.residual(crossed), 0.0, atol=POSITION_TOLERANCE)


def test_continuation_keeps_the_branch_over_two_turns(four_bar):
    partition = Partition(four_bar, ["crank_joint"])
    x = -2.0 * math.pi + np.linspace(0.0, 4.0 * math.pi, 401)[:, None]  # within the ±4π stops
    q0 = partition.assemble(np.array([x[0, 0], -0.35, 1.0]))
    motion = track(partition, q0, x)
    q, gain = motion.q, motion.gain
    rocker = np.array([math.remainder(value, 2 * math.pi) for value in q[:, 2]])
    assert np.all(rocker > 0)  # never jumped to the crossed branch (rocker below the ground)
    turn = q[400, 1:] - q[200, 1:]  # one crank turn apart: the same pose, angles up to 2π k
    np.testing.assert_allclose(np.remainder(turn + 1.0, 2 * math.pi) - 1.0, 0.0, atol=1e-9)
    assert np.all(np.isfinite(gain)) and gain.max() < WELL_CONDITIONED


def test_dead_centre_is_refused_for_any_driving_joint(four_bar):
    """Driven by the rocker, the crank-rocker has dead centres where crank and coupler line up
    (θ3 = θ2 or θ2 + π): there the crank's speed per unit rocker speed is unbounded."""
    # Extended dead centre: crank and coupler in line, A-B = a + b from the crank pivot.
    e = A + B
    theta2 = math.acos((e**2 + D**2 - C**2) / (2 * e * D))  # B above the ground line
    bx, by = e * math.cos(theta2), e * math.sin(theta2)
    theta4 = math.atan2(by, bx - D)
    rocker = Partition(four_bar, ["rocker_joint"])
    for inside in (0.0, 1e-8):  # at the dead centre, and 1e-8 rad before it
        with pytest.raises(SingularPoseError, match="singular pose"):
            rocker.assemble(np.array([theta2 - 0.01, 0.01, theta4 + inside]))
    q = rocker.assemble(np.array([theta2 - 0.01, 0.01, theta4 + 0.01]))  # 0.01 rad before
    assert 1.0 < rocker.gain(q) < rocker.max_gain
    crank = Partition(four_bar, ["crank_joint"])  # the same pose is harmless from the crank
    q = crank.assemble(np.array([theta2, 0.0, theta4]))
    assert crank.gain(q) < WELL_CONDITIONED


def test_unset_limits_do_not_limit(fourbar_urdf):
    """example-robot-data's double pendulum has revolute limits of [0, 0] ("not set")."""
    from lxml import etree

    robot = etree.parse(str(fourbar_urdf)).getroot()
    for limit in robot.iter("limit"):
        limit.set("lower", "0")
        limit.set("upper", "0")
    path = fourbar_urdf.parent / "unset_limits.urdf"
    path.write_bytes(etree.tostring(robot))
    chain = load_closed_chain(path, [("rocker_tip", "ground_pin")])
    q = Partition(chain, ["joint1"]).assemble(np.array([0.3, 1.0, 1.0]))
    assert np.linalg.norm(chain.residual(q)) <= POSITION_TOLERANCE
    assert np.all(np.abs(q[1:]) <= math.pi)  # dependent angles wrapped into (−π, π]
