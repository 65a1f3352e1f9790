"""∂M/∂q of any Pinocchio model, exact to round-off, in the layout of the paper's eq. (4).

With ∂M/∂q = [∂m_1/∂q … ∂m_n/∂q] (n × n², entry (i, j·n + k) = ∂M_ij/∂q_k, indices from 0):
Ṁ is linear in q̇, and Pinocchio's Christoffel Coriolis matrix satisfies Ṁ = C_chr + C_chrᵀ, so
∂M/∂q_k = C_chr(q, e_k) + C_chr(q, e_k)ᵀ. Feed the result to
:func:`feeder.paper.coriolis.kronecker_coriolis` for the paper's C of eq. (27) on any robot.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ...exceptions import InputError
from ...validation import check_vector


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
    q = check_vector("q", q, nv)
    d = np.empty((nv, nv, nv))  # d[i, j, k] = ∂M_ij/∂q_k
    for k, e_k in enumerate(np.eye(nv)):
        c = pin.computeCoriolisMatrix(model, data, q, e_k)
        d[:, :, k] = c + c.T
    return d.reshape(nv, nv * nv)


def _check_model(model: pin.Model) -> int:
    if model.nq != model.nv:
        raise InputError(
            f"∂M/∂q by q needs q̇ = v, i.e. nq = nv; model {model.name!r} has nq = {model.nq}, "
            f"nv = {model.nv} (continuous, spherical or free-flyer joints)"
        )
    return model.nv
