"""The motion of named frames at every sample at once against Pinocchio, sample by sample."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from feeder.chain import frame_motion
from feeder.device import load_feeder
from feeder.exceptions import InputError

ROUND_OFF = 1e-12
"""[m, m/s, rad/s] Products of a few 3 × 3 factors on lengths of ~1 m and rates of order 1."""

SAMPLES = 20
FRAMES = ("piston_pin", "arm_pin", "projectile")


@pytest.fixture(scope="module")
def chain():
    return load_feeder("projectile").chain


def test_placements_and_velocities_match_pinocchio(chain, rng):
    model, data = chain.model, chain.model.createData()
    q = rng.uniform(-1.0, 1.0, (SAMPLES, model.nq))  # open or closed: the tree's kinematics
    v = rng.uniform(-1.0, 1.0, (SAMPLES, model.nv))
    frames = frame_motion(chain, FRAMES, q, v)
    for name in FRAMES:
        frame = model.getFrameId(name)
        for k in range(SAMPLES):
            pin.forwardKinematics(model, data, q[k], v[k])
            pin.updateFramePlacements(model, data)
            placement = data.oMf[frame]
            velocity = pin.getFrameVelocity(model, data, frame, pin.LOCAL_WORLD_ALIGNED)
            motion = frames[name]
            np.testing.assert_allclose(motion.rotation[k], placement.rotation, atol=ROUND_OFF)
            np.testing.assert_allclose(motion.position[k], placement.translation, atol=ROUND_OFF)
            np.testing.assert_allclose(motion.velocity[k], velocity.linear, atol=ROUND_OFF)
            np.testing.assert_allclose(motion.omega[k], velocity.angular, atol=ROUND_OFF)


def test_without_velocities_the_frames_stand_still(chain, rng):
    q = rng.uniform(-1.0, 1.0, (3, chain.model.nq))
    still = frame_motion(chain, ["projectile"], q)["projectile"]
    moving = frame_motion(chain, ["projectile"], q, np.ones((3, chain.model.nv)))["projectile"]
    assert np.all(still.velocity == 0.0) and np.all(still.omega == 0.0)
    np.testing.assert_array_equal(still.position, moving.position)


def test_bad_frames_and_arrays_are_refused(chain):
    q = np.zeros((2, chain.model.nq))
    with pytest.raises(InputError, match="no frame 'nose'"):
        frame_motion(chain, ["nose"], q)
    with pytest.raises(InputError, match="N samples each"):
        frame_motion(chain, FRAMES, q, np.zeros((3, chain.model.nv)))
    with pytest.raises(InputError, match="must have shape"):
        frame_motion(chain, FRAMES, np.zeros((2, chain.model.nq + 1)))
    with pytest.raises(InputError, match="finite|NaN"):
        frame_motion(chain, FRAMES, np.full((2, chain.model.nq), np.nan))


STEP = 1e-4
"""[s] Time step of the central differences of a point's motion: truncation STEP² / 6 × the
third derivative (~1e-9 for the four-bar's ~0.5 m/s³ jerk at 2 rad/s), and the tracking's
1e-13 residual over 2 STEP (~5e-10): both below :data:`DIFFERENCE`."""

DIFFERENCE = 1e-8
"""[m/s, m/s²] Agreement of a point's velocity and acceleration with central differences
(1e-7 of the coupler point's 0.07 m/s²)."""


def test_a_point_s_velocity_and_acceleration_are_its_position_s_derivatives():
    """A point fixed on the four-bar's coupler at an offset (and the rocker tip's frame origin)
    along a tracked crank motion x(t) = 0.3 + 0.5 sin 2t: their velocity and acceleration are
    the central differences of their position and of their velocity."""
    from feeder.chain.assembly.partition import Partition
    from feeder.chain.assembly.tracking import track
    from feeder.chain.kinematics.frames import point_motion
    from feeder.chain.model.points import Point
    from feeder.study.analyze import mount_mechanism

    from ...conftest import REPO

    spec, chain, _, _, q0 = mount_mechanism(REPO / "examples/four_bar/closures.toml", None, None)
    t = np.arange(0.0, 0.5, STEP)
    x = 0.3 + 0.5 * np.sin(2 * t)
    dx, ddx = np.cos(2 * t), -2.0 * np.sin(2 * t)
    motion = track(Partition(chain, spec.independent), q0, x[:, None], dx[:, None], ddx[:, None])
    points = (Point("c", "coupler", (0.05, 0.01, 0.0), body=True), Point("r", "rocker_tip"))
    found = point_motion(chain, points, motion.q, motion.v, motion.a)
    for point in found.values():
        rate = (point.position[2:] - point.position[:-2]) / (2 * STEP)
        change = (point.velocity[2:] - point.velocity[:-2]) / (2 * STEP)
        np.testing.assert_allclose(point.velocity[1:-1], rate, rtol=0.0, atol=DIFFERENCE)
        np.testing.assert_allclose(point.acceleration[1:-1], change, rtol=0.0, atol=DIFFERENCE)
        assert np.abs(point.acceleration).max() > 0.02  # it does accelerate (0.07 m/s²)
    tip = frame_motion(chain, ["rocker_tip"], motion.q, motion.v)["rocker_tip"]
    np.testing.assert_allclose(found["r"].position, tip.position, atol=ROUND_OFF)
    np.testing.assert_allclose(found["r"].velocity, tip.velocity, atol=ROUND_OFF)
