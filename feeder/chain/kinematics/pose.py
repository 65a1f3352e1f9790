"""A closed chain at one configuration: the pose object that the rank tests, the continuation's
step test and the idle-motion test read, instead of the Pinocchio data that an earlier call
happened to leave (modelled on pink's ``Configuration``).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..model.closure import ClosedChain
from ..model.jacobians import frame_jacobian, joint_jacobian


class _once:
    """A property computed on its first read and kept in the instance's ``__dict__``, where later
    reads find it (``functools.cached_property`` without the lock that Python 3.11 takes)."""

    def __init__(self, method):
        self.method, self.name, self.__doc__ = method, method.__name__, method.__doc__

    def __get__(self, pose, owner=None):
        if pose is None:
            return self
        value = pose.__dict__[self.name] = self.method(pose)
        return value


class ChainPose:
    """The chain ``chain`` at the configuration ``q`` (nq,), q kept as a read-only copy.

    Each quantity is computed at q by the algorithms it needs, run right there on the chain's
    data, the first time it is read, and kept (read-only): nothing read depends on what the
    chain's data hold by then. Like pink's ``Configuration``, but lazy, as a continuation step
    needs only the hinge test of most poses it tries:

    * :attr:`reversed_hinges`: ``framesForwardKinematics`` (``forwardKinematics`` and
      ``updateFramePlacements``);
    * :attr:`residual`: ``forwardKinematics`` and the cut frames' placements
      (:meth:`~feeder.chain.model.closure.ClosedChain.residual`);
    * :attr:`jacobian`: ``computeJointJacobians`` and ``updateFramePlacements``
      (:meth:`~feeder.chain.model.closure.ClosedChain.jacobian`);
    * :meth:`point_rows`: the same two, on data of its own (not kept: only the idle-motion test
      asks, once per pose).

    Raises:
        InputError: NaN/inf or misshaped q.
    """

    def __init__(self, chain: ClosedChain, q: np.ndarray):
        plain = isinstance(q, np.ndarray) and q.dtype == np.float64 and q.ndim == 1
        if not (plain and q.shape[0] == chain.model.nq and np.isfinite(q).all()):
            q = chain.check_q(q)  # converts, or refuses with the message (else only checked:
            # a continuation makes some seventy poses per motion)
        q = q.copy()
        q.setflags(write=False)
        self.chain = chain
        self.q = q

    @_once
    def jacobian(self) -> np.ndarray:
        """The closure rows' Jacobian (nc, nv), world axes."""
        jacobian = self.chain.jacobian(self.q)
        jacobian.setflags(write=False)
        return jacobian

    @_once
    def residual(self) -> np.ndarray:
        """The closure error (nc,) [m, rad]."""
        residual = self.chain.residual(self.q)
        residual.setflags(write=False)
        return residual

    @_once
    def reversed_hinges(self) -> tuple[str, ...]:
        """Labels of the revolute cuts assembled upside down at q: their two hinge axes opposite
        (the rows vanish, but no real joint can be so)."""
        pin.framesForwardKinematics(self.chain.model, self.chain.data, self.q)
        return tuple(self.chain.reversed_hinges())

    @property
    def gap(self) -> float:
        """The largest closure error |residual| [m, rad] (0 without closures)."""
        return float(np.abs(self.residual).max(initial=0.0))

    def point_rows(self) -> np.ndarray:
        """World velocity rows (3 p, nv) of every joint origin, frame origin and centre of
        gravity of a body with mass (the points that an idle motion leaves in place)."""
        model = self.chain.model
        data = model.createData()
        pin.computeJointJacobians(model, data, self.q)
        pin.updateFramePlacements(model, data)
        world = pin.LOCAL_WORLD_ALIGNED
        rows = []
        for j in range(1, model.njoints):
            jac = joint_jacobian(model, data, j, world)
            rows.append(jac[:3])
            if model.inertias[j].mass > 0.0:
                lever = data.oMi[j].rotation @ model.inertias[j].lever
                rows.append(jac[:3] - pin.skew(lever) @ jac[3:])
        for f in range(1, len(model.frames)):
            if model.frames[f].parentJoint > 0:
                rows.append(frame_jacobian(model, data, f, world)[:3])
        return np.vstack(rows)
