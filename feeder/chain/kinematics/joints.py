"""Every Pinocchio joint type, at every sample at once: the motion of a joint's child frame
relative to the frame it is placed in (numpy).

A joint j sits in its parent's frame at the fixed placement (R₀, t₀); call that frame "before".
Its coordinates q_j (nq_j) and velocity v_j (nv_j) give the child frame's placement
(R_rel, p_rel) in "before", its angular velocity w_rel = A v_j and its origin's velocity
v_rel = B v_j (both in "before" axes, A and B (3, nv_j) the joint's angular and linear columns),
and the classical accelerations α_rel, a_rel. The conventions are Pinocchio's (its q and v):

=========================  ====  ====  =========================================================
kind (Pinocchio models)    nq    nv    child frame relative to "before"
=========================  ====  ====  =========================================================
``revolute`` (RX, RY, RZ,  1     1     turn θ about the unit axis s
RevoluteUnaligned)
``continuous`` (RUBX…,     2     1     the same, q = (cos θ, sin θ)
RevoluteUnboundedUnaligned)
``universal``              2     2     turn q₁ about a₁, then q₂ about the turned a₂
``spherical_zyx``          3     3     turns about z, the turned y, the turned x (q = angles)
``prismatic`` (PX, PY, PZ, 1     1     slide x along the unit axis s
PrismaticUnaligned)
``translation``            3     3     slide by q
``spherical``              4     3     rotation of the unit quaternion q = (x, y, z, w); v is the
                                       angular velocity in the child's axes
``planar``                 4     3     q = (x, y, cos θ, sin θ); v = (v_x, v_y, ω) in the
                                       child's axes
``free_flyer``             7     6     q = (position, quaternion); v = (linear, angular) in the
                                       child's axes
=========================  ====  ====  =========================================================

For the axis chains (revolute, continuous, universal, spherical_zyx) with world-like axes
e_k = R_{<k} a_k: w_rel = Σ e_k q̇_k and α_rel = Σ (e_k q̈_k + w_{<k} × e_k q̇_k). For the joints
whose v is in the child's axes, the classical acceleration of the origin is
a_rel = R_rel a_lin + w_rel × v_rel (Pinocchio's a is the spatial one).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ...exceptions import InputError
from ..model.jacobians import joint_jacobian

_Z = np.array([0.0, 0.0, 1.0])


def kind_of(joint: pin.JointModel) -> str:
    """The kind (module docstring) of a Pinocchio joint model.

    Raises:
        InputError: A joint type the kinematics do not handle (helical, ellipsoid, composite,
            mimic), named.
    """
    name = joint.shortname()
    if name in ("JointModelRX", "JointModelRY", "JointModelRZ", "JointModelRevoluteUnaligned"):
        return "revolute"
    if name.startswith("JointModelRUB") or name == "JointModelRevoluteUnboundedUnaligned":
        return "continuous"
    if name in ("JointModelPX", "JointModelPY", "JointModelPZ", "JointModelPrismaticUnaligned"):
        return "prismatic"
    kinds = {
        "JointModelUniversal": "universal",
        "JointModelSphericalZYX": "spherical_zyx",
        "JointModelTranslation": "translation",
        "JointModelSpherical": "spherical",
        "JointModelPlanar": "planar",
        "JointModelFreeFlyer": "free_flyer",
    }
    if name not in kinds:
        raise InputError(
            f"joint type {name} is not handled (revolute, continuous, prismatic, universal, "
            "spherical, spherical ZYX, translation, planar and free-flyer joints are)"
        )
    return kinds[name]


def joint_axes(model: pin.Model) -> list[np.ndarray]:
    """Per joint id, the unit axes (k, 3) of an axis chain or prismatic joint in its own axes, in
    the order of its velocity ((0, 3) for the other kinds and the world): the columns of its
    motion subspace at q = 0, read off one Jacobian pass at the neutral pose (the generic
    ``JointModel`` of ``model.joints`` does not expose the axes of every type; a joint's own
    columns in its own frame do not depend on the other joints' coordinates)."""
    data = model.createData()
    pin.computeJointJacobians(model, data, pin.neutral(model))
    axes = [np.zeros((0, 3))]
    for j in range(1, model.njoints):
        joint, kind = model.joints[j], kind_of(model.joints[j])
        if kind not in ("revolute", "continuous", "universal", "spherical_zyx", "prismatic"):
            axes.append(np.zeros((0, 3)))
            continue
        local = joint_jacobian(model, data, j, pin.LOCAL)
        subspace = local[:, joint.idx_v : joint.idx_v + joint.nv]
        columns = subspace[:3] if kind == "prismatic" else subspace[3:]
        axes.append((columns / np.linalg.norm(columns, axis=0)).T)
    return axes


@dataclass(frozen=True)
class RelativeMotion:
    """A joint's child frame relative to "before", N samples (module docstring).

    Attributes:
        rotation: R_rel (N, 3, 3). position: p_rel [m] (N, 3).
        angular, linear: The columns A, B (N, 3, nv_j) [rad/s, m/s per unit of v_j].
        omega, velocity: w_rel [rad/s], v_rel [m/s] (N, 3).
        alpha, acceleration: α_rel [rad/s²], a_rel [m/s²] (N, 3).
    """

    rotation: np.ndarray
    position: np.ndarray
    angular: np.ndarray
    linear: np.ndarray
    omega: np.ndarray
    velocity: np.ndarray
    alpha: np.ndarray
    acceleration: np.ndarray


def rotation_about(axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Rotations (N, 3, 3) by ``angle`` (N,) [rad] about the unit ``axis`` (3,) (Rodrigues)."""
    skew = pin.skew(axis)
    s, c = np.sin(angle)[:, None, None], np.cos(angle)[:, None, None]
    return np.eye(3) + s * skew + (1.0 - c) * (skew @ skew)


def quaternion_matrix(quaternion: np.ndarray) -> np.ndarray:
    """Rotation matrices (N, 3, 3) of unit quaternions (N, 4) in Pinocchio's order (x, y, z, w)."""
    x, y, z, w = (quaternion[:, k] for k in range(4))
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
            np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
            np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1),
        ],
        axis=1,
    )


def _cross(u: np.ndarray, w: np.ndarray) -> np.ndarray:
    out = np.empty(np.broadcast_shapes(u.shape, w.shape))
    out[..., 0] = u[..., 1] * w[..., 2] - u[..., 2] * w[..., 1]
    out[..., 1] = u[..., 2] * w[..., 0] - u[..., 0] * w[..., 2]
    out[..., 2] = u[..., 0] * w[..., 1] - u[..., 1] * w[..., 0]
    return out


def relative_motion(
    kind: str, axes: np.ndarray, q: np.ndarray, v: np.ndarray, a: np.ndarray
) -> RelativeMotion:
    """The child frame's motion relative to "before" (module docstring) for coordinates q
    (N, nq_j), velocities v and accelerations a (N, nv_j)."""
    n = q.shape[0]
    zero = np.zeros((n, 3))
    if kind in ("universal", "spherical_zyx"):  # the single-axis kinds: tree.tree_motion
        angles = q
        rotation = np.broadcast_to(np.eye(3), (n, 3, 3))
        omega, alpha = zero, zero
        columns = []
        for k, axis in enumerate(axes):
            e = rotation @ axis if k else np.broadcast_to(axis, (n, 3))
            columns.append(e)
            turn = e * v[:, k : k + 1]
            alpha = alpha + e * a[:, k : k + 1] + _cross(omega, turn)
            omega = omega + turn
            rotation = (
                rotation @ rotation_about(axis, angles[:, k])
                if k
                else rotation_about(axis, angles[:, k])
            )
        angular = np.stack(columns, axis=2)
        return RelativeMotion(
            rotation, zero, angular, np.zeros_like(angular), omega, zero, alpha, zero
        )
    identity = np.broadcast_to(np.eye(3), (n, 3, 3))
    if kind == "translation":
        linear = identity
        return RelativeMotion(
            identity,
            (linear @ q[:, :, None])[..., 0],
            np.zeros_like(linear),
            linear,
            zero,
            (linear @ v[:, :, None])[..., 0],
            zero,
            (linear @ a[:, :, None])[..., 0],
        )
    if kind == "spherical":
        rotation = quaternion_matrix(q)
        return RelativeMotion(
            rotation,
            zero,
            rotation,
            np.zeros_like(rotation),
            (rotation @ v[:, :, None])[..., 0],
            zero,
            (rotation @ a[:, :, None])[..., 0],
            zero,
        )
    if kind == "planar":
        rotation = rotation_about(_Z, np.arctan2(q[:, 3], q[:, 2]))
        angular = np.zeros((n, 3, 3))
        angular[:, 2, 2] = 1.0
        linear = np.zeros((n, 3, 3))
        linear[:, :, :2] = rotation[:, :, :2]
        position = np.zeros((n, 3))
        position[:, :2] = q[:, :2]
    else:  # free_flyer
        rotation = quaternion_matrix(q[:, 3:])
        angular = np.concatenate([np.zeros((n, 3, 3)), rotation], axis=2)
        linear = np.concatenate([rotation, np.zeros((n, 3, 3))], axis=2)
        position = q[:, :3]
    omega = (angular @ v[:, :, None])[..., 0]
    velocity = (linear @ v[:, :, None])[..., 0]
    return RelativeMotion(
        rotation,
        position,
        angular,
        linear,
        omega,
        velocity,
        (angular @ a[:, :, None])[..., 0],
        (linear @ a[:, :, None])[..., 0] + _cross(omega, velocity),
    )


def angle_columns(model: pin.Model) -> list[int]:
    """Velocity indices of the one-coordinate revolute joints: angles, 2π-periodic (a
    continuous joint's (cos, sin) and a quaternion are periodic by construction)."""
    return [
        model.joints[j].idx_v
        for j in range(1, model.njoints)
        if kind_of(model.joints[j]) == "revolute"
    ]


def angular_difference(
    model: pin.Model, q_from: np.ndarray, q_to: np.ndarray, angles: list[int]
) -> np.ndarray:
    """q_to ⊖ q_from (nv,) on the model's Lie groups, revolute angles (``angles``, from
    :func:`angle_columns`) taken the short way round, into (−π, π]."""
    step = pin.difference(model, q_from, q_to)
    step[angles] = np.pi - np.mod(np.pi - step[angles], 2.0 * np.pi)
    return step


def _quaternion_rate(quaternion: np.ndarray, omega: np.ndarray) -> np.ndarray:
    """d/dt of the unit quaternion (x, y, z, w) turning at ``omega`` in its own axes:
    ½ q ⊗ (ω, 0)."""
    x, y, z, w = quaternion
    a, b, c = omega
    return 0.5 * np.array(  # written out: np.cross on 3-vectors costs ten times as much
        [
            w * a + y * c - z * b,
            w * b + z * a - x * c,
            w * c + x * b - y * a,
            -(x * a + y * b + z * c),
        ]
    )


class ConfigurationRate:
    """q̇ (nq,) of the coefficients of q for the velocity v (nv,) (the table of the module
    docstring; Pinocchio's ``integrate(q, v dt)`` differentiated at dt = 0): v itself for the
    joints whose q is a vector, the rotation's and the unit circle's rates for the others.

    The joints are sorted once (a forward run's right-hand side calls it at every step): the
    vector ones' coordinates are copied in one indexed assignment, the unit circles' (cos, sin)
    rates (−sin, cos)·v computed in two (an N-four-bar has 2N + 1 of them), only the others are
    looped over.

    Args:
        model: The Pinocchio model.
    """

    def __init__(self, model: pin.Model):
        self.nq = model.nq
        plain_q, plain_v, circle_q, circle_v, self.others = [], [], [], [], []
        for j in range(1, model.njoints):
            joint = model.joints[j]
            iq, iv = joint.idx_q, joint.idx_v
            if joint.nq == joint.nv:
                plain_q += range(iq, iq + joint.nq)
                plain_v += range(iv, iv + joint.nv)
            elif (kind := kind_of(joint)) == "continuous":
                circle_q.append(iq)
                circle_v.append(iv)
            else:
                self.others.append((iq, iv, kind))
        self.plain_q, self.plain_v = np.array(plain_q, int), np.array(plain_v, int)
        self.circle_q, self.circle_v = np.array(circle_q, int), np.array(circle_v, int)

    def __call__(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        out = np.empty(self.nq)
        out[self.plain_q] = v[self.plain_v]
        cos, sin, rate = self.circle_q, self.circle_q + 1, v[self.circle_v]
        out[cos] = -rate * q[sin]
        out[sin] = rate * q[cos]
        for iq, iv, kind in self.others:
            if kind == "spherical":
                out[iq : iq + 4] = _quaternion_rate(q[iq : iq + 4], v[iv : iv + 3])
            elif kind == "planar":
                c, s, vj = q[iq + 2], q[iq + 3], v[iv : iv + 3]
                out[iq : iq + 4] = [
                    c * vj[0] - s * vj[1],
                    s * vj[0] + c * vj[1],
                    -s * vj[2],
                    c * vj[2],
                ]
            else:  # free flyer: position rate R v_linear, then the quaternion's
                qj, vj = q[iq : iq + 7], v[iv : iv + 6]
                out[iq : iq + 3] = quaternion_matrix(qj[None, 3:])[0] @ vj[:3]
                out[iq + 3 : iq + 7] = _quaternion_rate(qj[3:], vj[3:])
        return out
