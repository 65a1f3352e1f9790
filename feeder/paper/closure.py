"""The loop closure of the hand-derived model, eq. (44) corrected: f(q), J_f and J̇_f q̇.

The pin P = A + d3 (cos q3, sin q3) = (q2 + d2) (cos q1, sin q1); written here from the paper,
independently of the pipeline's closed form (:mod:`feeder.device.loop`), which the tests compare.
"""

from __future__ import annotations

import numpy as np

from ..device.parameters import FeederParameters
from .bodies import coordinates


def closure_residual(p: FeederParameters, q: np.ndarray) -> np.ndarray:
    """f(q) = P1 (c1, s1) − A − d3 (c3, s3) [m] (eq. 44, corrected), shape (..., 2)."""
    q = coordinates("q", q)
    reach = q[..., 1] + p.d2
    return np.stack(
        [
            reach * np.cos(q[..., 0]) - p.d3 * np.cos(q[..., 2]) - p.L1,
            reach * np.sin(q[..., 0]) - p.d3 * np.sin(q[..., 2]) - p.L2,
        ],
        axis=-1,
    )


def closure_jacobian(p: FeederParameters, q: np.ndarray) -> np.ndarray:
    """J_f = ∂f/∂q (eq. 44, corrected), shape (..., 2, 4)."""
    q = coordinates("q", q)
    reach = q[..., 1] + p.d2
    c1, s1, c3, s3 = np.cos(q[..., 0]), np.sin(q[..., 0]), np.cos(q[..., 2]), np.sin(q[..., 2])
    jac = np.zeros((*q.shape[:-1], 2, 4))
    jac[..., 0, 0], jac[..., 0, 1], jac[..., 0, 2] = -reach * s1, c1, p.d3 * s3
    jac[..., 1, 0], jac[..., 1, 1], jac[..., 1, 2] = reach * c1, s1, -p.d3 * c3
    return jac


def closure_bias(p: FeederParameters, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """J̇_f q̇ [m/s²], shape (..., 2): f̈ = J_f q̈ + J̇_f q̇."""
    q, qd = coordinates("q", q), coordinates("qd", qd)
    reach = q[..., 1] + p.d2
    c1, s1, c3, s3 = np.cos(q[..., 0]), np.sin(q[..., 0]), np.cos(q[..., 2]), np.sin(q[..., 2])
    cross, spin1, spin3 = 2.0 * qd[..., 0] * qd[..., 1], qd[..., 0] ** 2, qd[..., 2] ** 2
    return np.stack(
        [
            -s1 * cross - reach * c1 * spin1 + p.d3 * c3 * spin3,
            c1 * cross - reach * s1 * spin1 + p.d3 * s3 * spin3,
        ],
        axis=-1,
    )
