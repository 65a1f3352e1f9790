"""The animation's key frames set a track at a time (feeder.viz.key_frames): the same tracks,
values and order as MeshCat's frame-by-frame ``set_transform``, and quaternions that are the
rotations' (checked against Pinocchio's conversion, a second library)."""

from __future__ import annotations

import meshcat
import meshcat.animation
import numpy as np
import pinocchio as pin

from feeder.viz._offline import OfflineWindow
from feeder.viz.key_frames import js_quaternions, key_property, key_transforms


def _placements(count: int) -> np.ndarray:
    """Random transforms (count, 4, 4), with the rotations where the formula changes branch:
    the identity and half turns about each axis (w = 0)."""
    rng = np.random.default_rng(29)
    rotations = [pin.exp3(rng.normal(size=3) * 2.0) for _ in range(count)]
    rotations += [np.eye(3), np.diag([1.0, -1.0, -1.0]), np.diag([-1.0, 1.0, -1.0])]
    rotations += [np.diag([-1.0, -1.0, 1.0])]
    out = np.tile(np.eye(4), (len(rotations), 1, 1))
    out[:, :3, :3] = rotations
    out[:, :3, 3] = rng.normal(size=(len(rotations), 3))
    return out


def test_quaternions_are_meshcats_and_the_rotations():
    placements = _placements(200)
    ours = js_quaternions(placements)
    # MeshCat's own conversion, one matrix at a time: the same numbers, bit for bit (the same
    # eigh on the same matrix), so that a page's bytes do not change.
    theirs = np.array([meshcat.animation.js_quaternion(m) for m in placements])
    np.testing.assert_array_equal(ours, theirs)
    # Pinocchio's conversion (Shepperd's method, x, y, z, w): the same rotation, up to the sign
    # of the quaternion; an eigenvector is accurate to a few ulps of its unit norm.
    for quaternion, placement in zip(ours, placements, strict=True):
        expected = pin.Quaternion(placement[:3, :3]).coeffs()
        sign = 1.0 if quaternion @ expected >= 0.0 else -1.0
        np.testing.assert_allclose(quaternion, sign * expected, rtol=0.0, atol=1e-14)
    assert np.all(ours[:, 3] >= 0.0)


def test_tracks_are_those_of_meshcats_key_frames():
    placements = _placements(20)
    scales = np.random.default_rng(3).uniform(0.5, 2.0, size=(len(placements), 3))
    frames = np.cumsum(np.full(len(placements), 1.7)).tolist()
    vis = meshcat.Visualizer(window=OfflineWindow())
    theirs = meshcat.animation.Animation(default_framerate=30)
    for k, frame_time in enumerate(frames):
        with theirs.at_frame(vis, frame_time) as frame:
            frame["a"].set_transform(placements[k])
            frame["b/c"].set_transform(placements[-1 - k])
            frame["b/c"].set_property("scale", "vector3", scales[k].tolist())
    ours = meshcat.animation.Animation(default_framerate=30)
    key_transforms(ours, vis["a"], frames, placements)
    key_transforms(ours, vis["b/c"], frames, placements[::-1])
    key_property(ours, vis["b/c"], frames, "scale", "vector3", scales)
    assert ours.lower() == theirs.lower()
