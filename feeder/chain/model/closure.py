"""A kinematic tree plus rigid loop closures, for any URDF: each closure typed by its cut.

A :class:`Closure` names two frames, ``frame_a`` and ``frame_b``, that coincide (or turn about a
common axis) when the loop is assembled, and the kind of joint that was cut to open the loop:
one of :data:`~feeder.chain.model.cuts.KINDS` (``point``, ``weld``, ``revolute``), whose class
in :mod:`feeder.chain.model.cuts` owns the rows, their derivatives and Pinocchio's constraints.
:class:`ClosedChain` stacks the rows of its closures and evaluates them on Pinocchio's data.

A planar loop closed in its plane has redundant rows (the out-of-plane force, the two tilting
moments of a revolute cut): the closure Jacobian is rank-deficient everywhere, and every solve
here is rank-revealing, so redundancy is harmless; :mod:`feeder.chain.mobility` reports it and
:mod:`feeder.chain.dynamics.inverse` flags the indeterminate force components.
"""

from __future__ import annotations

import difflib
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ...exceptions import ClosureFrameError, InputError
from ...validation import check_vector
from .cuts import KINDS, Cut, CutFrames
from .jacobians import frame_jacobian


@dataclass(frozen=True)
class Closure:
    """One loop closure: two frames joined by the cut joint.

    Attributes:
        frame_a, frame_b: Names of the two frames (links or fixed-joint frames of the URDF),
            on different bodies.
        kind: One of :data:`~feeder.chain.model.cuts.KINDS`: ``"point"``, ``"weld"`` or
            ``"revolute"`` (:mod:`feeder.chain.model.cuts`).
        axis: Revolute only: the hinge axis in frame a's axes (unit vector, (3,)).
        axis_b: Revolute only: the hinge axis in frame b's axes (default: ``axis``).
        name: Label for reports (default ``frame_a-frame_b``).
    """

    frame_a: str
    frame_b: str
    kind: str = "point"
    axis: tuple[float, float, float] = (0.0, 0.0, 1.0)
    axis_b: tuple[float, float, float] | None = None
    name: str = ""

    @property
    def label(self) -> str:
        """The closure's name in reports."""
        return self.name or f"{self.frame_a}-{self.frame_b}"

    @property
    def rows(self) -> int:
        """Number of scalar constraints."""
        return len(KINDS[self.kind].labels)


def as_closure(spec: Closure | Sequence[str]) -> Closure:
    """A :class:`Closure` from itself or from a pair of frame names (a point closure).

    Raises:
        InputError: Anything else, an unknown kind, or a zero or non-finite axis.
    """
    if isinstance(spec, Closure):
        closure = spec
    elif (
        not isinstance(spec, str | bytes)
        and isinstance(spec, Sequence)
        and len(spec) == 2
        and all(isinstance(name, str) for name in spec)
    ):
        closure = Closure(spec[0], spec[1])
    else:
        raise InputError(f"a closure must be a Closure or a pair of frame names, got {spec!r}")
    names = (closure.frame_a, closure.frame_b)
    if not all(isinstance(name, str) and name for name in names):
        raise InputError(f"closure frames must be two non-empty names, got {names!r}")
    if closure.kind not in KINDS:
        raise InputError(
            f"closure {closure.label!r}: kind must be one of {sorted(KINDS)}, got {closure.kind!r}"
        )
    axes = {
        "axis": closure.axis,
        "axis_b": closure.axis if closure.axis_b is None else closure.axis_b,
    }
    unit = {}
    for name, value in axes.items():
        vector = check_vector(f"closure {closure.label!r}: {name}", value, 3)
        norm = float(np.linalg.norm(vector))
        if not norm > 1e-12:
            raise InputError(f"closure {closure.label!r}: {name} must not be zero, got {value!r}")
        unit[name] = tuple(float(x) for x in vector / norm)
    return Closure(
        closure.frame_a, closure.frame_b, closure.kind, unit["axis"], unit["axis_b"], closure.name
    )


def repeated_cut(pairs: Sequence[Sequence[str]]) -> tuple[int, int] | None:
    """Positions (i, j), i < j, of the first two cuts that join the same two frames, in either
    order, among ``pairs`` of frame names; None if there are none.

    One loop listed twice would be taken as two cuts of one joint: their forces are then
    indeterminate, and whatever split the solver picks between them is no load of the joint.
    """
    seen: dict[tuple[str, ...], int] = {}
    for j, pair in enumerate(pairs):
        key = tuple(sorted(pair))
        if key in seen:
            return seen[key], j
        seen[key] = j
    return None


class ClosedChain:
    """Pinocchio model and data of a kinematic tree with rigid loop closures.

    Attributes:
        model: Pinocchio model of the open tree.
        data: Its data, reused by every method (each method runs the forward kinematics it
            needs first, so the data always match the last call's arguments).
        closures: The closures, checked (:class:`Closure`).
        cuts: Per closure, its cut (:class:`~feeder.chain.model.cuts.Cut` of its kind), which
            owns its rows.
        frame_ids: Pinocchio frame ids (a, b) of each closure.
        row_slices: Per closure, its rows' slice in the stacked closure rows.
        constraint_models: Pinocchio ``RigidConstraintModel`` s of the closures (one or more per
            cut, :mod:`feeder.chain.model.cuts`), in closure order.
        constraint_datas: Their data.
    """

    def __init__(self, model: pin.Model, closures: Sequence[Closure | Sequence[str]]):
        if isinstance(closures, str | bytes) or not isinstance(closures, Sequence):
            raise InputError(f"closures must be a sequence of closures, got {closures!r}")
        self.model = model
        self.data = model.createData()
        self.closures = tuple(as_closure(c) for c in closures)
        labels = [closure.label for closure in self.closures]
        repeated = repeated_cut([(c.frame_a, c.frame_b) for c in self.closures])
        if repeated is not None:
            i, j = repeated
            raise InputError(
                f"closures #{i + 1} ({labels[i]}) and #{j + 1} ({labels[j]}) join the same "
                "frames: one loop given twice is not two cuts; give it once"
            )
        if len(set(labels)) != len(labels):
            raise InputError(
                f"closure names must be distinct (name= tells them apart), got {labels}"
            )
        self.frame_ids: list[tuple[int, int]] = []
        self.cuts: tuple[Cut, ...] = tuple(
            KINDS[c.kind](c.label, c.axis, c.axis_b) for c in self.closures
        )
        self.constraint_models = pin.StdVec_RigidConstraintModel()
        for closure, cut in zip(self.closures, self.cuts, strict=True):
            for name in (closure.frame_a, closure.frame_b):
                if not model.existFrame(name):
                    raise ClosureFrameError(
                        f"closure frame {name!r} is not in model {model.name!r}; "
                        f"frames: {[f.name for f in model.frames]}"
                    )
            ids = (model.getFrameId(closure.frame_a), model.getFrameId(closure.frame_b))
            fa, fb = (model.frames[i] for i in ids)
            if fa.parentJoint == fb.parentJoint:
                raise InputError(
                    f"closure ({closure.frame_a!r}, {closure.frame_b!r}) joins two frames on the "
                    f"same body (joint {model.names[fa.parentJoint]!r}): it closes no loop"
                )
            self.frame_ids.append(ids)
            for constraint in cut.constraint_models(model, fa, fb):
                self.constraint_models.append(constraint)
        self.constraint_datas = pin.StdVec_RigidConstraintData()
        for constraint in self.constraint_models:
            self.constraint_datas.append(constraint.createData())
        self.row_slices = []
        start = 0
        for cut in self.cuts:
            self.row_slices.append(slice(start, start + cut.rows))
            start += cut.rows

    def corrected_constraints(
        self, data: pin.Data, rate: float
    ) -> tuple[pin.StdVec_RigidConstraintModel, pin.StdVec_RigidConstraintData]:
        """Copies of :attr:`constraint_models` with Baumgarte's corrector K_p = ω², K_d = 2ω for
        the rate ω [1/s] (critically damped: a loop error decays like (1 + ωt) e^(−ωt)), and
        their datas, initialised for ``constraintDynamics`` on ``data`` (a Data of
        :attr:`model`, or of a copy of it with other inertias or gravity)."""
        models = pin.StdVec_RigidConstraintModel()
        for constraint in self.constraint_models:
            copy = pin.RigidConstraintModel(constraint)
            copy.m_baumgarte_parameters.Kp = rate**2
            copy.m_baumgarte_parameters.Kd = 2.0 * rate
            models.append(copy)
        datas = pin.StdVec_RigidConstraintData()
        for constraint in models:
            datas.append(constraint.createData())
        pin.initConstraintDynamics(self.model, data, models, datas)
        return models, datas

    def frame_id(self, name: str) -> int:
        """Pinocchio id of the frame ``name``.

        Raises:
            InputError: No frame of that name in the model (the message names the nearest one,
                or lists the frames).
        """
        if not isinstance(name, str) or not self.model.existFrame(name):
            names = [f.name for f in self.model.frames]
            near = difflib.get_close_matches(str(name), names, n=1)
            hint = f"did you mean {near[0]!r}?" if near else f"frames: {names}"
            raise InputError(f"no frame {name!r} in model {self.model.name!r}; {hint}")
        return self.model.getFrameId(name)

    @property
    def nc(self) -> int:
        """Number of scalar closure equations (3 per point, 6 per weld, 5 per revolute cut)."""
        return sum(cut.rows for cut in self.cuts)

    def row_labels(self) -> list[str]:
        """``closure-label:row`` for every row, e.g. ``"tip-ground:fz"``, (nc,)."""
        return [f"{cut.label}:{row}" for cut in self.cuts for row in cut.labels]

    def check_q(self, q: np.ndarray) -> np.ndarray:
        """``q`` as a float array of shape (nq,), or :class:`InputError` if NaN/inf/misshaped."""
        return check_vector("q", q, self.model.nq)

    def check_v(self, name: str, v: np.ndarray) -> np.ndarray:
        """A velocity-like vector of shape (nv,), checked finite."""
        return check_vector(name, v, self.model.nv)

    def residual(self, q: np.ndarray) -> np.ndarray:
        """Closure error of every closure at ``q`` [m, rad-like], shape (nc,)."""
        pin.forwardKinematics(self.model, self.data, self.check_q(q))
        return self.placed_residual()

    def placed_residual(self) -> np.ndarray:
        """Closure error (nc,) at the configuration of the last forward kinematics run on
        :attr:`data` (by :meth:`residual` or by the caller): each cut's
        :meth:`~feeder.chain.model.cuts.Cut.residual` (p_a − p_b for the point rows, log3(R_a
        R_bᵀ) [rad] for a weld's rotation, the two components of b's hinge axis perpendicular
        to a's for a revolute cut)."""
        model, data = self.model, self.data
        rows = []
        for cut, (a, b) in zip(self.cuts, self.frame_ids, strict=True):
            pa = pin.updateFramePlacement(model, data, a)
            pb = pin.updateFramePlacement(model, data, b)
            frames = CutFrames(pa.rotation, pb.rotation, pa.translation, pb.translation)
            rows.append(cut.residual(frames))
        return np.concatenate(rows) if rows else np.zeros(0)

    def _frames(self, a: int, b: int, jacobians: bool = False, rates: bool = False) -> CutFrames:
        """One sample's :class:`~feeder.chain.model.cuts.CutFrames` (without the sample axis) of
        frames a and b from :attr:`data`, whose frame placements are current; with their
        Jacobians (the joint Jacobians are current) and with their velocities and classical
        accelerations (the forward kinematics ran with v and a)."""
        model, data = self.model, self.data
        placements = data.oMf
        pa, pb = placements[a], placements[b]
        frames = CutFrames(pa.rotation, pb.rotation, pa.translation, pb.translation)
        world = pin.LOCAL_WORLD_ALIGNED
        if jacobians:
            frames.jacobian_a = frame_jacobian(model, data, a, world)
            frames.jacobian_b = frame_jacobian(model, data, b, world)
        if rates:
            acc_a = pin.getFrameClassicalAcceleration(model, data, a, world)
            acc_b = pin.getFrameClassicalAcceleration(model, data, b, world)
            frames.omega_a = pin.getFrameVelocity(model, data, a, world).angular
            frames.omega_b = pin.getFrameVelocity(model, data, b, world).angular
            frames.alpha_a, frames.alpha_b = acc_a.angular, acc_b.angular
            frames.acceleration_a, frames.acceleration_b = acc_a.linear, acc_b.linear
        return frames

    def _jacobian_frames(self, q: np.ndarray) -> list[CutFrames]:
        pin.computeJointJacobians(self.model, self.data, q)
        pin.updateFramePlacements(self.model, self.data)
        return [self._frames(a, b, jacobians=True) for a, b in self.frame_ids]

    def jacobian(self, q: np.ndarray) -> np.ndarray:
        """The closure rows' Jacobian in world axes, shape (nc, nv): q̇ ↦ the rows' rates
        (:mod:`feeder.chain.model.cuts`). At an assembled q it spans the same rows as the
        residual's."""
        frames = self._jacobian_frames(self.check_q(q))
        rows = [cut.jacobian(f) for cut, f in zip(self.cuts, frames, strict=True)]
        return np.vstack(rows) if rows else np.zeros((0, self.model.nv))

    def residual_jacobian(self, q: np.ndarray) -> np.ndarray:
        """∂(residual)/∂q, shape (nc, nv): the exact derivative that Newton's method needs. It
        equals :meth:`jacobian` but for a weld's rotation rows: d log3(R)/dt =
        Jlog3(R) (Rᵀ ω_a − ω_b) with R = R_a R_bᵀ, which is ω_a − ω_b only where R = I."""
        frames = self._jacobian_frames(self.check_q(q))
        rows = [cut.residual_jacobian(f) for cut, f in zip(self.cuts, frames, strict=True)]
        return np.vstack(rows) if rows else np.zeros((0, self.model.nv))

    def reversed_hinges(self) -> list[str]:
        """Labels of the revolute cuts whose two hinge axes point opposite ways at the
        configuration of the last :meth:`residual` (u_a · u_b < 0): their rows vanish there too,
        but the hinge is assembled upside down, which no real joint can be."""
        out = []
        for cut, (a, b) in zip(self.cuts, self.frame_ids, strict=True):
            alignment = cut.alignment(self._frames(a, b))
            if alignment is not None and alignment < 0.0:
                out.append(cut.label)
        return out

    def bias(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """J̇ q̇: the rows' second time derivative at zero q̈, world axes, shape (nc,)."""
        q, v = self.check_q(q), self.check_v("v", v)
        model, data = self.model, self.data
        pin.forwardKinematics(model, data, q, v, np.zeros(model.nv))
        pin.updateFramePlacements(model, data)
        out = [
            cut.acceleration(self._frames(a, b, rates=True))
            for cut, (a, b) in zip(self.cuts, self.frame_ids, strict=True)
        ]
        return np.concatenate(out) if out else np.zeros(0)

    def coordinate_columns(self, names: Sequence[str], role: str) -> np.ndarray:
        """Velocity indices (k,) of the one-coordinate joints ``names`` (revolute, continuous,
        prismatic: those a motion table prescribes and an actuator drives), in the order given.

        Args:
            names: Joint names.
            role: What they are, for the messages (``"independent"``, ``"actuated"``).

        Raises:
            InputError: Not a list of names, a name given twice, an unknown joint, a joint with
                several coordinates.
        """
        if isinstance(names, str) or not isinstance(names, Sequence):
            raise InputError(f"{role} joints must be a list of names, got {names!r}")
        if len(set(names)) != len(names):
            raise InputError(f"{role} joints must be distinct, got {list(names)}")
        columns = []
        for name in names:
            span = self.joint_slice(name)
            if span.stop - span.start != 1:
                raise InputError(
                    f"{role} joint {name!r} has {span.stop - span.start} coordinates: {role} "
                    "joints are revolute, continuous or prismatic"
                )
            columns.append(span.start)
        return np.array(columns, dtype=int)

    def joint_slice(self, joint: str) -> slice:
        """Index range of ``joint`` in the velocity vector.

        Raises:
            InputError: No joint of that name (the message names the nearest one, or lists the
                joints).
        """
        if not isinstance(joint, str) or not self.model.existJointName(joint):
            names = list(self.model.names)[1:]
            near = difflib.get_close_matches(str(joint), names, n=1)
            hint = f"did you mean {near[0]!r}?" if near else f"joints: {names}"
            raise InputError(f"no joint {joint!r} in model {self.model.name!r}; {hint}")
        j = self.model.joints[self.model.getJointId(joint)]
        return slice(j.idx_v, j.idx_v + j.nv)
