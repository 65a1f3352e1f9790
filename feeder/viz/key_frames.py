"""An animation's key frames set a whole track at a time: MeshCat's
``animation.at_frame(...)[node].set_transform(matrix)`` converts one rotation at a time (a 4 × 4
``eigh`` each, thousands per page) and inserts each key by bisection; here every rotation of a
node is converted in one stacked call, with MeshCat's own formula and ordering, so the page's
bytes are those MeshCat would write."""

from __future__ import annotations

from collections.abc import Sequence

import meshcat
import meshcat.animation
import numpy as np


def js_quaternions(placements: np.ndarray) -> np.ndarray:
    """The rotations of the transforms ``placements`` (K, 4, 4) as three.js quaternions
    [x, y, z, w] (K, 4): :func:`meshcat.transformations.quaternion_from_matrix` (the
    eigenvector of the largest eigenvalue of the symmetric 4 × 4 matrix of Bar-Itzhack, w ≥ 0)
    for all K in one ``eigh``."""
    m = placements[:, :3, :3]
    k = np.zeros((len(m), 4, 4))
    k[:, 0, 0] = m[:, 0, 0] - m[:, 1, 1] - m[:, 2, 2]
    k[:, 1, 0] = m[:, 0, 1] + m[:, 1, 0]
    k[:, 1, 1] = m[:, 1, 1] - m[:, 0, 0] - m[:, 2, 2]
    k[:, 2, 0] = m[:, 0, 2] + m[:, 2, 0]
    k[:, 2, 1] = m[:, 1, 2] + m[:, 2, 1]
    k[:, 2, 2] = m[:, 2, 2] - m[:, 0, 0] - m[:, 1, 1]
    k[:, 3, 0] = m[:, 2, 1] - m[:, 1, 2]
    k[:, 3, 1] = m[:, 0, 2] - m[:, 2, 0]
    k[:, 3, 2] = m[:, 1, 0] - m[:, 0, 1]
    k[:, 3, 3] = m[:, 0, 0] + m[:, 1, 1] + m[:, 2, 2]
    k /= 3.0
    values, vectors = np.linalg.eigh(k)
    largest = np.argmax(values, axis=1)
    xyzw = vectors[np.arange(len(m)), :, largest]  # the eigenvector: x, y, z, w
    return np.where(xyzw[:, 3:] < 0.0, -xyzw, xyzw)


def _clip(
    animation: meshcat.animation.Animation, vis: meshcat.Visualizer
) -> meshcat.animation.AnimationClip:
    """The clip of node ``vis`` (created, as MeshCat does, on first use)."""
    if vis.path not in animation.clips:
        fps = animation.default_framerate
        animation.clips[vis.path] = meshcat.animation.AnimationClip(fps=fps)
    return animation.clips[vis.path]


def key_transforms(
    animation: meshcat.animation.Animation,
    vis: meshcat.Visualizer,
    frames: Sequence[float],
    placements: np.ndarray,
) -> None:
    """Node ``vis`` placed at ``placements`` (K, 4, 4) at the animation's ``frames`` (K,,
    increasing): its position and quaternion tracks."""
    clip = _clip(animation, vis)
    for name, jstype, values in (
        ("position", "vector3", placements[:, :3, 3]),
        ("quaternion", "quaternion", js_quaternions(placements)),
    ):
        clip.tracks[name] = meshcat.animation.AnimationTrack(
            name, jstype, list(frames), values.tolist()
        )


def key_property(
    animation: meshcat.animation.Animation,
    vis: meshcat.Visualizer,
    frames: Sequence[float],
    name: str,
    jstype: str,
    values: np.ndarray,
) -> None:
    """Node ``vis``'s property ``name`` (a three.js ``jstype``) at ``values`` (K, …) at the
    animation's ``frames`` (K,, increasing)."""
    clip = _clip(animation, vis)
    clip.tracks[name] = meshcat.animation.AnimationTrack(
        name, jstype, list(frames), values.tolist()
    )
