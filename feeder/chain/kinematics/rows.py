"""The closure rows along a batched motion: their Jacobian, error, rate and acceleration at every
sample at once (numpy; the rows are those of :class:`~feeder.chain.model.closure.ClosedChain`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..model.closure import ClosedChain
from .tree import TreeMotion, cross, frame_placements, point_jacobian


@dataclass(frozen=True)
class ClosureKinematics:
    """The closure rows along a motion, N samples.

    Attributes:
        jacobian: J, (N, nc, nv) ((N, nc, 0) when skipped). residual: the rows' position
            error, (N, nc).
        rate, acceleration: The rows' first and second time derivatives, (N, nc).
        directions: Per closure, the revolute rows' moment directions (N, 2, 3) (None otherwise).
        rotation_a: Per closure, frame a's world rotation (N, 3, 3).
        hinge_alignment: Revolute closure label → u_a · u_b of its hinge axes (N,) (1 assembled,
            −1 upside down).
    """

    jacobian: np.ndarray
    residual: np.ndarray
    rate: np.ndarray
    acceleration: np.ndarray
    directions: list[np.ndarray | None]
    rotation_a: list[np.ndarray]
    hinge_alignment: dict[str, np.ndarray]


NEAR_HALF_TURN = 1e-6
"""Below this sine of the angle, the rotation vector is not read off the antisymmetric part: near
0 the factor θ / (2 sin θ) is ½, near π that part vanishes and Pinocchio's log3 takes over."""


def _log3(rotation: np.ndarray) -> np.ndarray:
    """Rotation vectors (N, 3) of rotation matrices (N, 3, 3), angles in [0, π]."""
    cosine = np.clip((np.trace(rotation, axis1=1, axis2=2) - 1.0) / 2.0, -1.0, 1.0)
    angle = np.arccos(cosine)
    skew = np.stack(
        [
            rotation[:, 2, 1] - rotation[:, 1, 2],
            rotation[:, 0, 2] - rotation[:, 2, 0],
            rotation[:, 1, 0] - rotation[:, 0, 1],
        ],
        axis=1,
    )
    sine = np.sin(angle)
    near = sine <= NEAR_HALF_TURN
    factor = np.where(near, 0.5, angle / np.where(near, 1.0, 2.0 * sine))
    out = factor[:, None] * skew
    for k in np.flatnonzero(near & (cosine < 0.0)):  # near a half turn: the skew part vanishes
        out[k] = pin.log3(rotation[k])
    return out


def _frame_acceleration(model, motion: TreeMotion, frame: int, point: np.ndarray) -> np.ndarray:
    """Classical acceleration (N, 3) of a frame's origin at ``point`` (N, 3)."""
    j = model.frames[frame].parentJoint
    r = point - motion.origin[j]
    w = motion.omega[j]
    return motion.acceleration[j] + cross(motion.alpha[j], r) + cross(w, cross(w, r))


def closure_kinematics(
    chain: ClosedChain, motion: TreeMotion, v: np.ndarray | None = None, with_jacobian: bool = True
) -> ClosureKinematics:
    """Every closure row's Jacobian, error, rate and acceleration along a batched motion with
    velocities v (N, nv); without v, at rest (a position-level pass: rates and accelerations
    zero, not computed). ``with_jacobian=False`` skips the Jacobian and the rates (zero)
    where only the accelerations are wanted."""
    model = chain.model
    n = motion.origin[0].shape[0]
    jacobian = np.zeros((n, chain.nc, model.nv if with_jacobian else 0))
    residual = np.zeros((n, chain.nc))
    acceleration = np.zeros((n, chain.nc))
    directions, rotations, alignment = [], [], {}
    for closure, rows, (a, b), perpendicular in zip(
        chain.closures, chain.row_slices, chain.frame_ids, chain.hinge_normals, strict=True
    ):
        rot_a, p_a = frame_placements(model, motion, a)
        rot_b, p_b = frame_placements(model, motion, b)
        if with_jacobian:
            jac_a, jac_b = point_jacobian(model, motion, a), point_jacobian(model, motion, b)
        else:  # no columns
            jac_a = jac_b = np.zeros((n, 6, 0))
        start = rows.start
        jacobian[:, start : start + 3] = jac_a[:, :3] - jac_b[:, :3]
        residual[:, start : start + 3] = p_a - p_b
        if v is not None:
            acceleration[:, start : start + 3] = _frame_acceleration(
                model, motion, a, p_a
            ) - _frame_acceleration(model, motion, b, p_b)
        ja, jb = model.frames[a].parentJoint, model.frames[b].parentJoint
        relative = motion.omega[ja] - motion.omega[jb]
        spin = motion.alpha[ja] - motion.alpha[jb]
        direction = None
        if closure.kind == "weld":
            jacobian[:, start + 3 : rows.stop] = jac_a[:, 3:] - jac_b[:, 3:]
            residual[:, start + 3 : rows.stop] = _log3(rot_a @ np.swapaxes(rot_b, 1, 2))
            acceleration[:, start + 3 : rows.stop] = spin
        elif closure.kind == "revolute":
            normals = rot_a @ perpendicular.T  # (N, 3, 2): columns n_1, n_2
            u_b = rot_b @ np.array(closure.axis_b)
            normals = np.swapaxes(normals, 1, 2)  # (N, 2, 3)
            direction = np.cross(normals, u_b[:, None, :])
            alignment[closure.label] = np.einsum("ni,ni->n", rot_a @ np.array(closure.axis), u_b)
            jacobian[:, start + 3 : rows.stop] = direction @ (jac_a[:, 3:] - jac_b[:, 3:])
            residual[:, start + 3 : rows.stop] = np.einsum("nki,ni->nk", normals, u_b)
            if v is None:
                directions.append(direction)
                rotations.append(rot_a)
                continue
            w_a, w_b = motion.omega[ja], motion.omega[jb]
            rates = np.cross(np.cross(w_a[:, None, :], normals), u_b[:, None, :]) + np.cross(
                normals, np.cross(w_b, u_b)[:, None, :]
            )
            acceleration[:, start + 3 : rows.stop] = np.einsum(
                "nki,ni->nk", rates, relative
            ) + np.einsum("nki,ni->nk", direction, spin)
        directions.append(direction)
        rotations.append(rot_a)
    rate = (
        np.einsum("ncv,nv->nc", jacobian, v)
        if v is not None and with_jacobian
        else np.zeros((n, chain.nc))
    )
    return ClosureKinematics(
        jacobian, residual, rate, acceleration, directions, rotations, alignment
    )
