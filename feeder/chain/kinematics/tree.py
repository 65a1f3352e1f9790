"""Kinematics of a tree at every sample at once (numpy, world frame): the forward recursions.

One Pinocchio call per sample costs a Python round trip each; for the thousands of samples of a
motion the same recursions run here over the joint tree once, on arrays of all samples, for every
joint type of :mod:`~feeder.chain.kinematics.joints`. For a joint j with parent p, placement
(R₀, t₀) in p's frame ("before": R_b = R_p R₀, o_b = o_p + R_p t₀) and the child's motion
relative to "before" (R_rel, p_rel, w_rel, v_rel, α_rel, a_rel; columns A, B):

* placement: R_j = R_b R_rel, o_j = o_b + R_b p_rel;
* angular velocity and acceleration: ω_j = ω_p + R_b w_rel,
  α_j = α_p + R_b α_rel + ω_p × R_b w_rel;
* origin velocity and acceleration, r = o_j − o_p: v_j = v_p + ω_p × r + R_b v_rel,
  a_j = a_p + α_p × r + ω_p × (ω_p × r) + 2 ω_p × R_b v_rel + R_b a_rel;
* the joint's world columns at its origin: linear R_b B, angular R_b A (its motion subspace).

The backward pass that turns this motion into forces (Newton–Euler) is in
:mod:`feeder.chain.dynamics.newton_euler`; tests/chain/kinematics/test_tree.py checks both passes
against Pinocchio.

On a moving base (:func:`on_base`) the same recursions hold in the base's moving axes: the base's
angular velocity Ω, angular acceleration Ω̇ and origin acceleration a₀ seed joint 0, and each
body's motion relative to the base composes with them (vectors in the moving axes):

    ω = Ω + ω_r,   ω̇ = Ω̇ + ω̇_r + Ω × ω_r,   a = a₀ + Ω̇ × o + Ω × (Ω × o) + 2 Ω × v_r + a_r,

with gravity turned into the moving axes.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np
import pinocchio as pin

from ..model.base import BaseState
from .joints import relative_motion
from .layout import SINGLE_AXIS, tree_layout

MIN_REACH = 1e-3
"""Smallest mechanism size [m] :func:`reach` gives (a mechanism whose frames all sit at the world
origin has none)."""


@dataclass(frozen=True)
class TreeMotion:
    """World placements and motion of every joint frame of a tree, N samples; the placements
    and rates indexed by joint id first (0 is the world, at rest: ``motion.origin[j]`` is joint
    j's (N, 3), :data:`JOINT_FIRST`), the columns by sample first.

    Attributes:
        rotation: R_j, (njoints, N, 3, 3). origin: o_j [m], (njoints, N, 3).
        omega, alpha: Angular velocity [rad/s] and acceleration [rad/s²], (njoints, N, 3).
        velocity, acceleration: Velocity [m/s] and acceleration [m/s²] of the origin,
            (njoints, N, 3).
        linear_columns, angular_columns: Every joint's world columns at its origin in the order
            of the velocity (module docstring; a joint's are its velocity slice's,
            :attr:`~.layout.TreeLayout.slices`: for a revolute joint, angular is its world axis
            and linear is zero), (N, 3, nv).
        gravity: Gravity [m/s²] in these axes (N, 3), or None: the model's (a base at rest).
    """

    rotation: np.ndarray
    origin: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    linear_columns: np.ndarray
    angular_columns: np.ndarray
    gravity: np.ndarray | None = None

    def at_rest(self, index: np.ndarray) -> TreeMotion:
        """The placements at the samples ``index`` (M,), at rest: rates zero, no columns (what
        a statics pass, :func:`~feeder.chain.dynamics.newton_euler.joint_wrenches` without
        inertia, reads)."""
        zero = np.broadcast_to(0.0, (self.origin.shape[0], index.size, 3))
        empty = np.zeros((index.size, 3, 0))
        return TreeMotion(
            np.take(self.rotation, index, axis=1),  # take: contiguous (an index keeps strides)
            np.take(self.origin, index, axis=1),
            zero,
            zero,
            zero,
            zero,
            empty,
            empty,
        )


JOINT_FIRST = ("rotation", "origin", "omega", "alpha", "velocity", "acceleration")
"""The :class:`TreeMotion` fields indexed by joint id first, their samples on axis 1."""


def cross(u: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Row-wise cross product of two (..., 3) arrays, broadcast (numpy's ``cross`` is several
    times slower on many short rows)."""
    out = np.empty(np.broadcast(u, w).shape)  # (np.broadcast_shapes costs µs in Python)
    out[..., 0] = u[..., 1] * w[..., 2] - u[..., 2] * w[..., 1]
    out[..., 1] = u[..., 2] * w[..., 0] - u[..., 0] * w[..., 2]
    out[..., 2] = u[..., 0] * w[..., 1] - u[..., 1] * w[..., 0]
    return out


def apply_each(stacks: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """Each stack k of (3, 3)s of ``stacks`` (k, N, 3, 3) times its one 3-vector of ``vectors``
    (k, 3), (k, N, 3): k products (3N × 3)(3) (BLAS; einsum's loop is several times slower)."""
    k = stacks.shape[0]
    return (stacks.reshape(k, -1, 3) @ vectors[:, :, None]).reshape(k, -1, 3)


def turn_each(stacks: np.ndarray, matrices: np.ndarray) -> np.ndarray:
    """Each stack k of (3, 3)s of ``stacks`` (k, N, 3, 3) times its one (3, 3) of ``matrices``
    (k, 3, 3), (k, N, 3, 3): k products (3N × 3)(3 × 3) (BLAS; a stacked product of (3, 3)s is
    several times slower)."""
    k = stacks.shape[0]
    return (stacks.reshape(k, -1, 3) @ matrices).reshape(stacks.shape)


def _turn(stack: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """Each (3, 3) of a stack (N, 3, 3) times its own 3-vector of (N, 3)."""
    return np.einsum("nij,nj->ni", stack, vectors)


def _placed_rotations(
    parents: np.ndarray | None,
    placed: np.ndarray,
    axes: np.ndarray,
    cosine: np.ndarray,
    sine: np.ndarray,
) -> np.ndarray:
    """R_p R₀ R(s, θ) (k, N, 3, 3): joints on parents of rotations R_p (k, N, 3, 3) (None: on
    the world, R_p = I), placed at the rotations ``placed`` R₀ (k, 3, 3), turned by θ about
    their unit ``axes`` s (k, 3), of cosines and sines (k, N) — Rodrigues,
    R_p R₀ + sin θ R_p R₀ S + (1 − cos θ) R_p R₀ S², S the axis' skew matrix (as
    :func:`~.joints.rotation_about` for one axis): three products of each joint's stack with
    one (3, 3) (:func:`turn_each`), not a stacked product of (3, 3)s."""
    x, y, z = axes.T
    skew = np.zeros((axes.shape[0], 3, 3))
    skew[:, 0, 1], skew[:, 0, 2], skew[:, 1, 2] = -z, y, -x
    skew[:, 1, 0], skew[:, 2, 0], skew[:, 2, 1] = z, -y, x
    once = placed @ skew
    fixed = (placed, once, once @ skew)
    if parents is None:
        base, first, second = (matrix[:, None] for matrix in fixed)
    else:
        base, first, second = (turn_each(parents, matrix) for matrix in fixed)
    return base + sine[..., None, None] * first + (1.0 - cosine)[..., None, None] * second


def tree_motion(
    model: pin.Model, q: np.ndarray, v: np.ndarray | None = None, a: np.ndarray | None = None
) -> TreeMotion:
    """The forward recursion of the module docstring for configurations q (N, nq) and, if given,
    velocities v and accelerations a (N, nv) (zero otherwise; with neither, the velocity and
    acceleration recursions are skipped: a position-level pass), one depth of the tree at a
    time (:mod:`.layout`). q, v, a are trusted (checked by the caller); a joint type that is not
    handled raises :class:`~feeder.exceptions.InputError`."""
    layout = tree_layout(model)
    n, count = q.shape[0], model.njoints
    moving = v is not None or a is not None
    v = np.zeros((n, model.nv)) if v is None else v
    a = np.zeros((n, model.nv)) if a is None else a
    rotation = np.empty((count, n, 3, 3))
    rotation[0] = np.eye(3)
    origin = np.zeros((count, n, 3))
    rates = np.zeros((4, count, n, 3)) if moving else np.broadcast_to(0.0, (4, count, n, 3))
    w, dw, vel, acc = rates
    linear, angular = np.zeros((n, 3, model.nv)), np.zeros((n, 3, model.nv))
    placed = model.jointPlacements
    turned = np.array([placement.rotation for placement in placed])
    shifted = np.array([placement.translation for placement in placed])
    for level in layout.levels:
        for group in level:
            j, p = group.joints, group.parents
            if group.kind in SINGLE_AXIS:
                # a group on the world (an N-four-bar's rockers) needs no product with its
                # parents' placements: the world's is the identity, at rest
                root = not p.any()
                axes = np.einsum("kij,kj->ki", turned[j], group.axes)  # in the parents' axes
                if root:
                    e = np.broadcast_to(axes[:, None], (j.size, n, 3))  # world axes (k, N, 3)
                    here = np.broadcast_to(shifted[j][:, None], (j.size, n, 3))
                else:
                    e = apply_each(rotation[p], axes)
                    here = origin[p] + apply_each(rotation[p], shifted[j])
                rate, rate2 = v[:, group.iv].T[..., None], a[:, group.iv].T[..., None]
                if group.kind == "prismatic":
                    here = here + e * q[:, group.iq].T[..., None]
                    rotation[j] = turned[j][:, None] if root else turn_each(rotation[p], turned[j])
                    linear[:, :, group.iv] = np.moveaxis(e, 0, 2)
                    turn = alpha_rel = None
                    slide, a_rel = e * rate, e * rate2
                else:
                    if group.kind == "revolute":
                        angle = q[:, group.iq].T
                        cosine, sine = np.cos(angle), np.sin(angle)
                    else:  # continuous: q = (cos θ, sin θ), taken as a direction
                        cosine, sine = q[:, group.iq].T, q[:, group.iq + 1].T
                        size = np.hypot(cosine, sine)
                        cosine, sine = cosine / size, sine / size
                    parents = None if root else rotation[p]
                    rotation[j] = _placed_rotations(parents, turned[j], group.axes, cosine, sine)
                    angular[:, :, group.iv] = np.moveaxis(e, 0, 2)
                    turn, alpha_rel = e * rate, e * rate2
                    slide = a_rel = None
            else:
                joint, b = model.joints[int(j[0])], (rotation[p] @ turned[j][:, None])[0]
                here = origin[p] + apply_each(rotation[p], shifted[j])
                iq, iv = joint.idx_q, joint.idx_v
                rel = relative_motion(
                    group.kind,
                    group.axes,
                    q[:, iq : iq + joint.nq],
                    v[:, iv : iv + joint.nv],
                    a[:, iv : iv + joint.nv],
                )
                if rel.position.any():
                    here = here + _turn(b, rel.position)
                rotation[j] = b @ rel.rotation
                linear[:, :, iv : iv + joint.nv] = b @ rel.linear
                angular[:, :, iv : iv + joint.nv] = b @ rel.angular
                turn, alpha_rel = _turn(b, rel.omega)[None], _turn(b, rel.alpha)[None]
                slide, a_rel = _turn(b, rel.velocity)[None], _turn(b, rel.acceleration)[None]
            origin[j] = here
            if moving:
                _rates(w, dw, vel, acc, j, p, here - origin[p], turn, alpha_rel, slide, a_rel)
    return TreeMotion(rotation, origin, w, dw, vel, acc, linear, angular)


def _rates(w, dw, vel, acc, j, p, r, turn, alpha_rel, slide, a_rel) -> None:
    """The velocity and acceleration recursion (module docstring) of the joints j (k,) from
    their parents p (k,), r = o_j − o_p (k, N, 3), and their relative terms in world axes
    (k, N, 3) (R_b w_rel, R_b α_rel, R_b v_rel, R_b a_rel; None where zero: a revolute joint's
    slide, a prismatic joint's turn), written into w, dw, vel, acc (njoints, N, 3). Joints on
    the world (parents all 0, at rest: w, dw, vel, acc zero there) take their relative terms
    as they are, the same values without the products with the world's zero rates."""
    if not p.any():
        if turn is not None:
            w[j], dw[j] = turn, alpha_rel
        if slide is not None:
            vel[j], acc[j] = slide, a_rel
        return
    w_p, dw_p = w[p], dw[p]
    spin = cross(w_p, r)
    omega, alpha = w_p, dw_p
    if turn is not None:
        omega = w_p + turn
        alpha = dw_p + alpha_rel + cross(w_p, turn)
    velocity = vel[p] + spin
    acceleration = acc[p] + cross(dw_p, r) + cross(w_p, spin)
    if slide is not None:
        velocity = velocity + slide
        acceleration = acceleration + 2.0 * cross(w_p, slide) + a_rel
    w[j], dw[j], vel[j], acc[j] = omega, alpha, velocity, acceleration


def on_base(motion: TreeMotion, base: BaseState) -> TreeMotion:
    """The absolute motion, in the base's moving axes, of a tree whose motion relative to its
    base is ``motion``, the base moving as ``base`` (module docstring), every joint at once;
    placements and columns are unchanged."""
    spin, turn = base.omega, base.alpha
    o, w_r, v_r = motion.origin, motion.omega, motion.velocity
    around = cross(spin, o)
    return replace(
        motion,
        omega=spin + w_r,
        alpha=turn + motion.alpha + cross(spin, w_r),
        velocity=base.velocity + around + v_r,
        acceleration=base.acceleration
        + cross(turn, o)
        + cross(spin, around)
        + 2.0 * cross(spin, v_r)
        + motion.acceleration,
        gravity=base.gravity,
    )


def frame_placements(
    model: pin.Model, motion: TreeMotion, frame: int | Sequence[int]
) -> tuple[np.ndarray, np.ndarray]:
    """World rotation (N, 3, 3) and origin (N, 3) of a frame at every sample; for several
    frames (ids (F,)), (F, N, 3, 3) and (F, N, 3), all at once."""
    ids = [int(f) for f in np.atleast_1d(frame)]
    placed = [model.frames[f].placement for f in ids]
    joints = _parents(model, ids)
    turn = motion.rotation[joints]  # (F, N, 3, 3)
    rotation = turn_each(turn, np.array([placement.rotation for placement in placed]))
    shift = np.array([placement.translation for placement in placed])
    origin = motion.origin[joints] + apply_each(turn, shift)
    return (rotation[0], origin[0]) if np.ndim(frame) == 0 else (rotation, origin)


def _parents(model: pin.Model, frame: int | Sequence[int]) -> int | np.ndarray:
    """The joint id that moves a frame, or those of several frames (F,)."""
    if np.ndim(frame) == 0:
        return model.frames[frame].parentJoint
    return np.array([model.frames[f].parentJoint for f in frame])


def frame_velocity(
    model: pin.Model, motion: TreeMotion, frame: int, origin: np.ndarray
) -> np.ndarray:
    """World velocity (N, 3) of a frame's origin, whose world position ``origin`` (N, 3) is
    :func:`frame_placements`'s: its parent joint's origin velocity and the turn about it,
    v_j + ω_j × (origin − o_j)."""
    j = model.frames[frame].parentJoint
    return motion.velocity[j] + cross(motion.omega[j], origin - motion.origin[j])


def frame_acceleration(
    model: pin.Model, motion: TreeMotion, frame: int | Sequence[int], point: np.ndarray
) -> np.ndarray:
    """World (classical) acceleration (N, 3) of a point fixed on a frame's body, at the world
    position ``point`` (N, 3): a_j + α_j × r + ω_j × (ω_j × r), r = point − o_j; for several
    frames (ids (F,), points (F, N, 3)), (F, N, 3)."""
    j = _parents(model, frame)
    r = point - motion.origin[j]
    w = motion.omega[j]
    return motion.acceleration[j] + cross(motion.alpha[j], r) + cross(w, cross(w, r))


def reach(model: pin.Model, q: np.ndarray) -> float:
    """The mechanism's size [m] along the configurations q (N, nq): the largest distance of a
    frame's origin (joints, links, cut frames) from the world origin, at least
    :data:`MIN_REACH`. A reaction moment's terms are a force times a lever arm up to this; a
    prismatic speed divided by it compares with an angular one."""
    _, origins = frame_placements(model, tree_motion(model, q), np.arange(model.nframes))
    return max(float(np.linalg.norm(origins, axis=2).max(initial=0.0)), MIN_REACH)


def point_jacobians(
    model: pin.Model,
    motion: TreeMotion,
    frames: Sequence[int],
    columns: Sequence[np.ndarray],
    points: np.ndarray,
) -> np.ndarray:
    """World-aligned Jacobians (F, N, 6, C) of several frames (ids (F,)) at once: frame f's on
    its velocity columns ``columns[f]`` (sorted, (c_f,) int, among them every column that moves
    it), padded with zero columns to the most, C; ``points``: the frames' origins (F, N, 3).
    A frame's columns are L_k + W_k × (p − o_k), W_k for each ancestor joint k's columns
    (L_k, W_k) (:attr:`~.layout.TreeLayout.support`), every frame's every column in one set of
    array operations."""
    layout = tree_layout(model)
    which, slot, moved = [], [], []
    for f, (frame, own) in enumerate(zip(frames, columns, strict=True)):
        moving = layout.support[model.frames[frame].parentJoint]
        which.append(np.full(moving.size, f))
        slot.append(np.searchsorted(own, moving))
        moved.append(moving)
    which, slot, moved = (np.concatenate(x) for x in (which, slot, moved))
    width = max((own.size for own in columns), default=0)
    jac = np.zeros((len(frames), points.shape[1], 6, width))
    angular = np.moveaxis(np.take(motion.angular_columns, moved, axis=2), 2, 0)  # (E, N, 3)
    linear = np.moveaxis(np.take(motion.linear_columns, moved, axis=2), 2, 0)
    lever = points[which] - motion.origin[layout.column_joint[moved]]
    jac[which, :, :3, slot] = linear + cross(angular, lever)
    jac[which, :, 3:, slot] = angular
    return jac
