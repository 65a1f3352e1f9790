"""Kinematics and Newton–Euler dynamics of a tree at every sample at once (numpy, world frame).

One Pinocchio call per sample costs a Python round trip each; for the thousands of samples of a
motion the same recursions run here over the joint tree once, on arrays of all samples, for
trees of one-degree-of-freedom revolute and prismatic joints (every URDF joint but ``floating``,
``planar`` and ``continuous``). For a joint j with parent p, joint placement (R₀, t₀) in p's
frame and unit axis s in its own frame (world axis e = R_p R₀ s), coordinate θ:

* placement: R_j = R_p R₀ exp(θ [s]×) (revolute) or R_p R₀ (prismatic); o_j = o_p + R_p t₀
  (+ e θ, prismatic);
* angular velocity and acceleration: ω_j = ω_p + e θ̇, α_j = α_p + e θ̈ + ω_p × e θ̇ (revolute;
  a prismatic joint keeps its parent's);
* origin velocity and acceleration, r = o_j − o_p: v_j = v_p + ω_p × r (+ e θ̇),
  a_j = a_p + α_p × r + ω_p × (ω_p × r) (+ 2 ω_p × e θ̇ + e θ̈, prismatic).

The backward pass (Newton–Euler) gives the wrench each joint transmits, parent on child, about
its origin: the rate of momentum of its subtree less gravity and the external wrenches applied
to it. Its component along the joint axis is the joint's generalized force: Pinocchio's RNEA to
round-off (tests/chain/test_kinematics.py checks both passes against Pinocchio).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin


def supports_batches(model: pin.Model) -> bool:
    """Whether every joint is a one-coordinate revolute or prismatic joint (batchable)."""
    data = model.createData()
    for j in range(1, model.njoints):
        joint = model.joints[j]
        subspace = np.asarray(data.joints[j].S, dtype=float).ravel()
        if joint.nq != 1 or joint.nv != 1 or subspace.shape != (6,):
            return False
        if np.any(subspace[:3]) and np.any(subspace[3:]):
            return False
    return True


@dataclass(frozen=True)
class TreeMotion:
    """World placements and motion of every joint frame of a tree, N samples; lists indexed by
    joint id (0 is the world, at rest), each entry an array over the samples.

    Attributes:
        rotation: R_j, (N, 3, 3). origin: o_j [m], (N, 3). axis: e_j, the joint's world axis,
            (N, 3) (zero for the world). revolute: (njoints,) bool, True for revolute joints.
        omega, alpha: Angular velocity [rad/s] and acceleration [rad/s²], (N, 3).
        velocity, acceleration: Velocity [m/s] and acceleration [m/s²] of the origin, (N, 3).
    """

    rotation: list[np.ndarray]
    origin: list[np.ndarray]
    axis: list[np.ndarray]
    revolute: np.ndarray
    omega: list[np.ndarray]
    alpha: list[np.ndarray]
    velocity: list[np.ndarray]
    acceleration: list[np.ndarray]


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
    velocities v and accelerations a (N, nv) (zero otherwise). The model must pass
    :func:`supports_batches`; q, v, a are trusted (checked by the caller)."""
    n, count = q.shape[0], model.njoints
    v = np.zeros((n, model.nv)) if v is None else v
    a = np.zeros((n, model.nv)) if a is None else a
    data = model.createData()
    zero = np.zeros((n, 3))
    rotation = [np.broadcast_to(np.eye(3), (n, 3, 3))]
    origin, axis, w, dw, vel, acc = ([zero] for _ in range(6))
    revolute = np.zeros(count, dtype=bool)
    for j in range(1, count):
        p, placement = model.parents[j], model.jointPlacements[j]
        subspace = np.asarray(data.joints[j].S, dtype=float).ravel()
        turning = bool(np.any(subspace[3:]))
        revolute[j] = turning
        local = subspace[3:] if turning else subspace[:3]
        x = q[:, model.joints[j].idx_q]
        dx = v[:, model.joints[j].idx_v][:, None]
        ddx = a[:, model.joints[j].idx_v][:, None]
        before = _rows(rotation[p], placement.rotation)
        here = origin[p] + _apply(rotation[p], placement.translation)
        e = _apply(before, local)
        axis.append(e)
        if turning:
            skew = pin.skew(local)
            s, c = np.sin(x)[:, None, None], np.cos(x)[:, None, None]
            rotation.append(
                before + s * _rows(before, skew) + (1.0 - c) * _rows(before, skew @ skew)
            )
            w.append(w[p] + e * dx)
            dw.append(dw[p] + e * ddx + cross(w[p], e * dx))
        else:
            here = here + e * x[:, None]
            rotation.append(before)
            w.append(w[p])
            dw.append(dw[p])
        r = here - origin[p]
        spin = cross(w[p], r)
        vel.append(vel[p] + spin)
        acc.append(acc[p] + cross(dw[p], r) + cross(w[p], spin))
        if not turning:
            vel[j] = vel[j] + e * dx
            acc[j] = acc[j] + 2.0 * cross(w[p], e * dx) + e * ddx
        origin.append(here)
    return TreeMotion(rotation, origin, axis, revolute, w, dw, vel, acc)


def frame_placements(
    model: pin.Model, motion: TreeMotion, frame: int
) -> tuple[np.ndarray, np.ndarray]:
    """World rotation (N, 3, 3) and origin (N, 3) of a frame at every sample."""
    placement = model.frames[frame].placement
    j = model.frames[frame].parentJoint
    rotation = _rows(motion.rotation[j], placement.rotation)
    origin = motion.origin[j] + _apply(motion.rotation[j], placement.translation)
    return rotation, origin


def point_jacobian(model: pin.Model, motion: TreeMotion, frame: int) -> np.ndarray:
    """World-aligned Jacobian (N, 6, nv) of a frame: [linear velocity of its origin; angular
    velocity], columns e_k × (p − o_k), e_k for revolute ancestors k, e_k, 0 for prismatic."""
    n = motion.origin[0].shape[0]
    _, point = frame_placements(model, motion, frame)
    jac = np.zeros((n, 6, model.nv))
    j = model.frames[frame].parentJoint
    while j > 0:
        k = model.joints[j].idx_v
        e = motion.axis[j]
        if motion.revolute[j]:
            jac[:, :3, k] = cross(e, point - motion.origin[j])
            jac[:, 3:, k] = e
        else:
            jac[:, :3, k] = e
        j = model.parents[j]
    return jac


def joint_wrenches(
    model: pin.Model, motion: TreeMotion, external: list[tuple[int, np.ndarray]] = ()
) -> tuple[np.ndarray, np.ndarray]:
    """Backward Newton–Euler pass (module docstring): the wrench each joint transmits, parent on
    child, world axes about the joint's origin — lists by joint id of force (N, 3) [N] and
    moment (N, 3) [N·m] — with the model's gravity.

    Args:
        external: (frame id, world wrench (N, 6) [force, moment about the frame's origin])
            applied to the frame's body.
    """
    n, count = motion.origin[0].shape[0], model.njoints
    gravity = model.gravity.linear
    force = [np.zeros((n, 3)) for _ in range(count)]
    moment = [np.zeros((n, 3)) for _ in range(count)]
    for j in range(1, count):
        inertia = model.inertias[j]
        rot = motion.rotation[j]
        lever = _apply(rot, inertia.lever)  # joint origin → centre of gravity, world
        w, dw = motion.omega[j], motion.alpha[j]
        a_g = motion.acceleration[j] + cross(dw, lever) + cross(w, cross(w, lever))
        f = inertia.mass * (a_g - gravity)
        # I ω̇ + ω × I ω with I = R I_local Rᵀ, evaluated in the body's axes.
        w_local, dw_local = _turn(np.swapaxes(rot, 1, 2), w), _turn(np.swapaxes(rot, 1, 2), dw)
        spin = w_local @ inertia.inertia
        n_local = dw_local @ inertia.inertia + cross(w_local, spin)
        force[j] = f
        moment[j] = _turn(rot, n_local) + cross(lever, f)
    for frame, wrench in external:
        j = model.frames[frame].parentJoint
        _, point = frame_placements(model, motion, frame)
        force[j] = force[j] - wrench[:, :3]
        moment[j] = moment[j] - wrench[:, 3:] - cross(point - motion.origin[j], wrench[:, :3])
    for j in range(count - 1, 0, -1):  # children have larger ids than their parents
        p = model.parents[j]
        if p > 0:
            force[p] = force[p] + force[j]
            moment[p] = (
                moment[p] + moment[j] + cross(motion.origin[j] - motion.origin[p], force[j])
            )
    return force, moment


def generalized_forces(
    model: pin.Model, motion: TreeMotion, force: list[np.ndarray], moment: list[np.ndarray]
) -> np.ndarray:
    """Each joint's generalized force (N, nv): e · moment (revolute), e · force (prismatic)."""
    tau = np.zeros((force[0].shape[0], model.nv))
    for j in range(1, model.njoints):
        along = moment[j] if motion.revolute[j] else force[j]
        tau[:, model.joints[j].idx_v] = np.einsum("ni,ni->n", motion.axis[j], along)
    return tau
