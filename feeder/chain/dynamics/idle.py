"""The accelerations of idle motions, solved with the loads.

An idle motion (:mod:`feeder.chain.assembly.partition`: a rod spinning about its axis between two
balls, two coaxial hinges turning together) is a free motion of the closed chain with every
actuated joint locked. No actuator and no closure force does work along it — for N, a basis of
the null space of [J; S] (the closure rows and the actuated joints' rows), Nᵀ Sᵀ = 0 and
Nᵀ Jᵀ = 0 — so its acceleration is not a matter of kinematics but of dynamics: with the
prescribed motion's accelerations a and the tree's forces f = M a + b − Σ J_eᵀ w_e,

    Nᵀ M N z = −Nᵀ f,          q̈ = a + N z,

the idle accelerations z that the unactuated mechanism has (no lock, no extra load). The loads are
then those of q̈; Pinocchio's ``constraintDynamics`` driven by them returns q̈. Where Nᵀ M N is
singular (an idle motion that moves no mass) the minimum-norm z is taken: such a direction does
not change M q̈, hence not the loads.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..kinematics.tree import TreeMotion, tree_motion
from .newton_euler import generalized_forces, joint_wrenches

INERTIA_RANK = 1e-12
"""Idle inertias Nᵀ M N below this fraction of the mass matrix's scale count as zero (round-off of
the Newton–Euler passes is ~1e-16 of it)."""


def idle_basis(jacobian: np.ndarray, columns: list[int], count: int) -> np.ndarray:
    """Orthonormal bases (N, nv, count) of the idle motions: the last ``count`` right singular
    vectors of [J; S] at every sample (``jacobian``: the closure rows J (N, nc, nv);
    ``columns``: the actuated joints' velocity indices)."""
    n, nc, nv = jacobian.shape
    stacked = np.zeros((n, nc + len(columns), nv))
    stacked[:, :nc] = jacobian
    stacked[:, nc:][:, np.arange(len(columns)), columns] = 1.0
    _, _, vt = np.linalg.svd(stacked, full_matrices=True)
    basis = np.swapaxes(vt[:, nv - count :, :], 1, 2)
    basis[:, columns, :] = 0.0  # zero by construction (S N = 0): no round-off on the motors
    return basis


def idle_accelerations(
    model: pin.Model,
    q: np.ndarray,
    motion: TreeMotion,
    basis: np.ndarray,
    external: list[tuple[int, np.ndarray]],
) -> np.ndarray:
    """N z (N, nv): the idle motions' accelerations of the module docstring, for the motion
    ``motion`` (with its prescribed accelerations) and the external wrenches ``external``."""
    forces = generalized_forces(model, motion, *joint_wrenches(model, motion, external))
    n, nv, count = basis.shape
    zero = np.zeros((n, nv))
    still = tree_motion(model, q, zero, zero)
    rest = generalized_forces(model, still, *joint_wrenches(model, still))  # gravity alone
    inertia_columns = np.empty((n, nv, count))  # M N, from M n = f(q, 0, n) − f(q, 0, 0)
    for k in range(count):
        moving = tree_motion(model, q, zero, basis[:, :, k])
        inertia_columns[:, :, k] = (
            generalized_forces(model, moving, *joint_wrenches(model, moving)) - rest
        )
    return np.einsum("nvk,nk->nv", basis, idle_rates(basis, inertia_columns, forces))


def idle_rates(basis: np.ndarray, inertia_columns: np.ndarray, forces: np.ndarray) -> np.ndarray:
    """z (N, k) of Nᵀ M N z = −Nᵀ f (module docstring), minimum norm where Nᵀ M N is singular
    (its singular values at or below :data:`INERTIA_RANK` of the largest |M N| count as zero),
    from the bases N (N, nv, k), the columns M N (N, nv, k) and the tree's forces f (N, nv)."""
    idle_inertia = np.swapaxes(basis, 1, 2) @ inertia_columns  # (N, k, k)
    rhs = -np.einsum("nvk,nv->nk", basis, forces)
    scale = max(float(np.abs(inertia_columns).max(initial=0.0)), 1e-300)
    u, s, vt = np.linalg.svd(idle_inertia)
    inverse = np.where(s > INERTIA_RANK * scale, 1.0 / np.where(s > 0.0, s, 1.0), 0.0)
    return np.einsum("nji,nj->ni", vt, inverse * np.einsum("nji,nj->ni", u, rhs))
