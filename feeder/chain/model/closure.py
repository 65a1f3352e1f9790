"""A kinematic tree plus rigid loop closures, for any URDF: the closures typed by their cut.

A closure joins two frames, ``frame_a`` and ``frame_b``, that coincide (or turn about a common
axis) when the loop is assembled. Three kinds, by the joint that was cut to open the loop:

=============  ====  ==============================================================================
kind           rows  the cut joint and its rows (world axes; "a minus b")
=============  ====  ==============================================================================
``point``      3     spherical pin: p_a − p_b
``weld``       6     rigid joint: p_a − p_b, and the relative rotation (its rows: ω_a − ω_b)
``revolute``   5     hinge about ``axis``: p_a − p_b, and the two components of frame b's hinge
                     axis u_b along n_1, n_2, the unit vectors of frame a that span the plane
                     perpendicular to its hinge (its rows: d_k · (ω_a − ω_b), d_k = n_k × u_b)
=============  ====  ==============================================================================

The constraint force conjugate to the rows acts on the body of ``frame_a`` (and its opposite on
the body of ``frame_b``): a force [N] at frame a's origin for the point rows, a moment [N·m] for
the rotation rows. A planar loop closed in its plane has redundant rows (the out-of-plane force,
the two tilting moments of a revolute cut): the closure Jacobian is rank-deficient everywhere,
and every solve here is rank-revealing, so redundancy is harmless; :mod:`feeder.chain.mobility`
reports it and :mod:`feeder.chain.dynamics.inverse` flags the indeterminate force components.

Pinocchio receives each closure as ``RigidConstraintModel`` s for ``constraintDynamics``: a
``CONTACT_3D`` for a point, a ``CONTACT_6D`` for a weld and, as Pinocchio 4.1 has no hinge
constraint, two ``CONTACT_3D`` on the hinge axis (:data:`HINGE_POINTS` apart) for a revolute cut.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ...exceptions import ClosureFrameError, InputError
from ...validation import check_vector
from .jacobians import frame_jacobian

KINDS = {"point": 3, "weld": 6, "revolute": 5}
"""Closure kinds and their number of scalar constraints."""

HINGE_POINTS = 0.1
"""Distance [m] along the hinge axis between the two point constraints that stand for a revolute
cut in Pinocchio's ``constraintDynamics``."""

ROW_LABELS = {
    "point": ("fx", "fy", "fz"),
    "weld": ("fx", "fy", "fz", "mx", "my", "mz"),
    "revolute": ("fx", "fy", "fz", "m1", "m2"),
}
"""Names of each kind's rows: world force components, world moment components, or (m1, m2) the
moments about the directions d_1 = n_1 × u, d_2 = n_2 × u perpendicular to the hinge u (with
(n_1, n_2, u) right-handed: d_1 = −n_2, d_2 = n_1 at an assembled hinge)."""


@dataclass(frozen=True)
class Closure:
    """One loop closure: two frames joined by the cut joint.

    Attributes:
        frame_a, frame_b: Names of the two frames (links or fixed-joint frames of the URDF),
            on different bodies.
        kind: ``"point"``, ``"weld"`` or ``"revolute"`` (see the module docstring).
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
        return KINDS[self.kind]


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


def _perpendicular_pair(axis: np.ndarray) -> np.ndarray:
    """Two unit vectors (2, 3) with (e1, e2, axis) right-handed and orthonormal."""
    helper = np.eye(3)[int(np.argmin(np.abs(axis)))]
    e1 = np.cross(helper, axis)
    e1 /= np.linalg.norm(e1)
    return np.array([e1, np.cross(axis, e1)])


class ClosedChain:
    """Pinocchio model and data of a kinematic tree with rigid loop closures.

    Attributes:
        model: Pinocchio model of the open tree.
        data: Its data, reused by every method (each method runs the forward kinematics it
            needs first, so the data always match the last call's arguments).
        closures: The closures, checked (:class:`Closure`).
        frame_ids: Pinocchio frame ids (a, b) of each closure.
        hinge_normals: Per closure, for a revolute cut the two unit vectors (2, 3) that span the
            plane perpendicular to its hinge, in frame a's axes (None for other kinds).
        row_slices: Per closure, its rows' slice in the stacked closure rows.
        constraint_models: Pinocchio ``RigidConstraintModel`` s of the closures (see the module
            docstring), in closure order.
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
        self.hinge_normals: list[np.ndarray | None] = []
        self.constraint_models = pin.StdVec_RigidConstraintModel()
        for closure in self.closures:
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
            axis = np.array(closure.axis)
            self.hinge_normals.append(
                _perpendicular_pair(axis) if closure.kind == "revolute" else None
            )
            for constraint in _constraint_models(model, closure, fa, fb):
                self.constraint_models.append(constraint)
        self.constraint_datas = pin.StdVec_RigidConstraintData()
        for constraint in self.constraint_models:
            self.constraint_datas.append(constraint.createData())
        self.row_slices = []
        start = 0
        for closure in self.closures:
            self.row_slices.append(slice(start, start + closure.rows))
            start += closure.rows

    def frame_id(self, name: str) -> int:
        """Pinocchio id of the frame ``name``.

        Raises:
            InputError: No frame of that name in the model (the message lists the frames).
        """
        if not isinstance(name, str) or not self.model.existFrame(name):
            raise InputError(
                f"no frame {name!r} in model {self.model.name!r}; "
                f"frames: {[f.name for f in self.model.frames]}"
            )
        return self.model.getFrameId(name)

    @property
    def nc(self) -> int:
        """Number of scalar closure equations (3 per point, 6 per weld, 5 per revolute cut)."""
        return sum(closure.rows for closure in self.closures)

    def row_labels(self) -> list[str]:
        """``closure-label:row`` for every row, e.g. ``"tip-ground:fz"``, (nc,)."""
        return [
            f"{closure.label}:{row}"
            for closure in self.closures
            for row in ROW_LABELS[closure.kind]
        ]

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
        :attr:`data` (by :meth:`residual` or by the caller): p_a − p_b for the point rows,
        log3(R_a R_bᵀ) [rad] for a weld's rotation, the two components of b's hinge axis
        perpendicular to a's for a revolute cut."""
        model, data = self.model, self.data
        rows = []
        for closure, (a, b), perpendicular in zip(
            self.closures, self.frame_ids, self.hinge_normals, strict=True
        ):
            pa = pin.updateFramePlacement(model, data, a)
            pb = pin.updateFramePlacement(model, data, b)
            rows.append(pa.translation - pb.translation)
            if closure.kind == "weld":
                rows.append(pin.log3(pa.rotation @ pb.rotation.T))
            elif closure.kind == "revolute":
                axis_b = pb.rotation @ np.array(closure.axis_b)
                rows.append((pa.rotation @ perpendicular.T).T @ axis_b)
        return np.concatenate(rows) if rows else np.zeros(0)

    def _frame_jacobians(self, q: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
        pin.computeJointJacobians(self.model, self.data, q)
        pin.updateFramePlacements(self.model, self.data)
        world = pin.LOCAL_WORLD_ALIGNED
        return [
            (
                frame_jacobian(self.model, self.data, a, world),
                frame_jacobian(self.model, self.data, b, world),
            )
            for a, b in self.frame_ids
        ]

    def jacobian(self, q: np.ndarray) -> np.ndarray:
        """The closure rows' Jacobian in world axes, shape (nc, nv): q̇ ↦ the rows' rates
        (module docstring). At an assembled q it spans the same rows as the residual's."""
        q = self.check_q(q)
        rows = []
        for closure, (ja, jb), (a, b), perpendicular in zip(
            self.closures,
            self._frame_jacobians(q),
            self.frame_ids,
            self.hinge_normals,
            strict=True,
        ):
            rows.append(ja[:3] - jb[:3])
            if closure.kind == "weld":
                rows.append(ja[3:] - jb[3:])
            elif closure.kind == "revolute":
                rows.append(
                    self._hinge_directions(closure, a, b, perpendicular) @ (ja[3:] - jb[3:])
                )
        return np.vstack(rows) if rows else np.zeros((0, self.model.nv))

    def reversed_hinges(self) -> list[str]:
        """Labels of the revolute cuts whose two hinge axes point opposite ways at the
        configuration of the last :meth:`residual` (u_a · u_b < 0): their rows vanish there too,
        but the hinge is assembled upside down, which no real joint can be."""
        out = []
        for closure, (a, b) in zip(self.closures, self.frame_ids, strict=True):
            if closure.kind == "revolute":
                u_a = self.data.oMf[a].rotation @ np.array(closure.axis)
                u_b = self.data.oMf[b].rotation @ np.array(closure.axis_b)
                if u_a @ u_b < 0.0:
                    out.append(closure.label)
        return out

    def residual_jacobian(self, q: np.ndarray) -> np.ndarray:
        """∂(residual)/∂q, shape (nc, nv): the exact derivative that Newton's method needs. It
        equals :meth:`jacobian` but for a weld's rotation rows: d log3(R)/dt =
        Jlog3(R) (Rᵀ ω_a − ω_b) with R = R_a R_bᵀ, which is ω_a − ω_b only where R = I."""
        q = self.check_q(q)
        jac = self.jacobian(q)
        for closure, rows, (a, b) in zip(
            self.closures, self.row_slices, self.frame_ids, strict=True
        ):
            if closure.kind == "weld":
                ra, rb = self.data.oMf[a].rotation, self.data.oMf[b].rotation
                relative = ra @ rb.T
                ja, jb = (
                    frame_jacobian(self.model, self.data, f, pin.LOCAL_WORLD_ALIGNED)[3:]
                    for f in (a, b)
                )
                jac[rows.start + 3 : rows.stop] = pin.Jlog3(relative) @ (relative.T @ ja - jb)
        return jac

    def _hinge_directions(
        self, closure: Closure, frame_a: int, frame_b: int, perpendicular: np.ndarray
    ) -> np.ndarray:
        """The two revolute rows' directions n_k × u_b (2, 3), world axes (module docstring),
        at the placements in :attr:`data`."""
        axis_b = self.data.oMf[frame_b].rotation @ np.array(closure.axis_b)
        normals = (self.data.oMf[frame_a].rotation @ perpendicular.T).T
        return normals @ pin.skew(axis_b)  # rows n_k × u_b (n × u = −[u]× n = ([n]× ... )ᵀ)

    def bias(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """J̇ q̇: the rows' second time derivative at zero q̈, world axes, shape (nc,)."""
        q, v = self.check_q(q), self.check_v("v", v)
        model, data = self.model, self.data
        pin.forwardKinematics(model, data, q, v, np.zeros(model.nv))
        pin.updateFramePlacements(model, data)
        world = pin.LOCAL_WORLD_ALIGNED
        out = []
        for closure, (a, b), perpendicular in zip(
            self.closures, self.frame_ids, self.hinge_normals, strict=True
        ):
            acc_a = pin.getFrameClassicalAcceleration(model, data, a, world)
            acc_b = pin.getFrameClassicalAcceleration(model, data, b, world)
            out.append(acc_a.linear - acc_b.linear)
            if closure.kind == "weld":
                out.append(acc_a.angular - acc_b.angular)
            elif closure.kind == "revolute":
                w_a = pin.getFrameVelocity(model, data, a, world).angular
                w_b = pin.getFrameVelocity(model, data, b, world).angular
                normals = (data.oMf[a].rotation @ perpendicular.T).T
                u_b = data.oMf[b].rotation @ np.array(closure.axis_b)
                relative, spin = w_a - w_b, acc_a.angular - acc_b.angular
                rates = np.cross(np.cross(w_a, normals), u_b) + np.cross(
                    normals, np.cross(w_b, u_b)
                )
                out.append(rates @ relative + np.cross(normals, u_b) @ spin)
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
            InputError: No joint of that name (the message lists the joints).
        """
        if not isinstance(joint, str) or not self.model.existJointName(joint):
            names = list(self.model.names)[1:]
            raise InputError(f"no joint {joint!r} in model {self.model.name!r}; joints: {names}")
        j = self.model.joints[self.model.getJointId(joint)]
        return slice(j.idx_v, j.idx_v + j.nv)


def _constraint_models(
    model: pin.Model, closure: Closure, fa: pin.Frame, fb: pin.Frame
) -> list[pin.RigidConstraintModel]:
    """Pinocchio's constraints standing for one closure (module docstring), LOCAL to frame a."""

    def contact(kind, placement_a: pin.SE3, placement_b: pin.SE3, suffix: str = ""):
        constraint = pin.RigidConstraintModel(
            kind, model, fa.parentJoint, placement_a, fb.parentJoint, placement_b, pin.LOCAL
        )
        constraint.name = closure.label + suffix
        return constraint

    if closure.kind == "point":
        return [contact(pin.ContactType.CONTACT_3D, fa.placement, fb.placement)]
    if closure.kind == "weld":
        return [contact(pin.ContactType.CONTACT_6D, fa.placement, fb.placement)]
    shift_a = pin.SE3(np.eye(3), HINGE_POINTS * np.array(closure.axis))
    shift_b = pin.SE3(np.eye(3), HINGE_POINTS * np.array(closure.axis_b))
    return [
        contact(pin.ContactType.CONTACT_3D, fa.placement, fb.placement, ":origin"),
        contact(
            pin.ContactType.CONTACT_3D, fa.placement * shift_a, fb.placement * shift_b, ":axis"
        ),
    ]
