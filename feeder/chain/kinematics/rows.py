"""The closure rows along a batched motion: their Jacobian, error, rate and acceleration at every
sample at once (numpy; each closure's rows are its cut's, :mod:`feeder.chain.model.cuts`, fed with
the two frames' motion from the tree's, :mod:`.tree`)."""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np
import pinocchio as pin

from ..model.closure import ClosedChain
from ..model.cuts import CutFrames
from .layout import tree_layout
from .tree import TreeMotion, frame_acceleration, frame_placements, point_jacobians


@dataclass(frozen=True)
class ClosureKinematics:
    """The closure rows along a motion, N samples.

    Attributes:
        jacobian: J, (N, nc, nv) ((N, nc, 0) when skipped). residual: the rows' position
            error, (N, nc).
        rate, acceleration: The rows' first and second time derivatives, (N, nc).
        frames: Per closure, its two frames' placements and motion
            (:class:`~feeder.chain.model.cuts.CutFrames`, without their Jacobians): what its
            cut makes its reaction wrench from.
        hinge_alignment: Label → cosine (N,) between the two axes of each cut that has them
            (a revolute cut: u_a · u_b of its hinge axes; 1 assembled, −1 upside down).
    """

    jacobian: np.ndarray
    residual: np.ndarray
    rate: np.ndarray
    acceleration: np.ndarray
    frames: list[CutFrames]
    hinge_alignment: dict[str, np.ndarray]

    def at(self, index: np.ndarray) -> ClosureKinematics:
        """The position-level rows at the samples ``index`` (M,): the Jacobian, the residual
        and the cuts' frames' placements (the rates, the accelerations and the frames' motion
        left zero or out: what the self-stresses and their wrenches read,
        :mod:`~feeder.chain.dynamics.indeterminacy`)."""
        frames = [
            CutFrames(
                f.rotation_a[index], f.rotation_b[index], f.origin_a[index], f.origin_b[index]
            )
            for f in self.frames
        ]
        zero = np.zeros((index.size, self.residual.shape[1]))
        return ClosureKinematics(
            self.jacobian[index],
            self.residual[index],
            zero,
            zero,
            frames,
            {label: cosine[index] for label, cosine in self.hinge_alignment.items()},
        )


def cut_frames(
    model: pin.Model,
    motion: TreeMotion,
    pairs: list[tuple[int, int]],
    columns: list[np.ndarray],
    jacobians: bool,
    rates: bool,
) -> CutFrames:
    """The frames (a, b) of K cuts (``pairs`` of frame ids) as one :class:`CutFrames` of K N
    samples, cut by cut (cut k's are samples k N … (k + 1) N − 1): placements, and if asked
    their Jacobians on each cut's velocity columns (``columns[k]``, sorted, among them every
    column that moves either frame; padded with zero columns to the widest, C: (K N, 6, C))
    and their velocities and accelerations; every frame of every cut in one set of array
    operations."""
    count, n = len(pairs), motion.origin.shape[1]
    ids = [a for a, _ in pairs] + [b for _, b in pairs]

    def split(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(2K, N, …) of the frames a then b → (K N, …) of a and of b (views)."""
        shape = (count * n, *values.shape[2:])
        return values[:count].reshape(shape), values[count:].reshape(shape)

    rotation, origin = frame_placements(model, motion, ids)
    frames = CutFrames(*split(rotation), *split(origin))
    if jacobians:
        jacobian = point_jacobians(model, motion, ids, columns + columns, origin)
        frames.jacobian_a, frames.jacobian_b = split(jacobian)
    else:  # no columns
        frames.jacobian_a = frames.jacobian_b = np.zeros((count * n, 6, 0))
    if rates:
        joints = [model.frames[f].parentJoint for f in ids]
        frames.omega_a, frames.omega_b = split(motion.omega[joints])
        frames.alpha_a, frames.alpha_b = split(motion.alpha[joints])
        acceleration = frame_acceleration(model, motion, ids, origin)
        frames.acceleration_a, frames.acceleration_b = split(acceleration)
    return frames


def _cut_groups(chain: ClosedChain) -> list[list[int]]:
    """The chain's cuts (indices) grouped by kind and axes: the cuts whose rows one set of
    array operations computes (an N-four-bar's N point cuts are one group)."""
    groups: dict[tuple, list[int]] = {}
    for i, cut in enumerate(chain.cuts):
        key = (type(cut), tuple(cut.axis), tuple(cut.axis_b))
        groups.setdefault(key, []).append(i)
    return list(groups.values())


def _by_cut(values: np.ndarray, count: int) -> np.ndarray:
    """Values (K N, …) of K cuts, cut by cut (:func:`cut_frames`) → (N, K, …)."""
    return np.moveaxis(values.reshape(count, -1, *values.shape[1:]), 0, 1)


def _cut_samples(frames: CutFrames, samples: slice) -> CutFrames:
    """One cut's ``samples`` of stacked frames (views; its rows' derived values too), without
    the Jacobians: what its reaction wrench is made from."""
    values = {
        f.name: getattr(frames, f.name)
        for f in fields(CutFrames)
        if f.name not in ("jacobian_a", "jacobian_b", "derived")
    }
    return CutFrames(
        **{name: None if x is None else x[samples] for name, x in values.items()},
        derived={name: x[samples] for name, x in frames.derived.items()},
    )


def closure_kinematics(
    chain: ClosedChain, motion: TreeMotion, v: np.ndarray | None = None, with_jacobian: bool = True
) -> ClosureKinematics:
    """Every closure row's Jacobian, error, rate and acceleration along a batched motion with
    velocities v (N, nv); without v, at rest (a position-level pass: rates and accelerations
    zero, not computed). ``with_jacobian=False`` skips the Jacobian and the rates (zero)
    where only the accelerations are wanted. The cuts of one kind and axes are computed
    together (:func:`cut_frames`)."""
    model = chain.model
    n = motion.origin.shape[1]
    # one row more than nc: the padding of the cuts' columns lands there, and is dropped
    jacobian = np.zeros((n, chain.nc + 1, model.nv if with_jacobian else 0))
    residual = np.zeros((n, chain.nc))
    acceleration = np.zeros((n, chain.nc))
    kept: list[CutFrames | None] = [None] * len(chain.cuts)
    cosines: dict[int, np.ndarray] = {}
    layout = tree_layout(model)
    for group in _cut_groups(chain):
        cut, count = chain.cuts[group[0]], len(group)
        pairs = [chain.frame_ids[i] for i in group]
        columns = [
            layout.columns(model.frames[a].parentJoint, model.frames[b].parentJoint)
            for a, b in pairs
        ]
        frames = cut_frames(model, motion, pairs, columns, with_jacobian, v is not None)
        rows = np.array(
            [np.arange(chain.row_slices[i].start, chain.row_slices[i].stop) for i in group]
        )
        if with_jacobian:
            place = np.zeros((count, 1, frames.jacobian_a.shape[2]), int)
            target = np.broadcast_to(rows[:, :, None], (count, cut.rows, place.shape[2])).copy()
            for k, own in enumerate(columns):
                place[k, 0, : own.size] = own
                target[k, :, own.size :] = chain.nc  # the padding: the dropped row
            jacobian[:, target, place] = _by_cut(cut.jacobian(frames), count)
        residual[:, rows] = _by_cut(cut.residual(frames), count)
        if v is not None:
            acceleration[:, rows] = _by_cut(cut.acceleration(frames), count)
        cosine = cut.alignment(frames)
        for k, i in enumerate(group):
            samples = slice(k * n, (k + 1) * n)
            if cosine is not None:
                cosines[i] = cosine[samples]
            kept[i] = _cut_samples(frames, samples)
    jacobian = jacobian[:, : chain.nc]
    rate = (
        np.einsum("ncv,nv->nc", jacobian, v)
        if v is not None and with_jacobian
        else np.zeros((n, chain.nc))
    )
    alignment = {chain.cuts[i].label: cosines[i] for i in sorted(cosines)}
    return ClosureKinematics(jacobian, residual, rate, acceleration, kept, alignment)
