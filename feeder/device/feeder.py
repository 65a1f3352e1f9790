"""A feeding device loaded in Pinocchio: parameters → URDF → model → pin closure.

The paper's generalized coordinates q = [φ1, r2, φ3, φ4] (eq. 29) are the positions of
``cylinder_joint``, ``piston_joint``, ``arm_joint`` and ``forearm_joint``. Pinocchio orders its
configuration vector by the tree, not by the paper, so :meth:`Feeder.to_pinocchio` and
:meth:`Feeder.to_paper` map by joint name.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..chain import ClosedChain
from ..chain.readers import build_model
from ..exceptions import InputError
from .builtin import DEVICES
from .parameters import GRAVITY, FeederParameters
from .urdf_writer import urdf_string

PAPER_JOINTS = ("cylinder_joint", "piston_joint", "arm_joint", "forearm_joint")
"""Joints of the paper's coordinates φ1, r2, φ3, φ4, in that order (eq. 29)."""

CLOSURE = ("piston_pin", "arm_pin")
"""The loop closure: the rod-eye pin, a frame on the piston and one on the arm."""

INDEPENDENT_JOINTS = ("arm_joint", "forearm_joint")
"""Joints of the independent coordinates φ3, φ4 (2 degrees of freedom)."""


class Feeder:
    """One feeding device: its parameters, URDF text and closed-chain Pinocchio model.

    A Feeder is not changed once loaded (to change the device, load one from other
    parameters): the dynamics built from it are kept and reused
    (:func:`feeder.dynamics.models.feeder_dynamics`).

    Attributes:
        params: The parameter set the model was generated from.
        urdf: The URDF text (as written by :func:`~feeder.device.urdf_writer.urdf_string`,
            which checks the parameters first).
        chain: Pinocchio model (gravity set to :data:`GRAVITY`), data and the
            ``piston_pin``–``arm_pin`` closure.
        index: Positions of φ1, r2, φ3, φ4 in Pinocchio's q (and v, since nq = nv), shape (4,).
    """

    def __init__(self, params: FeederParameters):
        self.params = params
        self.urdf = urdf_string(params)
        self.chain = ClosedChain(build_model(self.urdf, f"<{params.name} feeder URDF>"), [CLOSURE])
        model = self.chain.model
        model.gravity = pin.Motion(GRAVITY, np.zeros(3))
        self.index = np.array([model.joints[model.getJointId(n)].idx_q for n in PAPER_JOINTS])

    @property
    def model(self):
        """The Pinocchio model (open tree)."""
        return self.chain.model

    def to_pinocchio(self, x_paper: np.ndarray) -> np.ndarray:
        """Reorder paper-order vectors (..., 4) = [φ1, r2, φ3, φ4] into Pinocchio order."""
        x_paper = np.asarray(x_paper, dtype=float)
        out = np.empty_like(x_paper)
        out[..., self.index] = x_paper
        return out

    def to_paper(self, x: np.ndarray) -> np.ndarray:
        """Reorder Pinocchio-order vectors (..., 4) into the paper's [φ1, r2, φ3, φ4]."""
        return np.asarray(x, dtype=float)[..., self.index]

    def frame_id(self, name: str) -> int:
        """Pinocchio id of the frame ``name``.

        Raises:
            InputError: No frame of that name (:meth:`ClosedChain.frame_id`).
        """
        return self.chain.frame_id(name)


def load_feeder(device: str | FeederParameters = "projectile") -> Feeder:
    """Load a built-in device by name (``"projectile"`` or ``"charge"``) or from parameters.

    Raises:
        InputError: Unknown device name; a parameter out of range
            (:func:`~feeder.device.loop.check_device`).
        InertiaError: A non-physical inertia in the parameters.
        UnreachablePoseError: Parameters whose feeding cycle cannot be assembled.
    """
    if isinstance(device, FeederParameters):
        return Feeder(device)
    if not isinstance(device, str) or device not in DEVICES:
        raise InputError(f"unknown device {device!r}; choose one of {sorted(DEVICES)}")
    return Feeder(DEVICES[device])
