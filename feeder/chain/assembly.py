"""Generic assembly of a closed chain: dependent coordinates from independent ones.

Position level: Gauss–Newton on the closure residual f(q) = 0 over the dependent coordinates,
the independent ones held fixed. Velocity and acceleration level: the linear systems
J q̇ = 0 and J q̈ + J̇ q̇ = 0 solved for the dependent components. All solves are least squares,
so the redundant out-of-plane row of a planar loop does no harm. The dependent Jacobian must have
full column rank (otherwise the closure leaves some dependent coordinates free: too few
independent joints) and the closure's rank (otherwise the dependent coordinates cannot follow
every motion of the independent ones: too many); either fails at a singular pose.

This works for any :class:`~feeder.chain.closure.ClosedChain`; the feeding device also has a closed
form (:mod:`feeder.device.loop`), and the two agree.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pinocchio as pin

from ..exceptions import SingularPoseError, UnreachablePoseError
from .closure import ClosedChain

POSITION_TOLERANCE = 1e-13
"""Closure residual [m] at which Newton stops: a few ulps of the mechanism's size (~1 m)."""


class Partition:
    """Split of a chain's velocity indices into independent and dependent ones.

    Args:
        chain: The closed chain.
        independent: Names of the joints whose coordinates are given.
    """

    def __init__(self, chain: ClosedChain, independent: Sequence[str]):
        self.chain = chain
        self.independent_joints = tuple(independent)
        mask = np.zeros(chain.model.nv, dtype=bool)
        for name in self.independent_joints:
            mask[chain.joint_slice(name)] = True
        self.independent = np.flatnonzero(mask)
        self.dependent = np.flatnonzero(~mask)

    def _dependent_jacobian(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Closure Jacobian (nc, nv) and its dependent columns, after checking that the closure
        determines the dependent velocities: rank J_dep = number of dependent coordinates (none
        free) = rank J (the independent ones can move freely)."""
        jac = self.chain.jacobian(q)
        jac_dep = jac[:, self.dependent]
        tol = 1e-9 * max(1.0, np.abs(jac).max())
        rank_full = np.linalg.matrix_rank(jac, tol=tol)
        rank_dep = np.linalg.matrix_rank(jac_dep, tol=tol) if self.dependent.size else 0
        if rank_dep < self.dependent.size:
            raise SingularPoseError(
                f"the closure does not determine the {self.dependent.size} dependent "
                f"coordinates at q = {np.round(q, 6)}: dependent Jacobian rank {rank_dep} "
                f"(too few independent joints {list(self.independent_joints)}, or a singular pose)"
            )
        if rank_dep < rank_full:
            raise SingularPoseError(
                f"the dependent coordinates cannot follow the independent ones at "
                f"q = {np.round(q, 6)}: closure Jacobian rank {rank_full}, dependent part rank "
                f"{rank_dep} (too many independent joints, or a singular pose)"
            )
        return jac, jac_dep

    def assemble(self, q_guess: np.ndarray, max_iterations: int = 50) -> np.ndarray:
        """Closed configuration with the independent coordinates of ``q_guess``.

        Args:
            q_guess: Configuration (nq,) whose independent coordinates are kept; its dependent
                ones are the starting guess (choose the assembly branch with it).
            max_iterations: Newton iterations before giving up.

        Returns:
            q (nq,) with ‖residual‖ ≤ :data:`POSITION_TOLERANCE`.

        Raises:
            UnreachablePoseError: No convergence, or the solution leaves the joint limits.
            SingularPoseError: The dependent coordinates are not determined.
        """
        model = self.chain.model
        q = self.chain.check_q(q_guess).copy()
        residual = self.chain.residual(q)
        for _ in range(max_iterations):
            if np.linalg.norm(residual) <= POSITION_TOLERANCE:
                break
            _, jac_dep = self._dependent_jacobian(q)
            step = np.zeros(model.nv)
            step[self.dependent] = -np.linalg.lstsq(jac_dep, residual, rcond=None)[0]
            q = pin.integrate(model, q, step)
            residual = self.chain.residual(q)
        else:
            raise UnreachablePoseError(
                f"the loop does not close at the given independent coordinates "
                f"(residual {np.linalg.norm(residual):.3e} m after {max_iterations} Newton steps)"
            )
        self._dependent_jacobian(q)
        low, high = model.lowerPositionLimit, model.upperPositionLimit
        outside = (q < low - 1e-12) | (q > high + 1e-12)
        if np.any(outside):
            i = int(np.flatnonzero(outside)[0])
            joint = next(
                model.names[j]
                for j in range(1, model.njoints)
                if model.joints[j].idx_q <= i < model.joints[j].idx_q + model.joints[j].nq
            )
            raise UnreachablePoseError(
                f"closing the loop needs {joint} = {q[i]:.6g}, outside its limits "
                f"[{low[i]:.6g}, {high[i]:.6g}]"
            )
        return q

    def velocity(self, q: np.ndarray, v_independent: np.ndarray) -> np.ndarray:
        """Velocity (nv,) with the given independent components and J q̇ = 0.

        Args:
            q: Closed configuration (nq,).
            v_independent: Velocities of the independent coordinates, in the order of
                ``self.independent``.
        """
        jac, jac_dep = self._dependent_jacobian(q)
        v = np.zeros(self.chain.model.nv)
        v[self.independent] = v_independent
        v[self.dependent] = -np.linalg.lstsq(jac_dep, jac @ v, rcond=None)[0]
        return v

    def acceleration(self, q: np.ndarray, v: np.ndarray, a_independent: np.ndarray) -> np.ndarray:
        """Acceleration (nv,) with the given independent components and J q̈ + J̇ q̇ = 0."""
        jac, jac_dep = self._dependent_jacobian(q)
        a = np.zeros(self.chain.model.nv)
        a[self.independent] = a_independent
        rhs = jac @ a + self.chain.bias(q, v)
        a[self.dependent] = -np.linalg.lstsq(jac_dep, rhs, rcond=None)[0]
        return a
