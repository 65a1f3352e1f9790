"""A kinematic tree plus rigid loop closures, for any URDF.

A closure is a pair of frames (``frame_a``, ``frame_b``) whose origins coincide when the loop is
assembled: a spherical pin, three scalar constraints. Pinocchio receives each as a
``RigidConstraintModel`` of type ``CONTACT_3D`` (expressed in the LOCAL frame of ``frame_a``),
ready for ``initConstraintDynamics`` / ``constraintDynamics``. For kinematics the same closures are
written in the world frame (``residual``, ``jacobian``, ``bias``).

A planar loop closed by a 3-D pin has one redundant row (the out-of-plane one, identically zero):
the closure Jacobian has rank 2 per planar loop, not 3. Everything here uses least squares or
rank-revealing solves, so that redundancy is harmless.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pinocchio as pin

from ..exceptions import ClosureFrameError, InputError
from ..validation import check_vector
from .urdf import build_model, read_urdf

Closure = tuple[str, str]
"""Names of two frames whose origins coincide when the loop is assembled."""


class ClosedChain:
    """Pinocchio model and data of a kinematic tree with rigid point closures.

    Attributes:
        model: Pinocchio model of the open tree.
        data: Its data, reused by every method (each method runs the forward kinematics it
            needs first, so the data always match the last call's arguments).
        closures: The closed frame pairs.
        constraint_models: One ``CONTACT_3D`` ``RigidConstraintModel`` per closure.
        constraint_datas: Their data.
    """

    def __init__(self, model: pin.Model, closures: Sequence[Closure]):
        self.model = model
        self.data = model.createData()
        self.closures = _check_closures(closures)
        self.frame_ids: list[tuple[int, int]] = []
        self.constraint_models = pin.StdVec_RigidConstraintModel()
        for frame_a, frame_b in self.closures:
            for name in (frame_a, frame_b):
                if not model.existFrame(name):
                    raise ClosureFrameError(
                        f"closure frame {name!r} is not in model {model.name!r}; "
                        f"frames: {[f.name for f in model.frames]}"
                    )
            ids = (model.getFrameId(frame_a), model.getFrameId(frame_b))
            fa, fb = (model.frames[i] for i in ids)
            if fa.parentJoint == fb.parentJoint:
                raise InputError(
                    f"closure ({frame_a!r}, {frame_b!r}) joins two frames on the same body "
                    f"(joint {model.names[fa.parentJoint]!r}): it closes no loop"
                )
            self.frame_ids.append(ids)
            constraint = pin.RigidConstraintModel(
                pin.ContactType.CONTACT_3D,
                model,
                fa.parentJoint,
                fa.placement,
                fb.parentJoint,
                fb.placement,
                pin.ReferenceFrame.LOCAL,
            )
            constraint.name = f"{frame_a}-{frame_b}"
            self.constraint_models.append(constraint)
        self.constraint_datas = pin.StdVec_RigidConstraintData()
        for constraint in self.constraint_models:
            self.constraint_datas.append(constraint.createData())

    def frame_id(self, name: str) -> int:
        """Pinocchio id of the frame ``name``.

        Raises:
            InputError: No frame of that name in the model (the message lists the frames).
        """
        if not self.model.existFrame(name):
            raise InputError(
                f"no frame {name!r} in model {self.model.name!r}; "
                f"frames: {[f.name for f in self.model.frames]}"
            )
        return self.model.getFrameId(name)

    @property
    def nc(self) -> int:
        """Number of scalar closure equations (3 per closure)."""
        return 3 * len(self.closures)

    def check_q(self, q: np.ndarray) -> np.ndarray:
        """``q`` as a float array of shape (nq,), or :class:`InputError` if NaN/inf/misshaped."""
        return check_vector("q", q, self.model.nq)

    def check_v(self, name: str, v: np.ndarray) -> np.ndarray:
        """A velocity-like vector of shape (nv,), checked finite."""
        return check_vector(name, v, self.model.nv)

    def residual(self, q: np.ndarray) -> np.ndarray:
        """Closure error p_a − p_b of every closure, world frame [m], shape (nc,)."""
        pin.forwardKinematics(self.model, self.data, self.check_q(q))
        return self.placed_residual()

    def placed_residual(self) -> np.ndarray:
        """Closure error p_a − p_b [m], shape (nc,), at the configuration of the last forward
        kinematics run on :attr:`data` (by :meth:`residual` or by the caller)."""
        model, data = self.model, self.data
        return np.concatenate(
            [
                pin.updateFramePlacement(model, data, a).translation
                - pin.updateFramePlacement(model, data, b).translation
                for a, b in self.frame_ids
            ]
        )

    def jacobian(self, q: np.ndarray) -> np.ndarray:
        """∂(p_a − p_b)/∂q in the world frame, shape (nc, nv) (q̇ ↦ closure velocity error)."""
        q = self.check_q(q)
        pin.computeJointJacobians(self.model, self.data, q)
        pin.updateFramePlacements(self.model, self.data)
        rows = []
        for a, b in self.frame_ids:
            ja = pin.getFrameJacobian(self.model, self.data, a, pin.LOCAL_WORLD_ALIGNED)
            jb = pin.getFrameJacobian(self.model, self.data, b, pin.LOCAL_WORLD_ALIGNED)
            rows.append(ja[:3] - jb[:3])
        return np.vstack(rows)

    def bias(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """J̇ q̇: the closure's acceleration error at zero q̈, world frame [m/s²], shape (nc,)."""
        q, v = self.check_q(q), self.check_v("v", v)
        pin.forwardKinematics(self.model, self.data, q, v, np.zeros(self.model.nv))
        pin.updateFramePlacements(self.model, self.data)
        world = pin.LOCAL_WORLD_ALIGNED
        return np.concatenate(
            [
                pin.getFrameClassicalAcceleration(self.model, self.data, a, world).linear
                - pin.getFrameClassicalAcceleration(self.model, self.data, b, world).linear
                for a, b in self.frame_ids
            ]
        )

    def joint_slice(self, joint: str) -> slice:
        """Index range of ``joint`` in the velocity vector."""
        if not self.model.existJointName(joint):
            names = list(self.model.names)[1:]
            raise InputError(f"no joint {joint!r} in model {self.model.name!r}; joints: {names}")
        j = self.model.joints[self.model.getJointId(joint)]
        return slice(j.idx_v, j.idx_v + j.nv)


def _check_closures(closures: Sequence[Closure]) -> tuple[Closure, ...]:
    """The closures as a tuple of (frame_a, frame_b) name pairs, or :class:`InputError`."""
    if isinstance(closures, str | bytes) or not isinstance(closures, Sequence):
        raise InputError(f"closures must be a sequence of frame-name pairs, got {closures!r}")
    pairs = []
    for pair in closures:
        if (
            isinstance(pair, str | bytes)
            or not isinstance(pair, Sequence)
            or len(pair) != 2
            or not all(isinstance(name, str) for name in pair)
        ):
            raise InputError(f"a closure must be a pair of frame names, got {pair!r}")
        pairs.append((pair[0], pair[1]))
    return tuple(pairs)


def load_closed_chain(urdf: str | Path, closures: Sequence[Closure]) -> ClosedChain:
    """Load a URDF file strictly and close the loops given as frame pairs.

    Args:
        urdf: Path of the URDF file (fixed base; meshes are not needed).
        closures: Pairs of frame names (links or fixed joints) to pin together.

    Raises:
        UrdfError: Missing or malformed file.
        InertiaError: A non-physical link inertia.
        ClosureFrameError: A closure frame that is not in the model.
        InputError: ``closures`` not a sequence of name pairs, or a pair of frames on the same
            body.
    """
    return ClosedChain(build_model(read_urdf(urdf), str(urdf)), closures)
