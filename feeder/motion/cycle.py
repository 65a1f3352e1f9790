"""The sampled feeding cycle: the prescribed laws (:mod:`feeder.motion.laws`), the closed loop
(:mod:`feeder.device.loop`) and the payload's path from the URDF model's forward kinematics
(:func:`feeder.chain.frame_motion`, every sample at once).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..chain import frame_motion
from ..device.feeder import Feeder
from ..device.loop import solve_loop, transmission_angle
from ..validation import check_elevation
from .laws import CycleSpec, prescribed_motion


@dataclass(frozen=True)
class CycleKinematics:
    """Sampled kinematics of one feeding cycle; N samples, world frame, SI units.

    The payload's path and the closure residual are the URDF model's forward kinematics
    (:func:`payload_kinematics`), computed when one of them is first read: the peaks of a
    cycle without its controlled run never read them (a tenth of a sweep case's time). A
    pickled copy carries them computed, without the device (its Pinocchio closures do not
    pickle): read back, its ``feeder`` is None.

    Attributes:
        elevation: ε [rad].
        spec: The timing.
        t: Times [s], (N,).
        stage: Stage number 1–3, (N,).
        gripped: 1 once the payload is gripped (t ≥ T1), else 0, int (N,).
        q, v, a: [φ1, r2, φ3, φ4] and derivatives, paper order, (N, 4).
        transmission_angle: μ [rad], (N,).
        feeder: The device.
    """

    elevation: float
    spec: CycleSpec
    t: np.ndarray
    stage: np.ndarray
    gripped: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    transmission_angle: np.ndarray
    feeder: Feeder = field(kw_only=True, repr=False, compare=False)

    def __getstate__(self) -> dict:
        """The fields with the payload's path computed, and no device (class docstring)."""
        return {**self.__dict__, "_payload": self._payload, "feeder": None}

    @cached_property
    def _payload(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        return payload_kinematics(self.feeder, self.q, self.v)

    @property
    def payload_position(self) -> np.ndarray:
        """Payload CG [m], (N, 3)."""
        return self._payload[0]

    @property
    def payload_velocity(self) -> np.ndarray:
        """Payload CG velocity [m/s], (N, 3)."""
        return self._payload[1]

    @property
    def payload_axis(self) -> np.ndarray:
        """Unit payload axis, nose first, (N, 3)."""
        return self._payload[2]

    @property
    def closure_residual(self) -> np.ndarray:
        """Distance between ``piston_pin`` and ``arm_pin`` [m], (N,): the loop's closure error
        in the URDF model."""
        return self._payload[3]


def payload_kinematics(
    feeder: Feeder, q: np.ndarray, v: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Payload CG position [m], velocity [m/s], axis (unit, nose first) and closure gap [m].

    Forward kinematics of the URDF's model, all samples at once
    (:func:`~feeder.chain.frame_motion`: no per-sample Python call).

    Args:
        feeder: The device.
        q, v: Paper-order coordinates and velocities, shape (N, 4).

    Returns:
        Position, velocity and axis, each (N, 3), world frame; closure gap ‖p_a − p_b‖ (N,)
        over every closure.
    """
    chain = feeder.chain
    cuts = [(closure.frame_a, closure.frame_b) for closure in chain.closures]
    names = ["projectile", *(name for pair in cuts for name in pair)]
    frames = frame_motion(chain, names, feeder.to_pinocchio(q), feeder.to_pinocchio(v))
    payload = frames["projectile"]
    gaps = [frames[a].position - frames[b].position for a, b in cuts]
    residual = np.linalg.norm(np.hstack(gaps), axis=1)
    return payload.position, payload.velocity, payload.rotation[:, :, 1], residual


def feeding_cycle(
    feeder: Feeder, elevation: float, spec: CycleSpec | None = None
) -> CycleKinematics:
    """Sample the feeding cycle at ``elevation`` ε [rad].

    The independent coordinates follow :func:`~feeder.motion.laws.prescribed_motion`; φ1, r2
    come from the closed form (:func:`~feeder.device.loop.solve_loop`); the payload's position,
    velocity and axis and the closure residual come from the forward kinematics of the
    URDF.

    Raises:
        ElevationError: ε outside the device's range.
        InputError: NaN, infinite or non-scalar ε, bad timing.
    """
    p = feeder.params
    spec = spec or CycleSpec()
    elevation = check_elevation(elevation, p.elevation_limits)
    t, x, dx, ddx = prescribed_motion(p, elevation, spec)
    loop = solve_loop(p, x[:, 0], x[:, 1], (dx[:, 0], dx[:, 1]), (ddx[:, 0], ddx[:, 1]))
    ends = spec.boundaries
    stage = np.where(t < ends[1], 1, np.where(t < ends[2], 2, 3))
    return CycleKinematics(
        feeder=feeder,
        elevation=elevation,
        spec=spec,
        t=t,
        stage=stage,
        gripped=(t >= ends[1]).astype(int),
        q=loop.q,
        v=loop.v,
        a=loop.a,
        transmission_angle=transmission_angle(loop.q),
    )
