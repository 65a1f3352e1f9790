"""A closed chain at one configuration, its kinematics run once: the pose object that the rank
tests, the continuation's step test and the idle-motion test read, instead of the Pinocchio data
that an earlier call happened to leave (modelled on pink's ``Configuration``).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..model.closure import ClosedChain
from ..model.jacobians import frame_jacobian, joint_jacobian


class ChainPose:
    """The chain ``chain`` at the configuration ``q`` (nq,).

    At construction it runs ``computeJointJacobians`` (the joints' placements and Jacobians at
    q) and ``updateFramePlacements`` on the chain's data, through
    :meth:`~feeder.chain.model.closure.ClosedChain.jacobian`, and keeps what the closure needs
    from them; :meth:`point_rows` runs the same two algorithms on data of its own when it is
    asked (only the idle-motion test needs it). Nothing read later depends on what the chain's
    data hold by then.

    Attributes:
        chain: The closed chain.
        q: The configuration (nq,), a read-only copy.
        jacobian: The closure rows' Jacobian (nc, nv), world axes (read-only).
        residual: The closure error (nc,) [m, rad] (read-only).
        reversed_hinges: Labels of the revolute cuts assembled upside down at q (their two hinge
            axes opposite: the rows vanish, but no real joint can be so).

    Raises:
        InputError: NaN/inf or misshaped q.
    """

    def __init__(self, chain: ClosedChain, q: np.ndarray):
        q = chain.check_q(q).copy()
        q.setflags(write=False)
        self.chain = chain
        self.q = q
        self.jacobian = chain.jacobian(q)  # computeJointJacobians, updateFramePlacements
        self.residual = chain.placed_residual()
        self.reversed_hinges = tuple(chain.reversed_hinges())
        self.jacobian.setflags(write=False)
        self.residual.setflags(write=False)

    @property
    def gap(self) -> float:
        """The largest closure error |residual| [m, rad] (0 without closures)."""
        return float(np.abs(self.residual).max(initial=0.0))

    def point_rows(self) -> np.ndarray:
        """World velocity rows (3 p, nv) of every joint origin, frame origin and centre of
        gravity of a body with mass (the points that an idle motion leaves in place), from
        ``computeJointJacobians`` and ``updateFramePlacements`` run here at :attr:`q`."""
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
