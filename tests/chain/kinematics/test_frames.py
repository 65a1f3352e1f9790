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
