"""The refusals of the assembly, worded in one place: each one line that names the loop (its
cut), the joints with their values and units (never an unlabelled q), and what to change.

Each function returns the exception for its caller to raise; ``partition`` is the
:class:`~feeder.chain.assembly.partition.Partition` whose test failed (its public attributes
only).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pinocchio as pin

from ...exceptions import InputError, SingularPoseError, UnreachablePoseError
from ..kinematics.coordinates import pose_text
from .rank import moved_joints


def loop_joints(model: pin.Model, frames: tuple[int, int]) -> frozenset[int]:
    """Ids of the joints of a closure's loop: those that carry one of its two ``frames`` (ids)
    but not the other (the tree's path between the two frames' bodies)."""
    a, b = (model.frames[f].parentJoint for f in frames)
    return frozenset((set(model.supports[a]) ^ set(model.supports[b])) - {0})


def inputs_text(partition, q: np.ndarray) -> str:
    """The independent joints' values at ``q``, labelled with their units (``this pose``
    without independent joints)."""
    model = partition.chain.model
    ids = [model.getJointId(name) for name in partition.independent_joints]
    return pose_text(model, q, ids) or "this pose"


def involved_text(partition, q: np.ndarray, names: Sequence[str]) -> str:
    """``loop <label>`` (or ``loops …``) of the loops through the joints ``names``, and those
    joints' values at ``q``, labelled with their units: ``loop a-b (j = 0.3 rad)``."""
    model = partition.chain.model
    ids = {model.getJointId(name) for name in names}
    loops = [label for label, joints in partition.loops if joints & ids]
    where = f"loop{'s' if len(loops) > 1 else ''} {', '.join(loops)}" if loops else "the tree"
    return f"{where} ({pose_text(model, q, sorted(ids))})"


def weakest_joints(partition, jac: np.ndarray, tolerance: float) -> tuple[str, ...]:
    """The dependent joints that the weakest direction of the closure Jacobian's dependent
    columns ``jac[:, dependent]`` moves (its smallest singular value above ``tolerance``: the
    motion a toggle frees), largest share first."""
    _, s, vt = np.linalg.svd(jac[:, partition.dependent], full_matrices=False)
    kept = np.flatnonzero(s > tolerance)
    motion = np.zeros(partition.chain.model.nv)
    motion[partition.dependent] = vt[kept[-1] if kept.size else -1]
    return moved_joints(partition.chain.model, motion)


def open_loop(partition, q: np.ndarray, residual: np.ndarray, tolerance: float):
    """A pose given as closed whose loops are open: the worst loop and its gap."""
    chain = partition.chain
    worst = [float(np.abs(residual[rows]).max()) for rows in chain.row_slices]
    label, joints = partition.loops[int(np.argmax(worst))]
    return UnreachablePoseError(
        f"loop {label} is open by {np.abs(residual).max():.3e} [m, rad] > {tolerance:g} at "
        f"{pose_text(chain.model, q, sorted(joints))}: not a closed pose (assemble it first)"
    )


def too_many_inputs(partition, freedom: int) -> InputError:
    """More independent joints than the ``freedom`` degrees of freedom."""
    count = len(partition.independent_joints)
    return InputError(
        f"this mechanism has {freedom} degree{'s' if freedom != 1 else ''} of freedom; "
        f"{count} independent joints given ({', '.join(partition.independent_joints)}): "
        f"make {freedom} of them independent (the file's 'independent' list)"
    )


def cannot_follow(partition, q, names, rank_full: int, rank_dep: int) -> SingularPoseError:
    """Independent joints ``names`` whose motion no dependent motion keeps closed."""
    return SingularPoseError(
        f"the dependent coordinates cannot follow the independent ones at "
        f"{inputs_text(partition, q)}: moving {', '.join(names)} opens "
        f"{involved_text(partition, q, names)} whatever the dependent joints do (closure "
        f"Jacobian rank {rank_full}, dependent part rank {rank_dep}: not an admissible "
        "choice of independent joints, or a singular pose)"
    )


def not_determined(partition, q, rank: int, names, moved: float) -> SingularPoseError:
    """A motion with the independent joints locked that moves a point by ``moved`` [m per unit
    rate]: not an idle motion."""
    return SingularPoseError(
        f"the closure does not determine the {partition.dependent.size} dependent coordinates "
        f"at {inputs_text(partition, q)}: dependent Jacobian rank {rank}; with "
        f"{list(partition.independent_joints)} locked, {', '.join(names)} can still move in "
        f"{involved_text(partition, q, names)}, up to {moved:.3g} m per unit rate: not an "
        "idle motion (too few independent joints, or a singular pose)"
    )


def near_singular(partition, q, weakest, gain: float) -> SingularPoseError:
    """A velocity gain past the partition's limit; ``weakest``: the joints the toggle frees."""
    return SingularPoseError(
        f"near a singular pose (toggle, dead centre) at {inputs_text(partition, q)}: "
        f"{', '.join(weakest)} must move up to {gain:.3g} times as fast as "
        f"{', '.join(partition.independent_joints)} in "
        f"{involved_text(partition, q, weakest)} (velocity gain {gain:.4g} > "
        f"limit {partition.max_gain:g}; {partition.gain_definition}); the loads grow without "
        "bound there"
    )


def dead_centre(partition, q_at, q, weakest, gain: float) -> SingularPoseError:
    """A continuation that cannot pass ``q`` (independent coordinates those of ``q_at``)."""
    return SingularPoseError(
        f"the motion reaches a singular pose (a dead centre, or assembly branches "
        f"meeting) at {inputs_text(partition, q_at)}, in "
        f"{involved_text(partition, q, weakest)}, velocity gain {gain:.3g}: "
        "it cannot be followed past there; end the motion before it, or choose "
        "other independent joints"
    )


def outside_limits(name: str, value: float, low: float, high: float, prescribed: bool):
    """A joint (``prescribed``: independent) whose value leaves its limits."""
    role = "prescribed" if prescribed else "dependent"
    return UnreachablePoseError(
        f"the {role} joint {name} = {value:.6g} is outside its limits "
        f"[{low:.6g}, {high:.6g}]" + ("" if prescribed else " where the loops close")
    )


def not_mounted(norm: float, gaps: Sequence[str]) -> UnreachablePoseError:
    """A mount that does not close the loops; ``gaps``: each loop's line."""
    return UnreachablePoseError(
        f"the loops do not close from the reference pose (residual {norm:.3e} after the "
        f"mount): {'; '.join(gaps)}. A loop that does not close even alone has frames its "
        "joints cannot bring together: check them in the model (an export's slip) and the "
        "side-file's pair and type; if every loop closes alone, a pose nearer the assembly "
        "(--pose) may close them together"
    )


def missed_branch(attempts: int) -> UnreachablePoseError:
    """An assembly that closed the loops only off the requested branch."""
    return UnreachablePoseError(
        f"no assembly on the requested branch found in {attempts} attempts"
    )


def not_assembled(norm: float, iterations: int, restarts: int) -> UnreachablePoseError:
    """An assembly whose every attempt stopped short of closing."""
    return UnreachablePoseError(
        f"the loop does not close at the given independent coordinates (best residual "
        f"{norm:.3e} after {iterations} damped Newton steps from the guess and from "
        f"{restarts} random guesses)"
    )


def end_of_travel(norm: float, cause: SingularPoseError) -> SingularPoseError:
    """An assembly that stops short of closing near a singular pose."""
    return SingularPoseError(
        f"the loops close only to {norm:.3e} [m, rad], near a singular pose (toggle, dead "
        "centre): the given independent coordinates are at or beyond the end of the "
        f"mechanism's travel ({cause})"
    )
