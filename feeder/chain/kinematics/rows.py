"""The closure rows along a batched motion: their Jacobian, error, rate and acceleration at every
sample at once (numpy; each closure's rows are its cut's, :mod:`feeder.chain.model.cuts`, fed with
the two frames' motion from the tree's, :mod:`.tree`)."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import pinocchio as pin

from ..model.closure import ClosedChain
from ..model.cuts import CutFrames
from .layout import tree_layout
from .tree import TreeMotion, frame_acceleration, frame_placements, point_jacobian


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

    def at(self, index: np.ndarray, jacobian: bool = True) -> ClosureKinematics:
        """The position-level rows at the samples ``index`` (M,): the Jacobian (if
        ``jacobian``; else none, as a pass without it), the residual and the cuts' frames'
        placements (the rates, the accelerations and the frames' motion left zero or out: what
        the self-stresses and their wrenches read, :mod:`~feeder.chain.dynamics.indeterminacy`)."""
        frames = [
            CutFrames(
                f.rotation_a[index], f.rotation_b[index], f.origin_a[index], f.origin_b[index]
            )
            for f in self.frames
        ]
        zero = np.zeros((index.size, self.residual.shape[1]))
        return ClosureKinematics(
            self.jacobian[index] if jacobian else np.zeros((index.size, zero.shape[1], 0)),
            self.residual[index],
            zero,
            zero,
            frames,
            {label: cosine[index] for label, cosine in self.hinge_alignment.items()},
        )


def cut_frames(
    model: pin.Model,
    motion: TreeMotion,
    a: int,
    b: int,
    jacobians: bool,
    rates: bool,
    columns: np.ndarray | None = None,
) -> CutFrames:
    """Frames a and b of a cut along a batched motion: placements, and if asked their
    Jacobians (``jacobians``; on the velocity ``columns`` only, if given: sorted, among them
    every column that moves either frame) and velocities and accelerations (``rates``)."""
    (rot_a, rot_b), (p_a, p_b) = placed = frame_placements(model, motion, (a, b))
    frames = CutFrames(rot_a, rot_b, p_a, p_b)
    if jacobians:
        frames.jacobian_a = point_jacobian(model, motion, a, columns, p_a)
        frames.jacobian_b = point_jacobian(model, motion, b, columns, p_b)
    else:  # no columns
        frames.jacobian_a = frames.jacobian_b = np.zeros((p_a.shape[0], 6, 0))
    if rates:
        ja, jb = model.frames[a].parentJoint, model.frames[b].parentJoint
        frames.omega_a, frames.omega_b = motion.omega[ja], motion.omega[jb]
        frames.alpha_a, frames.alpha_b = motion.alpha[ja], motion.alpha[jb]
        acceleration = frame_acceleration(model, motion, (a, b), placed[1])
        frames.acceleration_a, frames.acceleration_b = acceleration
    return frames


def closure_kinematics(
    chain: ClosedChain, motion: TreeMotion, v: np.ndarray | None = None, with_jacobian: bool = True
) -> ClosureKinematics:
    """Every closure row's Jacobian, error, rate and acceleration along a batched motion with
    velocities v (N, nv); without v, at rest (a position-level pass: rates and accelerations
    zero, not computed). ``with_jacobian=False`` skips the Jacobian and the rates (zero)
    where only the accelerations are wanted."""
    model = chain.model
    n = motion.origin[0].shape[0]
    jacobian = np.zeros((n, chain.nc, model.nv if with_jacobian else 0))
    residual = np.zeros((n, chain.nc))
    acceleration = np.zeros((n, chain.nc))
    kept, alignment = [], {}
    layout = tree_layout(model)
    for cut, rows, (a, b) in zip(chain.cuts, chain.row_slices, chain.frame_ids, strict=True):
        columns = layout.columns(model.frames[a].parentJoint, model.frames[b].parentJoint)
        frames = cut_frames(model, motion, a, b, with_jacobian, v is not None, columns)
        if with_jacobian:
            jacobian[:, rows][:, :, columns] = cut.jacobian(frames)
        residual[:, rows] = cut.residual(frames)
        if v is not None:
            acceleration[:, rows] = cut.acceleration(frames)
        cosine = cut.alignment(frames)
        if cosine is not None:
            alignment[cut.label] = cosine
        kept.append(replace(frames, jacobian_a=None, jacobian_b=None))
    rate = (
        np.einsum("ncv,nv->nc", jacobian, v)
        if v is not None and with_jacobian
        else np.zeros((n, chain.nc))
    )
    return ClosureKinematics(jacobian, residual, rate, acceleration, kept, alignment)
