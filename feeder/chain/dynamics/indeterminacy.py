"""Statically indeterminate loads: which closure rows, and which components of the cuts' wrenches
and of the joints' reactions, a rigid model does not determine.

A closed chain whose closure Jacobian J (nc × nv) has rank r < nc has k = nc − r *self-stresses*:
closure forces λ_s with Jᵀ λ_s = 0 (:func:`~feeder.chain.assembly.rank.self_stresses`). Added to
any solution of the loads' equations they change no generalized force and no drive load, so the
equations of a rigid model cannot tell how much of them the cuts carry. What they change is
indeterminate:

* the closure rows they involve (:func:`~feeder.chain.assembly.rank.indeterminate_mask`: the
  part of the row's unit vector in their span is not zero beyond round-off);
* the components (world axes) of each cut's wrench and of each joint's reaction that the
  self-stresses alone change: the wrenches they transmit, from the backward Newton–Euler pass of
  :mod:`.newton_euler` at rest, without gravity, with a self-stress as the only load — a component
  above :data:`CHANGE_TOLERANCE` of the largest such wrench (forces in N, moments over the
  mechanism's reach) is listed.

The values the tables give for them are one choice: the closure forces of minimum ‖K^(−1/2) λ‖
(:data:`~feeder.chain.dynamics.inverse.CONVENTION`, K the per-row ``stiffness`` of the
mechanism file, default 1) — what elastic supports of those relative stiffnesses would share,
and what a change of K moves (docs/ENGINE.md, "Indeterminate loads").

:func:`indeterminacy` is the one computation every report uses: ``feeder analyze --check`` at the
assembled pose, and the inverse dynamics along a motion (:attr:`ChainLoads.indeterminacy`: the
union over a subsample, computed when first asked), which the summaries and the tables' sidecar
list (``indeterminate.txt``) of ``feeder analyze`` and ``feeder simulate`` print.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..assembly.rank import indeterminate_mask, self_stress_bases
from ..blas import one_blas_thread
from ..kinematics.layout import tree_layout
from ..kinematics.rows import ClosureKinematics, closure_kinematics
from ..kinematics.tree import TreeMotion, cross, reach, tree_motion
from ..model.closure import ClosedChain
from ..model.cuts import CutFrames

COMPONENTS = ("force_x", "force_y", "force_z", "moment_x", "moment_y", "moment_z")
"""The wrench components a cut's or joint's entry of :class:`Indeterminacy` names (world axes;
the tables' column suffixes)."""

CHANGE_TOLERANCE = 1e-6
"""A wrench component changes under a self-stress when it exceeds this share of the largest
component any self-stress gives (moments divided by the mechanism's reach): the backward pass
adds products of unit-size terms, its round-off is ~1e-15 of that scale; a component is as
small as the rows' shares are at a pose near a symmetric one, which
:data:`~feeder.chain.assembly.rank.SELF_STRESS_TOLERANCE` (the same value) ignores."""

SUBSAMPLE = 32
"""Samples of a motion on which the self-stresses are computed (their structure changes only at
isolated singular poses)."""


@dataclass(frozen=True)
class Indeterminacy:
    """What a rigid model leaves undetermined (module docstring).

    Attributes:
        self_stresses: The number of independent self-stresses (the most over the samples).
        rows: Labels of the closure rows they involve (:meth:`ClosedChain.row_labels`).
        closures: Closure label → the components of its wrench they change (:data:`COMPONENTS`).
        joints: Joint name → the components of its reaction they change.
    """

    self_stresses: int
    rows: tuple[str, ...]
    closures: dict[str, tuple[str, ...]]
    joints: dict[str, tuple[str, ...]]

    def lines(self, convention: str, rows: bool = True) -> list[str]:
        """The summary lines: the rows (if ``rows``; the mobility report lists them at one
        pose), the cuts' and joints' wrench components, and how their values were chosen
        (``convention``); none when everything is determined."""
        if not self.self_stresses:
            return []

        def named(entries: dict[str, tuple[str, ...]]) -> str:
            return "; ".join(f"{name} ({', '.join(parts)})" for name, parts in entries.items())

        lines = [
            f"statically indeterminate under the {self.self_stresses} self-stress(es) of the "
            "closures (a rigid model does not determine them):"
        ]
        if rows:
            lines.append(f"  closure rows {', '.join(self.rows)}")
        if self.joints:
            lines.append(f"  joint reactions' components {named(self.joints)}")
        if self.closures:
            lines.append(f"  cuts' wrench components {named(self.closures)}")
        lines.append(f"  the values given: {convention}")
        return lines


@dataclass(frozen=True)
class PoseKinematics:
    """The tree's placements and the closure rows (with their Jacobian) at the closed poses
    :func:`subsample` picks of a motion: what :func:`indeterminacy` reads, which the inverse
    dynamics compute anyway (:attr:`~feeder.chain.dynamics.inverse.ChainLoads.kinematics`).

    Attributes:
        motion: Their placements (:meth:`TreeMotion.at_rest`).
        rows: Their closure rows (:meth:`ClosureKinematics.at`).
    """

    motion: TreeMotion
    rows: ClosureKinematics


def _largest_components(
    chain: ClosedChain,
    poses: TreeMotion,
    rows: ClosureKinematics,
    lam: np.ndarray,
    index: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """The largest force and moment components (world axes; N, N·m) of each cut's wrench and of
    each joint's reaction under the self-stresses ``lam`` (S, nc), self-stress s acting at the
    pose ``index[s]`` of ``poses`` and ``rows``: (cuts, 2, 3) and (njoints, 2, 3). What the
    backward pass of :mod:`.newton_euler` at rest gives with a self-stress as the only load
    (the cut's wrench, and its opposite, on the two frames' bodies, each joint transmitting
    minus the sum of those of the frames it carries, moments about its origin), written for a
    few loads of many: each cut is evaluated where its rows carry force, and each joint sums
    the terms of the frames it carries at those samples only."""
    model = chain.model
    layout = tree_layout(model)
    count = lam.shape[0]
    cuts = np.zeros((len(chain.cuts), 2, 3))
    parts: list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]] = []
    for c, (cut, span, pair, frames) in enumerate(
        zip(chain.cuts, chain.row_slices, chain.frame_ids, rows.frames, strict=True)
    ):
        acting = np.flatnonzero(np.any(lam[:, span] != 0.0, axis=1))
        if not acting.size:
            continue
        pose = index[acting]
        placed = CutFrames(
            frames.rotation_a[pose], frames.rotation_b[pose], frames.origin_a[pose],
            frames.origin_b[pose],
        )  # fmt: skip
        force, moment = cut.wrench(placed, lam[acting][:, span])
        cuts[c] = np.abs(force).max(axis=0), np.abs(moment).max(axis=0)
        for frame, origin, sign in zip(
            pair, (placed.origin_a, placed.origin_b), (-1.0, 1.0), strict=True
        ):
            for j in layout.ancestors[model.frames[frame].parentJoint]:
                lever = origin - poses.origin[j, pose]  # the joint's origin → the frame's
                turning = moment + cross(lever, force)
                parts.append((j * count + acting, sign * force, sign * turning))
    peaks = np.zeros((model.njoints, 2, 3))
    if parts:
        keys = np.concatenate([key for key, _, _ in parts])
        values = np.concatenate([np.hstack([f, m]) for _, f, m in parts])  # (E, 6)
        keys, where = np.unique(keys, return_inverse=True)  # one per joint and sample
        sums = np.zeros((keys.size, 6))
        for k in range(6):
            sums[:, k] = np.bincount(where, values[:, k], keys.size)
        largest = np.zeros((model.njoints, 6))
        np.maximum.at(largest, keys // count, np.abs(sums))
        peaks = largest.reshape(-1, 2, 3)
    return cuts, peaks


def subsample(count: int) -> np.ndarray:
    """The samples (indices) of a motion of ``count`` samples on which :func:`indeterminacy`
    computes the self-stresses: at most about :data:`SUBSAMPLE`, evenly spread."""
    return np.arange(0, count, max(1, count // SUBSAMPLE))


@one_blas_thread
def indeterminacy(
    chain: ClosedChain,
    q: np.ndarray,
    size: float | None = None,
    kinematics: PoseKinematics | None = None,
) -> Indeterminacy:
    """The indeterminate rows and wrench components (module docstring) at the closed poses q
    (N, nq) (trusted): the union over the poses, computed on those of :func:`subsample` (the
    self-stresses of all of them at once: :func:`~feeder.chain.assembly.rank.
    self_stress_bases`; the wrenches every self-stress makes the cuts and joints transmit, from
    the poses' placements: :func:`_largest_components`).

    Args:
        size: The mechanism's reach [m] at its neutral pose, if the caller has it
            (:attr:`~feeder.chain.assembly.partition.Partition.length`); measured otherwise.
        kinematics: The kinematics of the poses q[subsample(N)], if the caller has them (the
            inverse dynamics do: the same values); computed when absent.
    """
    model = chain.model
    if kinematics is not None:
        poses, rows = kinematics.motion, kinematics.rows
    else:
        poses = tree_motion(model, q[subsample(q.shape[0])])
        rows = closure_kinematics(chain, poses)
    bases = self_stress_bases(rows.jacobian)
    count = max((basis.shape[0] for basis in bases), default=0)
    if count == 0:
        return Indeterminacy(0, (), {}, {})
    sizes = np.array([basis.shape[0] for basis in bases])
    index = np.repeat(np.arange(sizes.size), sizes)
    lam = np.vstack(bases)  # one sample per self-stress, at its pose
    within = np.arange(index.size) - np.repeat(np.cumsum(sizes) - sizes, sizes)
    padded = np.zeros((sizes.size, count, lam.shape[1]))  # every pose's basis, zero rows added
    padded[index, within] = lam
    mask = indeterminate_mask(padded).any(axis=0)  # any pose's rows
    labels = chain.row_labels()
    cuts, peaks = _largest_components(chain, poses, rows, lam, index)
    if size is None:
        size = reach(model, pin.neutral(model)[None])
    # each cut's and joint's largest force and moment components over the self-stresses (6,)
    cuts[:, 1] /= size
    peaks[:, 1] /= size
    largest = {cut.label: peak for cut, peak in zip(chain.cuts, cuts.reshape(-1, 6), strict=True)}
    joints = [j for j in range(1, model.njoints) if model.joints[j].nv != 6]  # free-flyers: none
    largest |= {model.names[j]: peaks[j].reshape(6) for j in joints}
    scale = max(float(x.max()) for x in largest.values())

    def changed(names) -> dict[str, tuple[str, ...]]:
        out = {}
        for name in names:
            moved = largest[name] > CHANGE_TOLERANCE * scale
            if moved.any():
                out[name] = tuple(c for c, flag in zip(COMPONENTS, moved, strict=True) if flag)
        return out

    return Indeterminacy(
        self_stresses=count,
        rows=tuple(label for label, flag in zip(labels, mask, strict=True) if flag),
        closures=changed(cut.label for cut in chain.cuts),
        joints=changed(model.names[j] for j in joints),
    )
