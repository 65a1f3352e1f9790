"""The optimisation problem of ``feeder design optimize`` in the form SLSQP takes, and the cycles
it runs.

**Variables.** z = (x scaled to [0, 1] by each variable's bounds, t), where t holds one number
per objective term (the epigraph form below).

**Objective and the peaks.** A term's peak is a maximum over quantities, elevations and cases
(:mod:`~feeder.design.objectives`): not differentiable where the case that peaks changes. So the
optimiser minimises it in the epigraph form of :mod:`~feeder.design.epigraph` (the cost, the
scaling and one constraint per case and quantity, shared with a mechanism's problem). A
``[limits]`` entry L on a peak is likewise one constraint per case, 1 − |peak| / L ≥ 0.

**Derivatives.** The geometric constraints (:mod:`~feeder.design.constraints`) are closed forms,
differentiated here by central differences. The peaks are differentiated by central differences
of full cycle runs with the sensitivities' step (:func:`~feeder.design.differences.step`:
ε^(1/3) · max(|p|, 0.1 m or 1 kg)): x ± h e_i for each variable that any load depends on (the
end stops' columns are zero), all (2n + 1) × cases cycles in one batch on the sweep's executor.

**The cycles.** A point's cases are :class:`~feeder.study.grid.SweepCase` s run by the sweep's
:func:`~feeder.study.sweep.case_peaks`, with the end stops and the cylinder's swing widened to
the travel (no load depends on them): a trial point outside the end stops is still evaluated,
and its constraints say by how much it is out.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, replace

import numpy as np

from ..device.loop import solve_loop
from ..device.parameters import FeederParameters
from ..exceptions import FeederError
from ..motion.laws import CycleSpec
from ..study.grid import SweepCase, Variant
from ..study.sweep_table import Row
from .constraints import (
    geometry_constraints,
    geometry_margins,
    geometry_met,
    hugging_stops,
    travel,
)
from .design_space import DesignSpace, with_values
from .differences import step
from .epigraph import FEASIBLE, Epigraph
from .evaluations import run_evaluations
from .objectives import Objective

WIDENED = (1e-3, math.radians(1.0))
"""How far [m, rad] the end stops and the cylinder's swing are widened beyond the travel for
the cycles of a trial point (module docstring)."""

DEFAULT_ELEVATIONS = (-4.0, 70.0, 2.0)
"""Elevations (start, stop, step) [deg] of :class:`Scope` without ``--elevations`` or a grid
(:func:`~feeder.design.optimize.run_optimization`)."""

DEFAULT_RATE = 100.0
"""Sample rate [Hz] without ``--rate`` or a grid: 101 samples a 1 s stage, a peak missed by
< 0.05 % (:data:`~feeder.motion.laws.PEAK_TOLERANCE`), at a fifth of 1 kHz's cost."""


class EvaluationFailed(FeederError):
    """A point's cycle failed (its loop cannot be solved, a pose at the toggle): the search from
    there stops."""


@dataclass(frozen=True)
class Scope:
    """The cases of every point: elevations × vehicle cases.

    Attributes:
        elevations_deg: ε [deg], (K,).
        variants: The grid's vehicle cases (a base motion, a payload retrofit), none of which
            changes a variable.
        spec: Stage durations and sample rate of every cycle.
    """

    elevations_deg: tuple[float, ...]
    variants: tuple[Variant, ...]
    spec: CycleSpec

    def keys(self) -> list[tuple[str, float]]:
        """(variant, elevation [deg]) of each case, in order."""
        return [(v.name, e) for v in self.variants for e in self.elevations_deg]

    def cases(self, device: str, params: FeederParameters) -> list[SweepCase]:
        """The cases of ``params`` named ``device``, in the order of :meth:`keys`."""
        return [
            SweepCase(device, v.name, e, math.radians(e), v.apply(params), self.spec, v.base)
            for v in self.variants
            for e in self.elevations_deg
        ]


@dataclass(frozen=True)
class Evaluation:
    """One point: its geometry margins and, unless its cycles failed, every case's peaks.

    Attributes:
        x: The variables [their units], (n,).
        params: The parameter set.
        margins: The geometric constraints' margins [their units].
        rows: Each case's sweep-table row, in the scope's order (empty when failed).
        failure: Why a cycle failed ("" when none did).
    """

    x: np.ndarray
    params: FeederParameters
    margins: np.ndarray
    rows: tuple[Row, ...]
    failure: str

    def peaks(self, quantity: str) -> np.ndarray:
        """|peak| of ``quantity`` in each case [its unit], (C,)."""
        if self.failure:
            raise EvaluationFailed(self.failure)
        return np.array([abs(float(row[quantity])) for row in self.rows])


def widened(p: FeederParameters) -> FeederParameters:
    """``p`` with its end stops and the cylinder's swing just beyond the travel's (module
    docstring); unchanged where the loop leaves the plane of r2 > 0."""
    q = solve_loop(p, travel(p)).q
    r2, phi1 = q[:, 1], q[:, 0]
    length, angle = WIDENED
    return replace(
        p,
        r2_min=max(min(p.r2_min, r2.min() - length), length),
        r2_max=max(p.r2_max, r2.max() + length),
        phi1_min=max(min(p.phi1_min, phi1.min() - angle), -math.pi),
        phi1_max=min(max(p.phi1_max, phi1.max() + angle), math.pi),
    )


class Problem(Epigraph):
    """The scaled problem (module docstring) and the cycles it has run.

    Args:
        space: The design.
        objective: What to minimise.
        scope: The cases of every point.
        executor: Where the cycles run (:func:`~feeder.study.sweep.sweep_executor`); None: here.
        slots: Cycles the executor runs at once.
    """

    def __init__(
        self,
        space: DesignSpace,
        objective: Objective,
        scope: Scope,
        executor: Executor | None,
        slots: int,
    ):
        self.space, self.objective, self.scope = space, objective, scope
        self.executor, self.slots = executor, slots
        self.lower = np.array([v.lower for v in space.variables])
        self.upper = np.array([v.upper for v in space.variables])
        self.geometry = geometry_constraints(space)
        self.loads = [k for k, v in enumerate(space.variables) if v.loads]
        self.references = [1.0] * len(objective.terms)
        self.cycles = 0
        self._cache: dict[bytes, Evaluation] = {}
        self._points = 0

    def evaluate(self, points: Sequence[np.ndarray]) -> list[Evaluation]:
        """Each point's :class:`Evaluation`, the new ones' cycles run in one batch."""
        points = [np.asarray(x, dtype=float) for x in points]
        todo: dict[bytes, tuple[np.ndarray, FeederParameters, str, list[SweepCase]]] = {}
        for x in points:
            key = x.tobytes()
            if key in self._cache or key in todo:
                continue
            params = with_values(self.space, x)
            self._points += 1
            device = f"x{self._points}"
            try:
                cases = self.scope.cases(device, widened(params))
            except FeederError as exc:  # r2 ≤ 0 over the travel: no loop at all
                cases, reason = [], str(exc)
            else:
                reason = ""
            todo[key] = (x, params, reason, cases)
        every = [case for *_, cases in todo.values() for case in cases]
        outcomes = dict(run_evaluations(every, self.executor, self.slots, progress=False))
        self.cycles += len(every)
        for key, (x, params, reason, cases) in todo.items():
            rows = [outcomes[case.key] for case in cases]
            failed = reason or next((row for row in rows if isinstance(row, str)), "")
            margins = geometry_margins(self.space, params)
            self._cache[key] = Evaluation(
                x, params, margins, () if failed else tuple(rows), failed
            )
        return [self._cache[x.tobytes()] for x in points]

    def candidate(self, x: np.ndarray) -> np.ndarray | None:
        """A global-start point from the sample ``x`` [the variables' units]: its end stops set
        to the travel ± the clearance (:func:`~feeder.design.constraints.hugging_stops`), moved
        to the nearest point that meets the geometric constraints
        (:func:`~feeder.design.feasibility.nearest_feasible`); None when that misses them."""
        from .feasibility import nearest_feasible  # scipy.optimize: not for the CLI's parser

        params = hugging_stops(self.space, with_values(self.space, x))
        x = nearest_feasible(self.space, [v.parameter.value(params) for v in self.space.variables],
                             tolerance=FEASIBLE)  # fmt: skip
        return x if geometry_met(self.space, with_values(self.space, x)) else None

    def evaluate_written(self, params: FeederParameters) -> Evaluation:
        """``params`` as its parameter file holds them, run as ``feeder sweep`` runs them (its
        own name, no widening)."""
        x = np.array([v.parameter.value(params) for v in self.space.variables])
        cases = self.scope.cases(params.name, params)
        outcomes = dict(run_evaluations(cases, self.executor, self.slots, progress=False))
        self.cycles += len(cases)
        rows = [outcomes[case.key] for case in cases]
        failed = next((row for row in rows if isinstance(row, str)), "")
        margins = geometry_margins(self.space, params)
        return Evaluation(x, params, margins, () if failed else tuple(rows), failed)

    def violations(self, e: Evaluation) -> np.ndarray:
        """The scaled margins of the real constraints (geometry, then each limit's worst case);
        ≥ 0 where met."""
        geometry = e.margins / np.array([c.scale for c in self.geometry])
        limits = [1.0 - e.peaks(q).max() / L for q, L in self.space.limits.items()]
        return np.concatenate([geometry, limits])

    def _dynamic(self, e: Evaluation, t: np.ndarray) -> np.ndarray:
        """The per-case limit constraints, then the epigraph ones (module docstring)."""
        parts = [1.0 - e.peaks(q) / L for q, L in self.space.limits.items()]
        parts += self.epigraph_rows(e, t)
        return np.concatenate(parts) if parts else np.zeros(0)

    def constraint_names(self) -> list[str]:
        """The name of each entry of :meth:`constraints` (``peak:<term>:<q>@<variant>,<ε>``)."""
        keys = [f"{variant},{e:g}" for variant, e in self.scope.keys()]
        names = [c.name for c in self.geometry]
        names += [f"limit:{q}@{k}" for q in self.space.limits for k in keys]
        for term in self.objective.terms:
            names += [f"peak:{term.name}:{q}@{k}" for q in term.quantities for k in keys]
        return names

    def constraints(self, z: np.ndarray) -> np.ndarray:
        """Every constraint at z, scaled; ≥ 0 where met."""
        (e,) = self.evaluate([self.physical(z)])
        n = len(self.lower)
        geometry = e.margins / np.array([c.scale for c in self.geometry])
        return np.concatenate([geometry, self._dynamic(e, np.asarray(z)[n:])])

    def constraints_jacobian(self, z: np.ndarray) -> np.ndarray:
        """d constraints / dz by central differences (module docstring), (rows, n + m)."""
        z = np.asarray(z, dtype=float)
        n, m = len(self.lower), len(self.objective.terms)
        x = self.physical(z)
        steps = np.array(
            [step(x[k], v.parameter.scale) for k, v in enumerate(self.space.variables)]
        )
        scale = np.array([c.scale for c in self.geometry])
        rows = len(self.constraints(z))
        jacobian = np.zeros((rows, n + m))
        shifted = {(k, s): x + s * steps[k] * np.eye(n)[k] for k in range(n) for s in (-1, 1)}
        dynamic = [shifted[(k, s)] for k in self.loads for s in (-1, 1)]
        keys = [key for key in shifted if key[0] in self.loads]
        found = dict(zip(keys, self.evaluate(dynamic), strict=True))
        t = z[n:]
        for k in range(n):
            below, above = shifted[(k, -1)], shifted[(k, 1)]
            width = (above[k] - below[k]) / (self.upper[k] - self.lower[k])
            g = [geometry_margins(self.space, with_values(self.space, y)) for y in (below, above)]
            jacobian[: len(scale), k] = (g[1] - g[0]) / scale / width
            if k in self.loads:
                d = [self._dynamic(found[(k, s)], t) for s in (-1, 1)]
                jacobian[len(scale) :, k] = (d[1] - d[0]) / width
        first = len(scale) + len(self.space.limits) * len(self.scope.keys())
        for j, term in enumerate(self.objective.terms):
            count = len(term.quantities) * len(self.scope.keys())
            jacobian[first : first + count, n + j] = 1.0
            first += count
        return jacobian
