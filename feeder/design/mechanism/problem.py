"""The optimisation of a mechanism's design in SLSQP's form (the epigraph form of
:mod:`feeder.design.epigraph`, shared with the device), and the runs it makes.

**Cases.** A case is a sample of a motion table: each objective term's quantity gives one
epigraph constraint per sample of every table, t_j ≥ |q(sample)| / R_j. The peak is the largest
of these smooth functions of the variables, so the optimum that balances two samples (the
classic minimax of a cylinder's force at the two ends of its travel) is a vertex of smooth
constraints, which SLSQP meets to round-off; a constraint per table (its peak) would have a
kink there.

**Constraints** (≥ 0 where met, scaled; each per sample):

* every sample assembles: a point whose motion does not is a failed evaluation (the search
  from there stops, as on the device);
* ``stroke:<joint>:min|max``: (the coordinate − min allowed) / (max − min allowed), (max
  allowed − the coordinate) / (the same);
* ``max_velocity_gain``: 1 − gain / (the gain allowed), the distance to a singular pose
  (where the gain → ∞);
* ``limit:<peak>``: 1 − |value| / limit.

**Derivatives.** Central differences of full runs, x ± h e_k for every variable (h from
:func:`~feeder.design.differences.step`: ε^(1/3) · max(|p|, the unit's scale)), the 2n runs of
an iterate in one batch on the sweep's executor.
"""

from __future__ import annotations

from collections.abc import Sequence
from concurrent.futures import Executor
from dataclasses import dataclass

import numpy as np

from ..differences import step
from ..epigraph import Epigraph
from ..problem import EvaluationFailed
from .design_file import MechanismDesign
from .evaluation import GAIN, Mechanism, PointCase, Run, run_points


@dataclass(frozen=True)
class MechanismEvaluation:
    """One point of a mechanism.

    Attributes:
        x: The variables [their units], (n,).
        urdf: Its URDF text.
        run: Its runs (None when they failed).
        failure: Why they failed ("" when they did not).
    """

    x: np.ndarray
    urdf: str
    run: Run | None
    failure: str

    def peaks(self, quantity: str) -> np.ndarray:
        """|quantity| at every sample of every motion table [its unit], (S,): the epigraph's
        cases (module docstring)."""
        if self.failure:
            raise EvaluationFailed(self.failure)
        return self.run.values(quantity)

    def coordinate(self, joint: str) -> np.ndarray:
        """The joint's coordinate at every sample of every table [m or rad], (S,)."""
        if self.failure:
            raise EvaluationFailed(self.failure)
        return np.concatenate(self.run.coordinates[joint])


class MechanismProblem(Epigraph):
    """The scaled problem of a mechanism (module docstring) and the runs it has made.

    Args:
        design: The design file.
        mechanism: The mechanism's files.
        executor: Where the runs go (:func:`~feeder.study.sweep.sweep_executor`); None: here.
        slots: Runs the executor makes at once.
    """

    given = "the model as given"

    def __init__(
        self,
        design: MechanismDesign,
        mechanism: Mechanism,
        executor: Executor | None,
        slots: int,
    ):
        self.space, self.mechanism = design, mechanism
        self.objective = design.objective
        self.executor, self.slots = executor, slots
        self.lower = np.array([v.lower for v in design.variables])
        self.upper = np.array([v.upper for v in design.variables])
        self.loads = list(range(len(design.variables)))
        self.references = [1.0] * len(design.objective.terms)
        self.cycles = 0
        self.tables = [path.name for path in mechanism.motions]
        self._targets = [v.target for v in design.variables]
        self._cache: dict[bytes, MechanismEvaluation] = {}

    def evaluate(self, points: Sequence[np.ndarray]) -> list[MechanismEvaluation]:
        """Each point's evaluation, the new ones run in one batch."""
        points = [np.asarray(x, dtype=float) for x in points]
        cases = {}
        for x in points:
            key = x.tobytes()
            if key not in self._cache and key not in cases:
                urdf = self.mechanism.point_urdf(self._targets, x)
                cases[key] = PointCase(key, self.mechanism, urdf)
        outcomes = run_points(list(cases.values()), self.executor, self.slots)
        self.cycles += len(cases) * len(self.tables)
        for key, case in cases.items():
            outcome = outcomes[key]
            x = np.frombuffer(key, dtype=float).copy()
            if isinstance(outcome, str):
                self._cache[key] = MechanismEvaluation(x, case.urdf, None, outcome)
            else:
                self._cache[key] = MechanismEvaluation(x, case.urdf, outcome, "")
        return [self._cache[x.tobytes()] for x in points]

    def candidate(self, x: np.ndarray) -> np.ndarray:
        """A global-start point: the sample itself (no constraint is known without a run)."""
        return x

    # --- constraints ---------------------------------------------------------------------
    def margins(self, e: MechanismEvaluation) -> list[tuple[str, str, np.ndarray, float, str]]:
        """Each real constraint (module docstring): (name, unit, its margin in each table
        [unit], (M,), the margin that counts as 1 [unit], what holds)."""
        found = []
        for s in self.space.strokes:
            q = e.coordinate(s.joint)
            unit, width = ("m" if self._prismatic(e, s.joint) else "rad"), s.high - s.low
            found.append((f"stroke:{s.joint}:min", unit, q - s.low, width,
                          f"{s.joint} ≥ {s.low:g} {unit}"))  # fmt: skip
            found.append((f"stroke:{s.joint}:max", unit, s.high - q, width,
                          f"{s.joint} ≤ {s.high:g} {unit}"))  # fmt: skip
        if self.space.max_gain is not None:
            gain = self.space.max_gain
            found.append(("max_velocity_gain", "-", gain - e.peaks(GAIN), gain,
                          f"velocity gain ≤ {gain:g} (away from a singular pose)"))  # fmt: skip
        for q, limit in self.space.limits.items():
            unit = e.run.units[q]
            found.append((f"limit:{q}", unit, limit - e.peaks(q), limit,
                          f"peak {q} ≤ {limit:g} {unit}"))  # fmt: skip
        return found

    @staticmethod
    def _prismatic(e: MechanismEvaluation, joint: str) -> bool:
        return e.run.joint_units.get(joint) == "m"

    def violations(self, e: MechanismEvaluation) -> np.ndarray:
        """Every real constraint's scaled margin, per table (module docstring); ≥ 0 where met."""
        parts = [margin / scale for _, _, margin, scale, _ in self.margins(e)]
        return np.concatenate(parts) if parts else np.zeros(0)

    def case_labels(self) -> list[str]:
        """``<table>#<sample>`` of every case (sample), in order (from the model as given)."""
        run = next(e.run for e in self._cache.values() if e.run is not None)
        return [
            f"{self.tables[int(m)]}#{k}" for m, _, k in (s.partition("#") for s in run.labels())
        ]

    def constraint_names(self) -> list[str]:
        """The name of each entry of :meth:`constraints`, in order: ``stroke:<joint>:min|max``,
        ``max_velocity_gain``, ``limit:<peak>``, ``peak:<term>:<peak>``, each
        ``@<table>#<sample>``."""
        cases = self.case_labels()
        names = []
        for s in self.space.strokes:
            names += [f"stroke:{s.joint}:{end}@{c}" for end in ("min", "max") for c in cases]
        if self.space.max_gain is not None:
            names += [f"max_velocity_gain@{c}" for c in cases]
        names += [f"limit:{q}@{c}" for q in self.space.limits for c in cases]
        for term in self.objective.terms:
            names += [f"peak:{term.name}:{q}@{c}" for q in term.quantities for c in cases]
        return names

    def _all(self, e: MechanismEvaluation, t: np.ndarray) -> np.ndarray:
        return np.concatenate([self.violations(e), *self.epigraph_rows(e, t)])

    def constraints(self, z: np.ndarray) -> np.ndarray:
        """Every constraint at z, scaled; ≥ 0 where met."""
        (e,) = self.evaluate([self.physical(z)])
        return self._all(e, np.asarray(z)[len(self.lower) :])

    def steps(self, x: np.ndarray) -> np.ndarray:
        """Each variable's difference step [its unit] (module docstring), (n,)."""
        return np.array(
            [step(x[k], v.parameter.scale) for k, v in enumerate(self.space.variables)]
        )

    def constraints_jacobian(self, z: np.ndarray) -> np.ndarray:
        """d constraints / dz by central differences of full runs, (rows, n + m)."""
        z = np.asarray(z, dtype=float)
        n = len(self.lower)
        x, t = self.physical(z), z[n:]
        h = self.steps(x)
        shifted = [x + s * h[k] * np.eye(n)[k] for k in range(n) for s in (-1.0, 1.0)]
        found = self.evaluate(shifted)
        rows = len(self.constraints(z))
        jacobian = np.zeros((rows, n + len(t)))
        for k in range(n):
            below, above = shifted[2 * k], shifted[2 * k + 1]
            width = (above[k] - below[k]) / (self.upper[k] - self.lower[k])
            values = [self._all(found[2 * k + i], t) for i in (0, 1)]
            jacobian[:, k] = (values[1] - values[0]) / width
        count = len(found[0].peaks(self.objective.terms[0].quantities[0]))
        first = rows - sum(len(term.quantities) for term in self.objective.terms) * count
        for j, term in enumerate(self.objective.terms):
            jacobian[first : first + len(term.quantities) * count, n + j] = 1.0
            first += len(term.quantities) * count
        return jacobian
