"""The epigraph form that ``feeder design optimize`` hands SciPy's SLSQP, shared by the device's
problem (:class:`~feeder.design.problem.Problem`) and a mechanism's
(:class:`~feeder.design.mechanism.problem.MechanismProblem`).

**Variables.** z = (x scaled to [0, 1] by each variable's bounds, t), t holding one number per
objective term.

**Cost.** Σ W_j t_j, subject to t_j ≥ |peak of q in case c| / R_j for every quantity q of term j
and every case c (R_j: the term's peak as given): each case's peak is a constraint of its own,
differentiable while its largest sample stays put, and the optimum balances the cases that bind
(their multipliers say which).

A client supplies ``lower``, ``upper`` (the bounds, (n,)), ``objective`` (its terms' weights and
quantities), ``references`` (R_j), :meth:`violations` of an evaluated point and the points
themselves, whose ``peaks(q)`` is the magnitude of quantity q in each case, (C,).
"""

from __future__ import annotations

import numpy as np

FEASIBLE = 1e-8
"""Largest scaled violation [-] of a constraint that still counts as met: 1e-9 m of a 0.1 m
scale, 1e-8 of a limit (SLSQP meets its active constraints to ~1e-12 at convergence)."""


class Epigraph:
    """The scaled variables, the cost and the objective of the epigraph form (module
    docstring). Subclasses set ``lower``, ``upper``, ``objective``, ``references`` and define
    :meth:`violations`."""

    given = "the device as given"
    """How the reference point is named in messages."""

    lower: np.ndarray
    upper: np.ndarray

    def physical(self, z: np.ndarray) -> np.ndarray:
        """The variables [their units] of the scaled ``z`` (its first n entries)."""
        n = len(self.lower)
        return self.lower + np.asarray(z, dtype=float)[:n] * (self.upper - self.lower)

    def scaled(self, x: np.ndarray) -> np.ndarray:
        """The scaled variables of ``x`` [their units], (n,)."""
        return (np.asarray(x, dtype=float) - self.lower) / (self.upper - self.lower)

    def term_peaks(self, e) -> list[float]:
        """Each objective term's peak over its quantities and the cases [its unit]."""
        return [max(e.peaks(q).max() for q in t.quantities) for t in self.objective.terms]

    def objective_value(self, e) -> float:
        """The objective at ``e`` [its unit]."""
        return self.objective.value(self.term_peaks(e), self.references)

    def violations(self, e) -> np.ndarray:
        """The scaled margins of the real constraints; ≥ 0 where met."""
        raise NotImplementedError

    def max_violation(self, e) -> float:
        """The largest scaled violation of a real constraint (0 when all are met) [-]."""
        margins = self.violations(e)
        return float(max(0.0, -margins.min())) if margins.size else 0.0

    def feasible(self, e) -> bool:
        """Every real constraint met within :data:`FEASIBLE`, and the runs succeeded."""
        return not e.failure and self.max_violation(e) <= FEASIBLE

    def start(self, e) -> np.ndarray:
        """z at the point ``e``: its scaled variables and t at the terms' peaks."""
        peaks = self.term_peaks(e)
        return np.concatenate([self.scaled(e.x), np.divide(peaks, self.references)])

    def cost(self, z: np.ndarray) -> float:
        """Σ W_j t_j [-]."""
        return float(np.dot(self.weights(), z[len(self.lower) :]))

    def cost_gradient(self, z: np.ndarray) -> np.ndarray:
        """d cost / dz, (n + m,)."""
        return np.concatenate([np.zeros(len(self.lower)), self.weights()])

    def weights(self) -> np.ndarray:
        """W_j, (m,)."""
        return np.array([term.weight for term in self.objective.terms])

    def epigraph_rows(self, e, t: np.ndarray) -> list[np.ndarray]:
        """t_j − peak(q, c) / R_j for every term j, quantity q and case c, one array per (j, q)."""
        return [
            t[j] - e.peaks(q) / self.references[j]
            for j, term in enumerate(self.objective.terms)
            for q in term.quantities
        ]
