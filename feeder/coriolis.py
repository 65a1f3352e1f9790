"""The paper's Kronecker-product Coriolis matrix, eq. (27), for the feeder and for any robot.

With the derivative of a matrix by a vector laid out as in eq. (4),

    ∂M/∂q = [∂m_1/∂q  ∂m_2/∂q  …  ∂m_n/∂q]   (n × n²),  entry (i, j·n + k) = ∂M_ij/∂q_k,

(m_j is the j-th column of M; indices from 0), the paper writes the Lagrange equations as
M q̈ + C q̇ + g = τ − J_fᵀ λ (eq. 28) with

    C(q, q̇) = ∂M/∂q (I_n ⊗ q̇) − ½ [∂M/∂q (q̇ ⊗ I_n)]ᵀ                          (27)
            = Ṁ − ½ Nᵀ,   N = ∂M/∂q (q̇ ⊗ I_n),  N_il = Σ_j ∂M_ij/∂q_l q̇_j.

C q̇ = Ṁ q̇ − ½ ∂(q̇ᵀ M q̇)/∂q is the Coriolis–centrifugal force, the same vector as any other
factorisation gives (Pinocchio's ``nonLinearEffects − computeGeneralizedGravity``), but the
matrix is not the Christoffel one that Pinocchio's ``computeCoriolisMatrix`` returns,
C_chr = ½ (Ṁ + N − Nᵀ). Consequences of the paper's convention:

* C_paper − C_chr = ½ (Ṁ − N), not zero in general;
* Ṁ − 2 C_paper = Nᵀ − Ṁ is **not** skew-symmetric (Ṁ − 2 C_chr = Nᵀ − N is);
* yet q̇ᵀ (Ṁ − 2 C_paper) q̇ = 0, because q̇ᵀ N q̇ = q̇ᵀ Ṁ q̇ — the power balance
  d/dt(½ q̇ᵀ M q̇) = q̇ᵀ (τ − g − J_fᵀ λ) still holds.

:func:`kronecker_coriolis` is eq. (27) on a given ∂M/∂q; :func:`mass_matrix_derivative` gets
∂M/∂q exactly from Pinocchio for any model with nq = nv: Ṁ is linear in q̇ and Pinocchio's
Christoffel matrix satisfies Ṁ = C_chr + C_chrᵀ, so ∂M/∂q_k = C_chr(q, e_k) + C_chr(q, e_k)ᵀ.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from .exceptions import InputError, check_finite


def kronecker_coriolis(dM_dq: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """Eq. (27): C = ∂M/∂q (I ⊗ q̇) − ½ [∂M/∂q (q̇ ⊗ I)]ᵀ, written with Kronecker products.

    Args:
        dM_dq: ∂M/∂q in the layout of eq. (4), shape (..., n, n²).
        qd: Generalized velocities q̇, shape (..., n).

    Returns:
        C(q, q̇), shape (..., n, n).
    """
    qd, dM_dq = check_finite("qd", qd), check_finite("dM_dq", dM_dq)
    n = qd.shape[-1] if qd.ndim else 0
    if n == 0 or dM_dq.shape[-2:] != (n, n * n):
        raise InputError(
            f"∂M/∂q must have shape (..., n, n²) for q̇ of shape (..., n); got "
            f"{dM_dq.shape} and {qd.shape}"
        )
    # I ⊗ q̇ and q̇ ⊗ I per sample, (..., n², n): entries (j n + k, l) = δ_jl q̇_k, q̇_j δ_kl.
    eye_kron_qd = np.zeros((*qd.shape[:-1], n, n, n))
    qd_kron_eye = np.zeros((*qd.shape[:-1], n, n, n))
    for j in range(n):
        eye_kron_qd[..., j, :, j] = qd
        qd_kron_eye[..., :, j, j] = qd
    eye_kron_qd = eye_kron_qd.reshape(*qd.shape[:-1], n * n, n)
    qd_kron_eye = qd_kron_eye.reshape(*qd.shape[:-1], n * n, n)
    m_dot = dM_dq @ eye_kron_qd
    n_matrix = dM_dq @ qd_kron_eye
    return m_dot - 0.5 * np.swapaxes(n_matrix, -1, -2)


def christoffel_coriolis(dM_dq: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """The Christoffel-symbol Coriolis matrix ½ (Ṁ + N − Nᵀ) (Pinocchio's convention).

    Args:
        dM_dq: ∂M/∂q in the layout of eq. (4), shape (..., n, n²).
        qd: Generalized velocities q̇, shape (..., n).

    Returns:
        C_chr(q, q̇), shape (..., n, n), with Ṁ − 2 C_chr skew-symmetric.
    """
    qd = check_finite("qd", qd)
    n = qd.shape[-1]
    d = np.asarray(dM_dq, dtype=float).reshape(
        *dM_dq.shape[:-2], n, n, n
    )  # d[..., i, j, k] = ∂M_ij/∂q_k
    m_dot = np.einsum("...ijk,...k->...ij", d, qd)
    n_matrix = np.einsum("...ijl,...j->...il", d, qd)
    return 0.5 * (m_dot + n_matrix - np.swapaxes(n_matrix, -1, -2))


def mass_matrix_derivative(model: pin.Model, data: pin.Data, q: np.ndarray) -> np.ndarray:
    """∂M/∂q (nv × nv², layout of eq. 4) of a Pinocchio model at ``q``, exact to round-off.

    Uses ∂M/∂q_k = C_chr(q, e_k) + C_chr(q, e_k)ᵀ with Pinocchio's ``computeCoriolisMatrix``.

    Args:
        model: Any Pinocchio model whose configuration is its own velocity space (nq = nv:
            revolute, prismatic and other Euclidean joints, so that q̇ = v).
        data: Its data (overwritten).
        q: Configuration, shape (nq,).

    Raises:
        InputError: nq ≠ nv (e.g. continuous or free-flyer joints), or a non-finite or
            misshaped q.
    """
    nv = _check_model(model)
    q = _check_vector("q", q, nv)
    d = np.empty((nv, nv, nv))  # d[i, j, k] = ∂M_ij/∂q_k
    for k, e_k in enumerate(np.eye(nv)):
        c = pin.computeCoriolisMatrix(model, data, q, e_k)
        d[:, :, k] = c + c.T
    return d.reshape(nv, nv * nv)


def coriolis_matrix(model: pin.Model, data: pin.Data, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """The paper's C(q, q̇) of eq. (27) for any Pinocchio model with nq = nv, shape (nv, nv).

    C(q, q̇) q̇ equals Pinocchio's Coriolis–centrifugal term; see the module docstring for how
    C itself differs from Pinocchio's ``computeCoriolisMatrix``.

    Raises:
        InputError: nq ≠ nv, or a non-finite or misshaped q or q̇.
    """
    qd = _check_vector("qd", qd, _check_model(model))
    return kronecker_coriolis(mass_matrix_derivative(model, data, q), qd)


def _check_model(model: pin.Model) -> int:
    if model.nq != model.nv:
        raise InputError(
            f"eq. (27) needs q̇ = v, i.e. nq = nv; model {model.name!r} has nq = {model.nq}, "
            f"nv = {model.nv} (continuous, spherical or free-flyer joints)"
        )
    return model.nv


def _check_vector(name: str, value: np.ndarray, size: int) -> np.ndarray:
    array = check_finite(name, value)
    if array.shape != (size,):
        raise InputError(f"{name} must have shape ({size},), got {array.shape}")
    return array
