"""Projection of a forward run's state back onto the closed chain's position and velocity
constraints (the drift control of :func:`~feeder.chain.dynamics.forward.simulate`).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..assembly.newton import POSITION_TOLERANCE, newton
from ..assembly.rank import truncated_inverse
from ..model.closure import ClosedChain
from .forward_equations import IntegrationError
from .singular import SINGULAR_TOLERANCE


def project(chain: ClosedChain, y: np.ndarray) -> np.ndarray:
    """The state y = (q, q̇, …) with (q, q̇) moved onto the position and velocity constraints:
    the nearest closed q (minimum-norm Newton over every coordinate, unit quaternions restored),
    then the minimum-norm change of q̇ that gives J q̇ = 0; the rest of y is kept. Both steps
    use the singular values of the closure Jacobian above
    :data:`~feeder.chain.dynamics.singular.SINGULAR_TOLERANCE` of the largest: near a singular
    position (a parallelogram lying flat) the vanishing ones would turn a residual at round-off
    into a jump onto another branch (1e-10 m over a singular value of 1e-7 is a millimetre).

    Raises:
        IntegrationError: q cannot be brought back onto the constraints.
    """
    model = chain.model
    nq, nv = model.nq, model.nv
    q = pin.normalize(model, y[:nq].copy())
    q, norm = newton(chain, q, np.arange(nv), tolerance=SINGULAR_TOLERANCE)
    if norm > POSITION_TOLERANCE * 1e3:
        raise IntegrationError(
            f"the run left the constraints by {norm:.3e} and cannot be projected back: a "
            "singular pose, or tolerances too loose"
        )
    v = y[nq : nq + nv]
    jac = chain.jacobian(q)
    # J⁺ truncated: a redundant row (a planar loop's, Bricard's) is a singular value of
    # round-off size that lstsq's default cut-off (n ε σ_max) may keep, and then J⁺ J = I would
    # project every velocity to zero.
    pinv, _, _ = truncated_inverse(jac, SINGULAR_TOLERANCE, relative=True)
    v = v - pinv @ (jac @ v)
    return np.concatenate([q, v, y[nq + nv :]])
