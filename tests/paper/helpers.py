"""Hand-derived quantities that only the tests use: the paper's potential energy, its forward
dynamics (the KKT system of eqs. (46)–(47)) and the central inertia tensors of eq. (17), moved
here from :mod:`feeder.paper` since nothing in the package calls them."""

from __future__ import annotations

import numpy as np

from feeder.device.parameters import FeederParameters
from feeder.paper import bodies, closure, lagrange


def potential_energy(
    p: FeederParameters, q: np.ndarray, gripped: bool | np.ndarray = True
) -> np.ndarray:
    """Π = Σ_i m_i g y_i [J] (eq. 42, corrected: no ½; datum y = 0 at B), shape (...)."""
    q = bodies.coordinates("q", q)
    flag = bodies.grip_weight(gripped, q.shape[:-1])[..., None]
    masses = bodies.body_masses(p) * np.concatenate([np.ones((*q.shape[:-1], 4)), flag], axis=-1)
    return bodies.G * np.sum(masses * bodies.body_positions(p, q)[..., 1], axis=-1)


def generalized_forces(p: FeederParameters, q, qd, gripped) -> np.ndarray:
    """C q̇ + g, shape (..., 4)."""
    c = lagrange.coriolis_matrix(p, q, qd, gripped)
    return np.einsum("...ij,...j->...i", c, qd) + lagrange.gravity_vector(p, q, gripped)


def forward_dynamics(
    p: FeederParameters,
    q: np.ndarray,
    qd: np.ndarray,
    tau: np.ndarray,
    gripped: bool | np.ndarray = True,
) -> tuple[np.ndarray, np.ndarray]:
    """q̈ and λ from the generalized forces: eqs. (46)–(47) differentiated twice,

        [M  J_fᵀ; J_f  0] [q̈; λ] = [τ − C q̇ − g; −J̇_f q̇].

    Args:
        p: Device parameters.
        q, qd: Assembled state [φ1, r2, φ3, φ4] and its rates, (..., 4).
        tau: Generalized forces [N·m, N, N·m, N·m], (..., 4) (τ1 = τ3 = 0 for the real drive).
        gripped: Payload held (bool or (...,) 0/1).

    Returns:
        q̈ (..., 4) and λ (..., 2) [N] (the force of the piston on the arm, world x, y).
    """
    q, qd, tau = (
        bodies.coordinates("q", q),
        bodies.coordinates("qd", qd),
        bodies.coordinates("tau", tau),
    )
    shape = np.broadcast_shapes(q.shape, qd.shape, tau.shape)[:-1]
    jac = np.broadcast_to(closure.closure_jacobian(p, q), (*shape, 2, 4))
    kkt = np.zeros((*shape, 6, 6))
    kkt[..., :4, :4] = lagrange.mass_matrix(p, q, gripped)
    kkt[..., :4, 4:] = np.swapaxes(jac, -1, -2)
    kkt[..., 4:, :4] = jac
    rhs = np.concatenate(
        [tau - generalized_forces(p, q, qd, gripped), -closure.closure_bias(p, q, qd)], axis=-1
    )
    solution = np.linalg.solve(kkt, rhs[..., None])[..., 0]
    return solution[..., :4], solution[..., 4:]


def central_inertias(p: FeederParameters, q: np.ndarray) -> np.ndarray:
    """I_i = R_i diag(I_ix, I_iy, I_iz) R_iᵀ: central inertia tensors in world axes [kg·m²],
    (..., 5, 3, 3) (eq. 17's I_i, full tensors)."""
    rot = bodies.body_rotations(p, q)
    moments = np.array([link.moments for link in p.links().values()])
    return np.einsum("...bij,bj,...bkj->...bik", rot, moments, rot)
