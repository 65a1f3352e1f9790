"""Mobility of a closed chain at an assembled pose: degrees of freedom, redundant closure rows,
the admissible choices of independent joints, and the distance to a singular pose.

* Grübler–Kutzbach count: the tree's degrees of freedom minus the closures' scalar constraints
  (3 per point, 6 per weld, 5 per revolute cut). It assumes the constraints independent.
* The actual mobility: the tree's degrees of freedom minus the rank of the closure Jacobian. The
  difference is the number of redundant rows (a planar loop has 3 per point closure of a spatial
  count that only 2 are needed for, 5 per revolute cut of which 2 act in its plane); the forces
  along them are statically indeterminate in a rigid model.
* An independent-joint choice is admissible when the remaining (dependent) columns of the
  Jacobian determine the dependent velocities and let the chosen ones move freely
  (:class:`~feeder.chain.assembly.partition.Partition`'s rank test).
* Distance to a singular pose: the smallest singular value of the closure Jacobian's dependent
  columns relative to the largest of the whole Jacobian, and the velocity gain
  ‖J_dep⁺ J_ind‖₂ (:data:`~feeder.chain.assembly.partition.MAX_GAIN`).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from ..exceptions import InputError
from .assembly.partition import RANK_TOLERANCE, Partition
from .model.closure import ClosedChain

MAX_CHOICES = 20_000
"""Largest number of independent-joint combinations :func:`mobility` enumerates."""


@dataclass(frozen=True)
class MobilityReport:
    """Mobility of a chain at one assembled pose.

    Attributes:
        joints: Names of the tree's one-dof joints, in velocity order.
        dof: Degrees of freedom of the open tree (nv).
        constraints: Scalar closure constraints (nc).
        kutzbach: Grübler–Kutzbach mobility, dof − constraints.
        rank: Rank of the closure Jacobian.
        mobility: Actual degrees of freedom, dof − rank.
        redundant_rows: One choice of closure rows that can be dropped without changing the
            constraints (later rows repeating earlier ones). Every row that takes part in a
            redundancy has a statically indeterminate force
            (:attr:`~feeder.chain.dynamics.inverse.ChainLoads.indeterminate` lists them all).
        admissible: Independent-joint choices (tuples of ``mobility`` names) that work here.
        singular_values: Singular values of the closure Jacobian, descending.
        margin: For the choice ``independent``: smallest singular value of the dependent
            columns over the Jacobian's largest, σ_min/σ_max (0 at a singular pose), or None.
        gain: For that choice, the velocity gain (∞ at a singular pose), or None.
        independent: The choice the margin and gain refer to, or None.
    """

    joints: tuple[str, ...]
    dof: int
    constraints: int
    kutzbach: int
    rank: int
    mobility: int
    redundant_rows: tuple[str, ...]
    admissible: tuple[tuple[str, ...], ...]
    singular_values: np.ndarray
    margin: float | None
    gain: float | None
    independent: tuple[str, ...] | None

    def text(self) -> str:
        """The report as lines of text (what ``feeder analyze --check`` prints)."""
        lines = [
            f"degrees of freedom of the open tree: {self.dof} ({', '.join(self.joints)})",
            f"closure constraints: {self.constraints}; Grübler–Kutzbach mobility "
            f"{self.dof} − {self.constraints} = {self.kutzbach}",
            f"closure Jacobian rank: {self.rank}; actual mobility {self.dof} − {self.rank} = "
            f"{self.mobility}",
        ]
        if self.redundant_rows:
            lines.append(
                f"redundant closure rows ({len(self.redundant_rows)}, their forces are statically "
                f"indeterminate): {', '.join(self.redundant_rows)}"
            )
        else:
            lines.append("redundant closure rows: none")
        shown = ", ".join("[" + ", ".join(choice) + "]" for choice in self.admissible[:12])
        more = f" and {len(self.admissible) - 12} more" if len(self.admissible) > 12 else ""
        lines.append(f"admissible independent joints here: {shown or 'none'}{more}")
        if self.independent is not None:
            lines.append(
                f"with independent {list(self.independent)}: distance to singularity "
                f"σ_min/σ_max = {self.margin:.3g}, velocity gain {self.gain:.3g}"
            )
        return "\n".join(lines)


def mobility(
    chain: ClosedChain, q: np.ndarray, independent: tuple[str, ...] | list[str] | None = None
) -> MobilityReport:
    """The mobility report of ``chain`` at the assembled configuration ``q`` (nq,).

    Args:
        chain: The closed chain.
        q: An assembled configuration (the report describes the Jacobian there).
        independent: Optional choice of independent joints to report the distance to a
            singular pose for.

    Raises:
        InputError: NaN/inf or misshaped q, an unknown joint name.
    """
    model = chain.model
    q = chain.check_q(q)
    jac = chain.jacobian(q)
    joints = tuple(model.names[j] for j in range(1, model.njoints) if model.joints[j].nv == 1)
    columns = {name: chain.joint_slice(name).start for name in joints}
    singular = np.linalg.svd(jac, compute_uv=False) if jac.size else np.zeros(0)
    scale = float(singular[0]) if singular.size and singular[0] > 0.0 else 1.0
    tolerance = RANK_TOLERANCE * scale
    rank = int(np.sum(singular > tolerance))
    labels = chain.row_labels()
    redundant, kept = [], np.zeros((0, model.nv))
    for label, row in zip(labels, jac, strict=True):
        trial = np.vstack([kept, row])
        if np.linalg.matrix_rank(trial, tol=tolerance) > kept.shape[0]:
            kept = trial
        else:
            redundant.append(label)
    dof = model.nv
    free = dof - rank
    admissible = []
    if math.comb(len(joints), free) <= MAX_CHOICES:
        for choice in itertools.combinations(joints, free):
            chosen = [columns[name] for name in choice]
            others = [i for i in range(dof) if i not in chosen]
            dependent = jac[:, others]
            rank_dep = np.linalg.matrix_rank(dependent, tol=tolerance) if dependent.size else 0
            if rank_dep == len(others) == rank:
                admissible.append(choice)
    margin = gain = None
    if independent is not None:
        independent = tuple(independent)
        if len(set(independent)) != len(independent):
            raise InputError(f"independent joints must be distinct, got {list(independent)}")
        chosen = [chain.joint_slice(name).start for name in independent]
        others = [i for i in range(dof) if i not in chosen]
        dependent = jac[:, others]
        values = np.linalg.svd(dependent, compute_uv=False) if dependent.size else np.zeros(0)
        margin = float(values[len(others) - 1] / scale) if values.size >= len(others) > 0 else 0.0
        gain = Partition(chain, independent).gain(q)
    return MobilityReport(
        joints=joints,
        dof=dof,
        constraints=chain.nc,
        kutzbach=dof - chain.nc,
        rank=rank,
        mobility=free,
        redundant_rows=tuple(redundant),
        admissible=tuple(admissible),
        singular_values=singular,
        margin=margin,
        gain=gain,
        independent=independent,
    )
