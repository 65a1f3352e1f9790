"""Mobility of a closed chain at an assembled pose: degrees of freedom, redundant closure rows,
the admissible choices of independent joints, and the distance to a singular pose.

* Grübler–Kutzbach count: the tree's degrees of freedom minus the closures' scalar constraints
  (3 per point, 6 per weld, 5 per revolute cut). It assumes the constraints independent.
* The actual mobility: the tree's degrees of freedom minus the rank of the closure Jacobian. The
  difference is the number of redundant rows (a planar loop has 3 per point closure of a spatial
  count that only 2 are needed for, 5 per revolute cut of which 2 act in its plane): as many
  self-stresses, closure forces that balance each other, and the forces of every row they
  involve are statically indeterminate in a rigid model
  (:func:`~feeder.chain.assembly.rank.self_stresses`, the computation the inverse dynamics share:
  :mod:`feeder.chain.dynamics.indeterminacy`).
* An independent-joint choice is admissible when the remaining (dependent) columns of the
  Jacobian determine the dependent velocities and let the chosen ones move freely
  (:class:`~feeder.chain.assembly.partition.Partition`'s rank test). Up to :data:`MAX_CHOICES`
  combinations of one-coordinate joints are enumerated; beyond, one admissible set is found by
  column-pivoted QR of the Jacobian (its pivots are the best-conditioned dependent columns) and
  the report says that the list is partial.
* Idle motions: the motions left with the chosen (actuated) joints locked that move no joint
  origin, frame or centre of gravity (a rod spinning about its axis); the report names the joints
  of each. The chosen joints are admissible *up to idle motions* when they determine everything
  else.
* Distance to a singular pose: the velocity gain, the largest dependent speed per unit
  independent speed, dimensionless (lengths' speeds in units of the mechanism's reach; defined
  in :mod:`feeder.chain.assembly.partition`, which refuses a pose past
  :data:`~feeder.chain.assembly.partition.MAX_GAIN`): ~1 for a linkage of comparable links
  driven by a crank, the reach over the lever arm for one driven by a cylinder, ∞ at a toggle.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from ..exceptions import SingularPoseError
from .assembly.check import idle_motions
from .assembly.newton import RANK_TOLERANCE
from .assembly.partition import Partition
from .assembly.rank import indeterminate_mask, moved_joints, self_stresses
from .kinematics.pose import ChainPose
from .model.closure import ClosedChain

NO_CLOSURE = (
    "an open tree, no closure: no dependent joint to gain speed, no singular pose of a loop"
)
"""What the reports say of the velocity gain of a mechanism without closures (its gain, 0 by
definition, would read as a distance to a singular pose)."""

MAX_CHOICES = 20_000
"""Largest number of independent-joint combinations :func:`mobility` enumerates."""


@dataclass(frozen=True)
class MobilityReport:
    """Mobility of a chain at one assembled pose.

    Attributes:
        joints: Names of the tree's one-dof joints, in velocity order.
        tree: Every joint, in velocity order, with its number of coordinates when it has
            several (``"ankle (3)"``).
        dof: Degrees of freedom of the open tree (nv).
        constraints: Scalar closure constraints (nc).
        kutzbach: Grübler–Kutzbach mobility, dof − constraints.
        rank: Rank of the closure Jacobian.
        mobility: Actual degrees of freedom, dof − rank.
        self_stresses: Number of independent self-stresses, constraints − rank (module
            docstring).
        indeterminate_rows: The closure rows they involve, whose forces are statically
            indeterminate (:func:`~feeder.chain.assembly.rank.indeterminate_mask`; the
            reactions they change: :mod:`feeder.chain.dynamics.indeterminacy`).
        admissible: Independent-joint choices (tuples of ``mobility`` names) that work here.
        complete: Whether ``admissible`` lists every choice (False: one found by column-pivoted
            QR, the enumeration being too long).
        choices: Number of combinations the complete list would have to test.
        singular_values: Singular values of the closure Jacobian, descending.
        gain: For the choice ``independent``, the velocity gain (∞ at a singular pose), or None.
        gain_definition: What the gain is and its unit (the reach it counts lengths in), or None.
        independent: The choice the gain refers to, or None.
        idle: For that choice, its idle motions: the joints each one moves, or None.
        determined: For that choice, None if it determines the mechanism up to its idle
            motions, else the reason it does not.
    """

    joints: tuple[str, ...]
    tree: tuple[str, ...]
    dof: int
    constraints: int
    kutzbach: int
    rank: int
    mobility: int
    self_stresses: int
    indeterminate_rows: tuple[str, ...]
    admissible: tuple[tuple[str, ...], ...]
    complete: bool
    choices: int
    singular_values: np.ndarray
    gain: float | None
    gain_definition: str | None
    independent: tuple[str, ...] | None
    idle: tuple[tuple[str, ...], ...] | None = None
    determined: str | None = None

    def text(self) -> str:
        """The report as lines of text (what ``feeder analyze --check`` prints)."""
        lines = [
            f"degrees of freedom of the open tree: {self.dof} ({', '.join(self.tree)})",
            f"closure constraints: {self.constraints}; Grübler–Kutzbach mobility "
            f"{self.dof} − {self.constraints} = {self.kutzbach}",
            f"closure Jacobian rank: {self.rank}; actual mobility {self.dof} − {self.rank} = "
            f"{self.mobility}",
        ]
        if self.self_stresses:
            lines.append(
                f"self-stresses of the closures: {self.self_stresses}; statically indeterminate "
                f"closure rows ({len(self.indeterminate_rows)}, the rows they involve): "
                f"{', '.join(self.indeterminate_rows)}"
            )
        else:
            lines.append(
                "self-stresses of the closures: none; statically indeterminate rows: none"
            )
        shown = ", ".join("[" + ", ".join(choice) + "]" for choice in self.admissible[:12])
        more = f" and {len(self.admissible) - 12} more" if len(self.admissible) > 12 else ""
        if self.complete:
            lines.append(f"admissible independent joints here: {shown or 'none'}{more}")
        else:
            lines.append(
                f"admissible independent joints here (partial list: one set found by "
                f"column-pivoted QR, of {self.choices} combinations not enumerated): "
                f"{shown or 'none'}"
            )
        if self.independent is not None:
            if self.determined is None:
                count = len(self.idle or ())
                gain = (
                    f"velocity gain {self.gain:.3g} ({self.gain_definition}; → ∞ at a singular "
                    "pose)"
                    if self.constraints
                    else f"no velocity gain: {NO_CLOSURE}"
                )
                lines.append(
                    f"with independent {list(self.independent)}: determined "
                    + (f"up to {count} idle motion(s)" if count else "(no idle motion)")
                    + f"; {gain}"
                )
            else:
                lines.append(f"with independent {list(self.independent)}: {self.determined}")
            for k, joints in enumerate(self.idle or (), start=1):
                lines.append(
                    f"  idle motion {k} (free with them locked, moves no joint origin, frame or "
                    f"centre of gravity): {', '.join(joints)}"
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
    pose = ChainPose(chain, q)  # its Jacobian computed once, for the report and the checks
    jac = pose.jacobian
    joints = tuple(model.names[j] for j in range(1, model.njoints) if model.joints[j].nv == 1)
    columns = {name: chain.joint_slice(name).start for name in joints}
    singular = np.linalg.svd(jac, compute_uv=False) if jac.size else np.zeros(0)
    scale = float(singular[0]) if singular.size and singular[0] > 0.0 else 1.0
    tolerance = RANK_TOLERANCE * scale
    rank = int(np.sum(singular > tolerance))
    stresses = self_stresses(jac)
    flags = indeterminate_mask(stresses)
    rows = tuple(label for label, flag in zip(chain.row_labels(), flags, strict=True) if flag)
    dof = model.nv
    free = dof - rank
    choices = math.comb(len(joints), free)
    admissible = []
    if choices <= MAX_CHOICES:
        for choice in itertools.combinations(joints, free):
            chosen = [columns[name] for name in choice]
            others = [i for i in range(dof) if i not in chosen]
            dependent = jac[:, others]
            rank_dep = np.linalg.matrix_rank(dependent, tol=tolerance) if dependent.size else 0
            if rank_dep == len(others) == rank:
                admissible.append(choice)
    else:
        admissible = _pivoted_choice(jac, joints, columns, rank, tolerance)
    gain = definition = idle = determined = None
    if independent is not None:
        independent = tuple(independent)
        partition = Partition(chain, independent)
        try:  # the idle-motion test first: its refusal is the one reported when both fail
            motions = idle_motions(partition, pose)
            gain = partition.check_pose(pose).gain
        except SingularPoseError as exc:
            determined = str(exc)
            motions = np.zeros((0, dof))
            gain = partition.gain(q)  # also past the partition's limit
        idle = tuple(moved_joints(model, motion) for motion in localised(motions)[0])
        definition = partition.gain_definition
    tree = tuple(
        model.names[j] + (f" ({model.joints[j].nv})" if model.joints[j].nv != 1 else "")
        for j in range(1, model.njoints)
    )
    return MobilityReport(
        joints=joints,
        tree=tree,
        dof=dof,
        constraints=chain.nc,
        kutzbach=dof - chain.nc,
        rank=rank,
        mobility=free,
        self_stresses=stresses.shape[0],
        indeterminate_rows=rows,
        admissible=tuple(admissible),
        complete=choices <= MAX_CHOICES,
        choices=choices,
        singular_values=singular,
        gain=gain,
        gain_definition=definition,
        independent=independent,
        idle=idle,
        determined=determined,
    )


def _pivoted_choice(jac, joints, columns, rank, tolerance) -> list[tuple[str, ...]]:
    """One admissible choice: the columns left out by the first ``rank`` pivots of the
    column-pivoted QR of the one-coordinate joints' columns (the best-conditioned dependent
    set), if they determine the rest."""
    index = [columns[name] for name in joints]
    pivots = _pivots(jac[:, index])
    dependent = set(pivots[:rank].tolist())
    choice = tuple(name for k, name in enumerate(joints) if k not in dependent)
    others = [i for i in range(jac.shape[1]) if i not in {columns[name] for name in choice}]
    part = jac[:, others]
    rank_dep = np.linalg.matrix_rank(part, tol=tolerance) if part.size else 0
    return [choice] if rank_dep == len(others) == rank else []


def localised(motions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The same span as ``motions`` (k, nv), each row with a unit entry at its own pivot joint and
    zeros at the others' (reduced row echelon form on column-pivoted QR pivots): each idle
    motion then involves as few joints as the span allows; and the pivots' velocity indices
    (k,)."""
    if motions.shape[0] == 0:
        return motions, np.zeros(0, dtype=int)
    pivots = _pivots(motions)
    chosen = pivots[: motions.shape[0]]
    return np.linalg.solve(motions[:, chosen], motions), chosen


def _pivots(matrix: np.ndarray) -> np.ndarray:
    """The column order of ``matrix``'s column-pivoted QR (SciPy's; imported here, so that
    reading or building a chain does not load scipy.linalg)."""
    import scipy.linalg

    return scipy.linalg.qr(matrix, pivoting=True, mode="economic")[2]
