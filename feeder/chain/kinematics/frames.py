"""The motion of named frames and of points fixed on bodies at every sample at once: where a
payload, a tool, a cut frame or a mechanism file's ``[[point]]`` is and how fast it moves, from
the tree's batched forward recursions (:mod:`.tree`, no per-sample Pinocchio call)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ...exceptions import InputError
from ...validation import check_samples
from ..model.closure import ClosedChain
from ..model.points import Point
from .tree import frame_acceleration, frame_placements, frame_velocity, tree_motion


@dataclass(frozen=True)
class FrameMotion:
    """A frame's placement and motion at N samples, world axes.

    Attributes:
        rotation: The frame's axes in the world ones, (N, 3, 3): column k is its k-th axis.
        position: Its origin [m], (N, 3).
        velocity: The velocity of its origin [m/s], (N, 3) (zero without velocities).
        omega: Its angular velocity [rad/s], (N, 3).
    """

    rotation: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    omega: np.ndarray


def frame_motion(
    chain: ClosedChain, frames: Sequence[str], q: np.ndarray, v: np.ndarray | None = None
) -> dict[str, FrameMotion]:
    """The placement and motion of the named frames of the chain's tree, frame name →
    :class:`FrameMotion`.

    Args:
        chain: The chain whose model's frames are named.
        frames: Frame names (links, joints or fixed frames of the model).
        q: Configurations (N, nq). Closed or not: the tree's kinematics, the loops not checked.
        v: Velocities (N, nv), or None for the placements alone (zero velocities).

    Raises:
        InputError: An unknown frame, NaN/inf or misshaped q or v.
    """
    model = chain.model
    ids = {name: chain.frame_id(name) for name in frames}
    q = check_samples("q", q, model.nq)
    if v is not None:
        v = check_samples("v", v, model.nv)
        if v.shape[0] != q.shape[0]:
            raise InputError(f"q and v must have N samples each, got {q.shape} and {v.shape}")
    motion = tree_motion(model, q, v)
    out = {}
    for name, frame in ids.items():
        rotation, position = frame_placements(model, motion, frame)
        velocity = frame_velocity(model, motion, frame, position)
        omega = motion.omega[model.frames[frame].parentJoint]
        out[name] = FrameMotion(rotation, position, velocity, omega)
    return out


@dataclass(frozen=True)
class PointMotion:
    """A point's motion at N samples, world axes (the base's on a moving base).

    Attributes:
        position: [m], (N, 3). velocity: [m/s], (N, 3). acceleration: [m/s²], (N, 3).
    """

    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray


def point_motion(
    chain: ClosedChain, points: Sequence[Point], q: np.ndarray, v: np.ndarray, a: np.ndarray
) -> dict[str, PointMotion]:
    """The motion of each point (:class:`~feeder.chain.model.points.Point`: its frame's origin
    plus its offset turned with the frame) along the motion q (N, nq), v, a (N, nv) (trusted:
    a checked motion), point name → :class:`PointMotion`: p = o_f + R_f d,
    v = v_j + ω_j × (p − o_j), a = a_j + α_j × (p − o_j) + ω_j × (ω_j × (p − o_j)), j the joint
    that moves the frame's body."""
    model = chain.model
    motion = tree_motion(model, q, v, a)
    out = {}
    for point in points:
        frame = chain.frame_id(point.frame)
        rotation, origin = frame_placements(model, motion, frame)
        position = origin + rotation @ np.asarray(point.offset, dtype=float)
        out[point.name] = PointMotion(
            position,
            frame_velocity(model, motion, frame, position),
            frame_acceleration(model, motion, frame, position),
        )
    return out
