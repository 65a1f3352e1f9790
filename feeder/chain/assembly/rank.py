"""The linear algebra of the rank tests: which points a locked-input motion moves (idle motions
move none), truncated pseudo-inverses that give idle motions no share, and the velocity gain
(:func:`velocity_gain`: dimensionless, lengths' speeds in units of the mechanism's reach).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..model.closure import ClosedChain
from ..model.jacobians import frame_jacobian, joint_jacobian

IDLE_TOLERANCE = 1e-9
"""An idle direction (unit vector of joint rates) may move a joint origin, frame or centre of
gravity by at most this [m per unit] times the mechanism's size: round-off of the Jacobians
(1e-16) is far below, any real lever arm (≥ 1e-3 of the size) far above."""


def point_rows(chain: ClosedChain) -> np.ndarray:
    """World velocity rows (3 p, nv) of every joint origin, frame origin and centre of
    gravity of a body with mass, from the Jacobians in the chain's data (after
    :meth:`ClosedChain.jacobian`)."""
    model, data = chain.model, chain.data
    world = pin.LOCAL_WORLD_ALIGNED
    rows = []
    for j in range(1, model.njoints):
        jac = joint_jacobian(model, data, j, world)
        rows.append(jac[:3])
        if model.inertias[j].mass > 0.0:
            lever = data.oMi[j].rotation @ model.inertias[j].lever
            rows.append(jac[:3] - pin.skew(lever) @ jac[3:])
    for f in range(1, len(model.frames)):
        if model.frames[f].parentJoint > 0:
            rows.append(frame_jacobian(model, data, f, world)[:3])
    return np.vstack(rows)


def truncated_inverse(matrix: np.ndarray, tolerance: float) -> tuple[np.ndarray, int, np.ndarray]:
    """The pseudo-inverse of ``matrix`` (m, n) with its singular values at or below
    ``tolerance`` dropped (idle motions get no share: minimum-norm solutions), its rank r, and an
    orthonormal basis (m, r) of its range."""
    if matrix.size == 0:
        return np.zeros((matrix.shape[1], matrix.shape[0])), 0, np.zeros((matrix.shape[0], 0))
    u, s, vt = np.linalg.svd(matrix, full_matrices=False)
    keep = s > tolerance
    return (vt[keep].T / s[keep]) @ u[:, keep].T, int(keep.sum()), u[:, keep]


def velocity_gain(
    rates: np.ndarray, dependent: np.ndarray, independent: np.ndarray
) -> float | np.ndarray:
    """The velocity gain ‖S_dep⁻¹ R S_ind‖₂ of the rate map R = ∂q̇_dep/∂q̇_ind, (n_dep, n_ind)
    or (N, n_dep, n_ind) (then one gain per sample): the largest dependent speed per unit
    independent speed, each speed divided by its coordinate's scale S (the mechanism's reach L
    [m] for a length's rate, 1 for an angle's), so that it is dimensionless — rad/rad for a
    mechanism of revolute joints — and the same for a mechanism scaled up or down. 0 without
    dependent or independent coordinates.

    Args:
        rates: R, the minimum-norm solution's map (idle motions get no share).
        dependent, independent: The scales S (n_dep,), (n_ind,) [m or 1].
    """
    if rates.shape[-1] == 0 or rates.shape[-2] == 0:
        return 0.0 if rates.ndim == 2 else np.zeros(rates.shape[0])
    gain = np.linalg.norm(rates * (independent / dependent[:, None]), ord=2, axis=(-2, -1))
    return float(gain) if rates.ndim == 2 else gain


def moved_joints(model: pin.Model, motion: np.ndarray) -> tuple[str, ...]:
    """Names of the joints an idle motion (nv,) moves, largest share first."""
    shares = {
        model.names[j]: float(
            np.abs(
                motion[model.joints[j].idx_v : model.joints[j].idx_v + model.joints[j].nv]
            ).max()
        )
        for j in range(1, model.njoints)
    }
    return tuple(
        name for name, share in sorted(shares.items(), key=lambda x: -x[1]) if share > 1e-6
    )
