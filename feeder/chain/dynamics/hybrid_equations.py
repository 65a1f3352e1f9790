"""The equations of a hybrid run (:mod:`~feeder.chain.dynamics.hybrid`, whose docstring derives
them): the actuated joints' prescribed motion between the table's samples (:class:`Prescribed`)
and the right-hand side (q̇, q̈, the free freedoms' travel rates) with the projection back onto the
loops and the table (:class:`HybridEquations`).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ...hermite import quintic_hermite
from ..assembly.newton import POSITION_TOLERANCE, newton
from ..assembly.rank import rank_tolerance, truncated_inverse
from ..kinematics.joints import ConfigurationRate
from .forward_base import MovingBase
from .forward_equations import IntegrationError
from .free_freedoms import FreeFreedoms
from .idle import idle_basis, idle_rates
from .inverse import ChainDynamics


class Prescribed:
    """The actuated joints' x(t), ẋ(t), ẍ(t): the quintic Hermite interpolant of the table's
    samples t (N,), x, dx, ddx (N, n) (module docstring), its n columns in one piecewise
    polynomial (evaluated once per call for all of them)."""

    def __init__(self, t: np.ndarray, x: np.ndarray, dx: np.ndarray, ddx: np.ndarray):
        curve = quintic_hermite(t, x, dx, ddx)
        self.curves = (curve, curve.derivative(), curve.derivative(2))

    def __call__(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return tuple(curve(t) for curve in self.curves)


class HybridEquations:
    """The right-hand side (q̇, q̈, travel rates) of a hybrid run (module docstring), called as
    f(t, y) with y = (q, q̇, travel) of size nq + nv + m; ``count``: the calls so far."""

    def __init__(self, dyn: ChainDynamics, free: FreeFreedoms, table: Prescribed, rate: float):
        model = dyn.chain.model
        self.dyn, self.free, self.table, self.rate = dyn, free, table, rate
        self.model, self.nq, self.nv = model, model.nq, model.nv
        self.columns = np.array(dyn.columns, dtype=int)
        self.select = np.zeros((self.columns.size, model.nv))
        self.select[np.arange(self.columns.size), self.columns] = 1.0
        self.turning = np.array(
            [model.joints[model.getJointId(name)].nq == 2 for name in dyn.actuated]
        )  # continuous joints: their gaps to the table are angles, wrapped
        self.velocity = None if model.nq == model.nv else ConfigurationRate(model)
        self.moving = None if dyn.base is None else MovingBase(model, dyn.base)
        self.data = model.createData()
        self.count = 0

    def accelerations(self, t: float, q: np.ndarray, v: np.ndarray):
        """q̈ (nv,) and the basis N (nv, k) of the motions left with the actuated joints
        locked, at time t [s] and state (q, v) (module docstring; one sample, on Pinocchio's
        algorithms as the forward runs' right-hand side)."""
        chain, model, data, w = self.dyn.chain, self.model, self.data, self.rate
        x, dx, ddx = self.table(t)
        jac = chain.jacobian(q)
        stacked = np.vstack([jac, self.select])
        gap = self.table_gap(x, q)
        target = np.concatenate(
            [
                -chain.bias(q, v) - 2.0 * w * (jac @ v) - w**2 * chain.residual(q),
                ddx + 2.0 * w * (dx - v[self.columns]) + w**2 * gap,
            ]
        )
        inverse, rank, _ = truncated_inverse(stacked, rank_tolerance(stacked))
        prescribed = inverse @ target
        basis = idle_basis(jac[None], self.dyn.columns, model.nv - rank)[0]
        mass = pin.crba(model, data, q)
        mass = np.triu(mass) + np.triu(mass, 1).T  # crba fills the upper triangle
        forces = mass @ prescribed + pin.nonLinearEffects(model, data, q, v)
        if self.moving is not None:  # b → b_B: the moving base's bias (hybrid's docstring)
            forces -= self.moving.bias(data, t, q, v)[0]
        if self.dyn.elements:
            forces -= self.dyn.elements.generalized(q, v, t)[0]
        z = idle_rates(basis[None], (mass @ basis)[None], forces[None])[0]
        return prescribed + basis @ z, basis

    def __call__(self, t: float, y: np.ndarray) -> np.ndarray:
        self.count += 1
        nq, nv = self.nq, self.nv
        q, v = y[:nq], y[nq : nq + nv]
        a, basis = self.accelerations(t, q, v)
        if not np.all(np.abs(a) < 1e154):
            raise IntegrationError(f"the accelerations are not finite at t = {t:.6g} s")
        out = np.empty_like(y)
        out[:nq] = v if self.velocity is None else self.velocity(q, v)
        out[nq : nq + nv] = a
        out[nq + nv :] = (basis @ (basis.T @ v))[self.free.pivots]
        return out

    def gap(self, t: float, q: np.ndarray) -> float:
        """The largest gap [m, rad] of q to the loops and to the table's x(t)."""
        loops = float(np.abs(self.dyn.chain.residual(q)).max(initial=0.0))
        table = np.abs(self.table_gap(self.table(t)[0], q))
        return max(loops, float(table.max(initial=0.0)))

    def table_gap(self, x: np.ndarray, q: np.ndarray) -> np.ndarray:
        """x − the actuated coordinates of q (n,) [rad, m], a continuous joint's wrapped into
        [−π, π)."""
        gap = x - self.dyn.partition.independent_values(q)
        return np.where(self.turning, np.mod(gap + np.pi, 2.0 * np.pi) - np.pi, gap)

    def project(self, t: float, y: np.ndarray) -> np.ndarray:
        """y with (q, q̇) moved onto the loops with the actuated joints at x(t), ẋ(t) (module
        docstring); the travel kept.

        Raises:
            IntegrationError: q cannot be brought back onto the loops.
        """
        chain, partition = self.dyn.chain, self.dyn.partition
        x, dx, _ = self.table(t)
        q = partition.with_independent(pin.normalize(self.model, y[: self.nq].copy()), x)
        q, norm = newton(chain, q, partition.dependent)
        if norm > POSITION_TOLERANCE * 1e3:
            raise IntegrationError(
                f"at t = {t:.6g} s the run left the loops by {norm:.3e} and cannot be projected "
                "back: a singular pose, or tolerances too loose"
            )
        v = y[self.nq : self.nq + self.nv].copy()
        v[self.columns] = dx
        jac = chain.jacobian(q)
        inverse, _, _ = truncated_inverse(jac[:, partition.dependent], rank_tolerance(jac))
        v[partition.dependent] -= inverse @ (jac @ v)
        return np.concatenate([q, v, y[self.nq + self.nv :]])
