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

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..model.base import BaseState
from .joints import joint_axes, kind_of, relative_motion

MIN_REACH = 1e-3
"""Smallest mechanism size [m] :func:`reach` gives (a mechanism whose frames all sit at the world
origin has none)."""


@dataclass(frozen=True)
class TreeMotion:
    """World placements and motion of every joint frame of a tree, N samples; lists indexed by
    joint id (0 is the world, at rest), each entry an array over the samples.

    Attributes:
        rotation: R_j, (N, 3, 3). origin: o_j [m], (N, 3).
        linear, angular: The joint's world columns at its origin (N, 3, nv_j) (module docstring;
            for a revolute joint, angular is its world axis and linear is zero).
        omega, alpha: Angular velocity [rad/s] and acceleration [rad/s²], (N, 3).
        velocity, acceleration: Velocity [m/s] and acceleration [m/s²] of the origin, (N, 3).
        gravity: Gravity [m/s²] in these axes (N, 3), or None: the model's (a base at rest).
    """

    rotation: list[np.ndarray]
    origin: list[np.ndarray]
    linear: list[np.ndarray]
    angular: list[np.ndarray]
    omega: list[np.ndarray]
    alpha: list[np.ndarray]
    velocity: list[np.ndarray]
    acceleration: list[np.ndarray]
    gravity: np.ndarray | None = None


def cross(u: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Row-wise cross product of two (N, 3) arrays (numpy's ``cross`` is several times slower
    on many short rows)."""
    out = np.empty(np.broadcast_shapes(u.shape, w.shape))
    out[..., 0] = u[..., 1] * w[..., 2] - u[..., 2] * w[..., 1]
    out[..., 1] = u[..., 2] * w[..., 0] - u[..., 0] * w[..., 2]
    out[..., 2] = u[..., 0] * w[..., 1] - u[..., 1] * w[..., 0]
    return out


def _rows(stack: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """Each (3, 3) of a stack (N, 3, 3) times one (3, 3), as one (3N × 3) product."""
    return (stack.reshape(-1, 3) @ matrix).reshape(stack.shape)


def _apply(stack: np.ndarray, vector: np.ndarray) -> np.ndarray:
    """Each (3, 3) of a stack (N, 3, 3) times one 3-vector, (N, 3)."""
    return (stack.reshape(-1, 3) @ vector).reshape(-1, 3)


def _turn(stack: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """Each (3, 3) of a stack (N, 3, 3) times its own 3-vector of (N, 3)."""
    return np.einsum("nij,nj->ni", stack, vectors)


def tree_motion(
    model: pin.Model, q: np.ndarray, v: np.ndarray | None = None, a: np.ndarray | None = None
) -> TreeMotion:
    """The forward recursion of the module docstring for configurations q (N, nq) and, if given,
    velocities v and accelerations a (N, nv) (zero otherwise; with neither, the velocity and
    acceleration recursions are skipped: a position-level pass). q, v, a are trusted (checked by
    the caller); a joint type that is not handled raises :class:`~feeder.exceptions.InputError`."""
    n, count = q.shape[0], model.njoints
    moving = v is not None or a is not None
    v = np.zeros((n, model.nv)) if v is None else v
    a = np.zeros((n, model.nv)) if a is None else a
    zero = np.zeros((n, 3))
    rotation = [np.broadcast_to(np.eye(3), (n, 3, 3))]
    origin, w, dw, vel, acc = ([zero] for _ in range(5))
    linear, angular = [np.zeros((n, 3, 0))], [np.zeros((n, 3, 0))]
    axes = joint_axes(model)
    for j in range(1, count):
        joint, p, placement = model.joints[j], model.parents[j], model.jointPlacements[j]
        kind = kind_of(joint)
        rel = relative_motion(
            kind,
            axes[j],
            q[:, joint.idx_q : joint.idx_q + joint.nq],
            v[:, joint.idx_v : joint.idx_v + joint.nv],
            a[:, joint.idx_v : joint.idx_v + joint.nv],
        )
        before = _rows(rotation[p], placement.rotation)
        here = origin[p] + _apply(rotation[p], placement.translation)
        if rel.position.any():
            here = here + _turn(before, rel.position)
        rotation.append(before @ rel.rotation)
        linear.append(before @ rel.linear)
        angular.append(before @ rel.angular)
        origin.append(here)
        if not moving:
            for rates in (w, dw, vel, acc):
                rates.append(zero)
            continue
        turn, slide = _turn(before, rel.omega), _turn(before, rel.velocity)
        w.append(w[p] + turn)
        dw.append(dw[p] + _turn(before, rel.alpha) + cross(w[p], turn))
        r = here - origin[p]
        spin = cross(w[p], r)
        vel.append(vel[p] + spin + slide)
        acc.append(
            acc[p]
            + cross(dw[p], r)
            + cross(w[p], spin)
            + 2.0 * cross(w[p], slide)
            + _turn(before, rel.acceleration)
        )
    return TreeMotion(rotation, origin, linear, angular, w, dw, vel, acc)


def on_base(motion: TreeMotion, base: BaseState) -> TreeMotion:
    """The absolute motion, in the base's moving axes, of a tree whose motion relative to its
    base is ``motion``, the base moving as ``base`` (module docstring); placements and columns
    are unchanged."""
    spin, turn = base.omega, base.alpha
    omega, alpha, velocity, acceleration = [spin], [turn], [base.velocity], [base.acceleration]
    for j in range(1, len(motion.origin)):
        o, w_r, v_r = motion.origin[j], motion.omega[j], motion.velocity[j]
        around = cross(spin, o)
        omega.append(spin + w_r)
        alpha.append(turn + motion.alpha[j] + cross(spin, w_r))
        velocity.append(base.velocity + around + v_r)
        acceleration.append(
            base.acceleration
            + cross(turn, o)
            + cross(spin, around)
            + 2.0 * cross(spin, v_r)
            + motion.acceleration[j]
        )
    return TreeMotion(
        motion.rotation,
        motion.origin,
        motion.linear,
        motion.angular,
        omega,
        alpha,
        velocity,
        acceleration,
        base.gravity,
    )


def frame_placements(
    model: pin.Model, motion: TreeMotion, frame: int
) -> tuple[np.ndarray, np.ndarray]:
    """World rotation (N, 3, 3) and origin (N, 3) of a frame at every sample."""
    placement = model.frames[frame].placement
    j = model.frames[frame].parentJoint
    rotation = _rows(motion.rotation[j], placement.rotation)
    origin = motion.origin[j] + _apply(motion.rotation[j], placement.translation)
    return rotation, origin


def frame_velocity(
    model: pin.Model, motion: TreeMotion, frame: int, origin: np.ndarray
) -> np.ndarray:
    """World velocity (N, 3) of a frame's origin, whose world position ``origin`` (N, 3) is
    :func:`frame_placements`'s: its parent joint's origin velocity and the turn about it,
    v_j + ω_j × (origin − o_j)."""
    j = model.frames[frame].parentJoint
    return motion.velocity[j] + cross(motion.omega[j], origin - motion.origin[j])


def frame_acceleration(
    model: pin.Model, motion: TreeMotion, frame: int, point: np.ndarray
) -> np.ndarray:
    """World (classical) acceleration (N, 3) of a point fixed on a frame's body, at the world
    position ``point`` (N, 3): a_j + α_j × r + ω_j × (ω_j × r), r = point − o_j."""
    j = model.frames[frame].parentJoint
    r = point - motion.origin[j]
    w = motion.omega[j]
    return motion.acceleration[j] + cross(motion.alpha[j], r) + cross(w, cross(w, r))


def reach(model: pin.Model, q: np.ndarray) -> float:
    """The mechanism's size [m] along the configurations q (N, nq): the largest distance of a
    frame's origin (joints, links, cut frames) from the world origin, at least
    :data:`MIN_REACH`. A reaction moment's terms are a force times a lever arm up to this; a
    prismatic speed divided by it compares with an angular one."""
    motion = tree_motion(model, q)
    distances = (
        float(np.linalg.norm(frame_placements(model, motion, f)[1], axis=1).max())
        for f in range(model.nframes)
    )
    return max(max(distances, default=0.0), MIN_REACH)


def point_jacobian(model: pin.Model, motion: TreeMotion, frame: int) -> np.ndarray:
    """World-aligned Jacobian (N, 6, nv) of a frame: [linear velocity of its origin; angular
    velocity], columns L_k + W_k × (p − o_k), W_k for each ancestor joint k's columns
    (L_k, W_k)."""
    n = motion.origin[0].shape[0]
    _, point = frame_placements(model, motion, frame)
    jac = np.zeros((n, 6, model.nv))
    j = model.frames[frame].parentJoint
    while j > 0:
        k = model.joints[j].idx_v
        columns = slice(k, k + model.joints[j].nv)
        lever = point - motion.origin[j]
        jac[:, :3, columns] = motion.linear[j] + cross(
            np.swapaxes(motion.angular[j], 1, 2), lever[:, None, :]
        ).swapaxes(1, 2)
        jac[:, 3:, columns] = motion.angular[j]
        j = model.parents[j]
    return jac
