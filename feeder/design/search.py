"""The search of ``feeder design optimize``: a global start, then SciPy's SLSQP.

1. **Reference.** The device as given (the variables at their starts): the objective terms'
   reference values, the "before" of every table.
2. **Global start.** The peaks may have several local minima over the bounds, so a
   Latin-hypercube sample (``scipy.stats.qmc.LatinHypercube``, seeded: the same sample every
   run) of the variables that loads depend on is drawn, and each point made a candidate by the
   problem (``candidate``: the device's moves it to its geometric constraints, which cost no
   cycle, and drops it if none is met); the candidates are run one after another.
3. **Local search.** ``scipy.optimize.minimize(method="SLSQP")`` on the problem of
   :mod:`~feeder.design.problem`, from the best feasible point so far (or the least infeasible
   one), then again from the next-best for each further start asked. Each iterate is a row of
   the history. A resumed run skips the global start and begins where the last run's last
   iterate was.

The result is the feasible point of least objective the search recorded, with the multipliers
of SLSQP's last QP. A Ctrl-C leaves the history as it is; the caller writes the best so far.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.optimize import OptimizeResult, minimize
from scipy.stats import qmc
from tqdm import tqdm

from ..exceptions import InputError
from .history import History
from .problem import Evaluation, EvaluationFailed, Problem

MAX_ITERATIONS = 100
"""Most SLSQP iterations of one local search."""

DISTINCT = 1e-3
"""Samples closer than this in every scaled variable [-] (moved to the same constraint, say)
are run once."""

TOLERANCE = 1e-9
"""SLSQP's ``ftol``: the objective, ~1 in its scaled form, converged to 1e-9 of the reference
peak (the peaks carry round-off of ~1e-12 of their value)."""


@dataclass(frozen=True)
class Found:
    """What the search found.

    Attributes:
        problem: The problem.
        reference: The device as given.
        best: The feasible point of least objective; None when none was feasible.
        result: SLSQP's last result (its message and multipliers); None without a local search.
        result_point: The point of that result.
        messages: One line per local search: where it started, how it ended.
    """

    problem: Problem
    reference: Evaluation
    best: Evaluation | None
    result: OptimizeResult | None
    result_point: Evaluation | None
    messages: tuple[str, ...]


class Search:
    """One run of the search (module docstring).

    Args:
        problem: The problem, its executor open.
        history: Where the rows go (an earlier run's rows when resuming).
        progress: Progress bars on a terminal.
    """

    def __init__(self, problem: Problem | Any, history: History, progress: bool = True):
        self.problem, self.history = problem, history
        self.quiet = None if progress else True  # None: tqdm shows the bar only on a terminal
        self.began = time.monotonic()
        self.points: dict[bytes, Evaluation] = {}
        self.reference_point: Evaluation | None = None

    def record(self, stage: str, e: Evaluation) -> None:
        """A history row for ``e`` (and keep it, as a candidate for the best)."""
        p = self.problem
        objective = np.nan if e.failure else p.objective_value(e)
        violation = np.inf if e.failure else p.max_violation(e)
        feasible = not e.failure and p.feasible(e)
        seconds = time.monotonic() - self.began
        self.history.record(stage, e.x, objective, violation, feasible, p.cycles, seconds)
        self.points[e.x.tobytes()] = e

    def feasible(self) -> list[Evaluation]:
        """The feasible points this run recorded, least objective first."""
        p = self.problem
        return sorted((e for e in self.points.values() if p.feasible(e)), key=p.objective_value)

    def best(self) -> Evaluation | None:
        """The feasible point of least objective among those this run recorded."""
        feasible = self.feasible()
        return feasible[0] if feasible else None

    def reference(self) -> Evaluation:
        """Evaluate the device as given and set the terms' reference values.

        Raises:
            FeederError: Its cycles fail, or an objective term's peak is zero there.
        """
        p = self.problem
        start = np.array([v.start for v in p.space.variables])
        (e,) = p.evaluate([start])
        if e.failure:
            raise InputError(f"{p.given} (the variables' starts) fails: {e.failure}")
        for term, peak in zip(p.objective.terms, p.term_peaks(e), strict=True):
            if not peak > 0.0:
                raise InputError(
                    f"the objective's peak {term.name} is zero for {p.given} over its cases: "
                    "there is nothing to minimise"
                )
        p.references = p.term_peaks(e)
        self.record("reference", e)
        self.reference_point = e
        return e

    def sample(self, count: int, seed: int, done: set[bytes] = frozenset()) -> None:
        """The global start: ``count`` Latin-hypercube points, each moved to the nearest point
        meeting the geometric constraints (:func:`~.feasibility.nearest_feasible`), run unless
        in ``done`` (an interrupted run's: the sample is the same every run)."""
        p = self.problem
        if count == 0:
            return
        unit = qmc.LatinHypercube(d=len(p.loads), seed=seed).random(count)
        candidates: list[np.ndarray] = []
        for row in unit:
            x = np.array([v.start for v in p.space.variables])
            x[p.loads] = p.lower[p.loads] + row * (p.upper[p.loads] - p.lower[p.loads])
            x = p.candidate(x)
            z = None if x is None else p.scaled(x)
            if z is not None and all(np.abs(z - p.scaled(y)).max() > DISTINCT for y in candidates):
                candidates.append(x)
        candidates = [x for x in candidates if x.tobytes() not in done]
        with tqdm(candidates, desc="global start", unit="point", disable=self.quiet) as bar:
            for x in bar:
                (e,) = p.evaluate([x])
                self.record("sample", e)

    def local(self, start: Evaluation, stage: str = "local") -> tuple[OptimizeResult, str]:
        """SLSQP from ``start``; returns its result and a line saying how it ended."""
        p = self.problem
        n = len(p.lower)
        bounds = [(0.0, 1.0)] * n + [(0.0, None)] * len(p.objective.terms)
        constraints = {"type": "ineq", "fun": p.constraints, "jac": p.constraints_jacobian}
        bar = tqdm(desc="SLSQP", unit="iteration", disable=self.quiet)

        def iterate(zk: np.ndarray) -> None:
            (e,) = p.evaluate([p.physical(zk)])
            self.record("local", e)
            bar.update()
            bar.set_postfix(objective=f"{p.objective_value(e):.6g}")

        z0 = p.start(start)
        try:
            result = minimize(
                p.cost,
                z0,
                jac=p.cost_gradient,
                method="SLSQP",
                bounds=bounds,
                constraints=constraints,
                callback=iterate,
                options={"maxiter": MAX_ITERATIONS, "ftol": TOLERANCE},
            )
        except EvaluationFailed as exc:
            return None, f"stopped: a trial point's cycles failed ({exc})"
        finally:
            bar.close()
        (end,) = p.evaluate([p.physical(result.x)])
        if not np.array_equal(end.x, self.history.rows[-1].x):
            self.record(stage, end)
        return result, f"{result.message} after {result.nit} iterations"

    def run(self, samples: int, starts: int, seed: int = 0) -> Found:
        """Reference, global start, local searches; the best point found. A resumed run (the
        history holds an earlier run's rows) starts SLSQP from the earlier run's last iterate,
        or, when it stopped in the global start, runs the points of the sample not yet run."""
        earlier = list(self.history.rows)
        reference = self.reference()
        last = next((r for r in reversed(earlier) if r.stage in ("local", "resumed")), None)
        kept = sorted((r for r in earlier if r.feasible), key=lambda r: r.objective)[:starts]
        for e in self.problem.evaluate([r.x for r in kept]):  # candidates for the best
            self.points.setdefault(e.x.tobytes(), e)
        if last is not None:
            (e,) = self.problem.evaluate([last.x])
            self.record("resumed", e)
            starts_from = [e]
        else:
            self.sample(samples, seed, {r.x.tobytes() for r in earlier})
            starts_from = self._starts(starts)
        messages, result, result_point = [], None, None
        for e in starts_from:
            result, message = self.local(e)
            messages.append(f"SLSQP from iteration {self._row_of(e)}: {message}")
            if result is not None:
                result_point = self.problem.evaluate([self.problem.physical(result.x)])[0]
        return Found(self.problem, reference, self.best(), result, result_point, tuple(messages))

    def _starts(self, count: int) -> list[Evaluation]:
        """The ``count`` best feasible points so far, or the least infeasible one."""
        p = self.problem
        ran = [e for e in self.points.values() if not e.failure]
        feasible = sorted((e for e in ran if p.feasible(e)), key=p.objective_value)
        if feasible:
            return feasible[:count]
        return [min(ran, key=p.max_violation)]

    def _row_of(self, e: Evaluation) -> int:
        key = e.x.tobytes()
        return next(r.iteration for r in reversed(self.history.rows) if r.x.tobytes() == key)
