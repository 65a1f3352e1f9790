"""Pinocchio's frame and joint Jacobians, always of shape (6, nv): its Python bindings return a
(6,) array when the model has one velocity, which slicing rows ``[:3]`` would then misread."""

from __future__ import annotations

import numpy as np
import pinocchio as pin


def frame_jacobian(
    model: pin.Model, data: pin.Data, frame: int, reference: pin.ReferenceFrame
) -> np.ndarray:
    """``getFrameJacobian`` (6, nv) [linear; angular] of ``frame`` in ``reference``, from the
    joint Jacobians already in ``data`` (``computeJointJacobians``)."""
    return pin.getFrameJacobian(model, data, frame, reference).reshape(6, model.nv)


def joint_jacobian(
    model: pin.Model, data: pin.Data, joint: int, reference: pin.ReferenceFrame
) -> np.ndarray:
    """``getJointJacobian`` (6, nv) of joint ``joint`` in ``reference`` (as above)."""
    return pin.getJointJacobian(model, data, joint, reference).reshape(6, model.nv)
