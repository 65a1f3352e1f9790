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

:func:`kronecker_coriolis` is eq. (27) on a given ∂M/∂q, for any robot:
:func:`feeder.chain.dynamics.derivatives.mass_matrix_derivative` gets ∂M/∂q of any Pinocchio model.
numpy only: the caller has checked the arrays.
"""

from __future__ import annotations

import numpy as np


def kronecker_coriolis(dM_dq: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """Eq. (27): C = ∂M/∂q (I ⊗ q̇) − ½ [∂M/∂q (q̇ ⊗ I)]ᵀ, written with Kronecker products.

    Args:
        dM_dq: ∂M/∂q in the layout of eq. (4), shape (..., n, n²).
        qd: Generalized velocities q̇, shape (..., n).

    Returns:
        C(q, q̇), shape (..., n, n).
    """
    qd, dM_dq = np.asarray(qd, dtype=float), np.asarray(dM_dq, dtype=float)
    n = qd.shape[-1]
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
    qd = np.asarray(qd, dtype=float)
    n = qd.shape[-1]
    d = np.asarray(dM_dq, dtype=float).reshape(*np.shape(dM_dq)[:-2], n, n, n)  # ∂M_ij/∂q_k
    m_dot = np.einsum("...ijk,...k->...ij", d, qd)
    n_matrix = np.einsum("...ijl,...j->...il", d, qd)
    return 0.5 * (m_dot + n_matrix - np.swapaxes(n_matrix, -1, -2))
