"""The feeding cycle (paper Fig. 7, REFERENCE.md): prescribed motion of φ3, φ4 and its samples.

Stage 1 (0 … T1): the forearm swings by ``swing`` about its hinge (vertical at loading) to the
conveyor, empty. Stage 2 (T1 … T1+T2): it swings back with the payload, gripped at the end of
stage 1, into the barrel plane. Stage 3 (… T1+T2+T3): the cylinder turns the arm up by 90° − ε,
laying the payload axis along the barrel at elevation ε. Every stage follows the quintic
rest-to-rest law h(s) = 10 s³ − 15 s⁴ + 6 s⁵ (zero velocity and acceleration at both ends).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from .device import Feeder
from .exceptions import InputError, check_elevation, check_finite
from .kinematics import arm_travel, dependent_coordinates, transmission_angle

MAX_SAMPLES = 1_000_000
"""Most samples a cycle may have. Measured per sample: the kinematics take ~0.5 kB (peak) and
7 µs, the whole cycle dynamics ~2 kB and 27 µs, so a million samples need ~2 GB and ~30 s (ten
million would need 20 GB); that is 250 kHz over the default 4 s cycle, far finer than any result
needs (1 kHz gives 4001 samples)."""


@dataclass(frozen=True)
class CycleSpec:
    """Timing of a feeding cycle; the numbers are checked and stored as floats.

    Attributes:
        durations: Durations (T1, T2, T3) [s] of stages 1–3. Default (1, 1, 2) s: Fig. 7 and
            section V give stage boundaries at 1 s and 2 s; T3 = 2 s is assumed.
        rate: Sample rate [Hz] (default 1 kHz).

    Raises:
        InputError: Durations that are not three finite positive times, a rate that is not
            finite and positive, or more than :data:`MAX_SAMPLES` samples.
    """

    durations: tuple[float, float, float] = (1.0, 1.0, 2.0)
    rate: float = 1000.0

    def __post_init__(self) -> None:
        durations = check_finite("stage durations", self.durations)
        if durations.shape != (3,) or np.any(durations <= 0.0):
            raise InputError(
                f"stage durations must be three positive times [s], got {self.durations!r}"
            )
        rate = check_finite("sample rate", self.rate)
        if rate.shape != () or rate <= 0.0:
            raise InputError(f"sample rate must be one positive number [Hz], got {self.rate!r}")
        count = round(float(durations.sum()) * float(rate)) + 1
        if count > MAX_SAMPLES:
            raise InputError(
                f"sample rate {float(rate):g} Hz over a {durations.sum():g} s cycle gives "
                f"{count} samples, more than the {MAX_SAMPLES} allowed"
            )
        object.__setattr__(self, "durations", tuple(float(d) for d in durations))
        object.__setattr__(self, "rate", float(rate))

    @property
    def boundaries(self) -> np.ndarray:
        """Stage start and end times [0, T1, T1+T2, T1+T2+T3] [s], shape (4,)."""
        return np.concatenate([[0.0], np.cumsum(self.durations)])

    def times(self) -> np.ndarray:
        """Sample times [s], shape (N,), from 0 to the cycle's end inclusive."""
        count = int(round(self.boundaries[-1] * self.rate))
        return np.arange(count + 1) / self.rate


def rest_to_rest(s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Quintic law h(s) = 10s³ − 15s⁴ + 6s⁵ and its derivatives h′, h″ for s in [0, 1]."""
    s = np.clip(s, 0.0, 1.0)
    h = s**3 * (10.0 - 15.0 * s + 6.0 * s**2)
    dh = 30.0 * s**2 * (1.0 - s) ** 2
    ddh = 60.0 * s * (1.0 - s) * (1.0 - 2.0 * s)
    return h, dh, ddh


@dataclass(frozen=True)
class CycleKinematics:
    """Sampled kinematics of one feeding cycle; N samples, world frame, SI units.

    Attributes:
        elevation: ε [rad].
        spec: The timing.
        t: Times [s], (N,).
        stage: Stage number 1–3, (N,).
        payload: 1 once the payload is gripped (t ≥ T1), else 0, (N,).
        q, v, a: [φ1, r2, φ3, φ4] and derivatives, paper order, (N, 4).
        projectile_position: Payload CG [m], (N, 3).
        projectile_velocity: Payload CG velocity [m/s], (N, 3).
        projectile_axis: Unit payload axis, nose first, (N, 3).
        transmission_angle: μ [rad], (N,).
        closure_residual: Distance between ``piston_pin`` and ``arm_pin`` [m], (N,).
    """

    elevation: float
    spec: CycleSpec
    t: np.ndarray
    stage: np.ndarray
    payload: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    projectile_position: np.ndarray
    projectile_velocity: np.ndarray
    projectile_axis: np.ndarray
    transmission_angle: np.ndarray
    closure_residual: np.ndarray

    def columns(self) -> dict[str, np.ndarray]:
        """The contract's kinematic columns (``t`` … ``closure_residual``) by name."""
        cols: dict[str, np.ndarray] = {
            "t": self.t,
            "stage": self.stage,
            "payload": self.payload,
        }
        for prefix, values in (("q", self.q), ("v", self.v), ("a", self.a)):
            for k, name in enumerate(("phi1", "r2", "phi3", "phi4")):
                cols[f"{prefix}_{name}"] = values[:, k]
        for k, axis in enumerate("xyz"):
            cols[f"projectile_{axis}"] = self.projectile_position[:, k]
        cols["projectile_speed"] = np.linalg.norm(self.projectile_velocity, axis=1)
        for k, axis in enumerate("xyz"):
            cols[f"projectile_axis_{axis}"] = self.projectile_axis[:, k]
        cols["transmission_angle_deg"] = np.degrees(self.transmission_angle)
        cols["closure_residual"] = self.closure_residual
        return cols


def payload_kinematics(
    feeder: Feeder, q: np.ndarray, v: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Payload CG position [m], velocity [m/s], axis (unit, nose first) and closure gap [m].

    Pinocchio's forward kinematics of the URDF at each sample.

    Args:
        feeder: The device.
        q, v: Paper-order coordinates and velocities, shape (N, 4).

    Returns:
        Position, velocity and axis, each (N, 3), world frame; closure gap ‖p_a − p_b‖ (N,).
    """
    chain = feeder.chain
    model, data = chain.model, chain.data
    payload_id = feeder.frame_id("projectile")
    count = q.shape[0]
    position, velocity, axis = (np.empty((count, 3)) for _ in range(3))
    residual = np.empty(count)
    q_pin, v_pin = feeder.to_pinocchio(q), feeder.to_pinocchio(v)
    for i in range(count):
        pin.forwardKinematics(model, data, q_pin[i], v_pin[i])
        placement = pin.updateFramePlacement(model, data, payload_id)
        position[i] = placement.translation
        axis[i] = placement.rotation[:, 1]
        velocity[i] = pin.getFrameVelocity(model, data, payload_id, pin.LOCAL_WORLD_ALIGNED).linear
        residual[i] = np.linalg.norm(chain.placed_residual())
    return position, velocity, axis, residual


def prescribed_motion(
    feeder: Feeder, elevation: float, spec: CycleSpec
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Times and the independent coordinates' laws: t (N,), and (N, 2) arrays of [φ3, φ4],
    their rates and accelerations."""
    p = feeder.params
    t = spec.times()
    ends = spec.boundaries
    x = np.zeros((t.size, 2))
    dx, ddx = np.zeros_like(x), np.zeros_like(x)
    stages = (
        (1, 1, 0.0, p.swing),  # (stage, coordinate: 0 = φ3, 1 = φ4, start, change)
        (2, 1, p.swing, -p.swing),
        (3, 0, p.phi3_load, arm_travel(elevation)),
    )
    x[:, 0] = p.phi3_load
    for stage, k, start, change in stages:
        duration = ends[stage] - ends[stage - 1]
        inside = (t >= ends[stage - 1]) & (t <= ends[stage])
        h, dh, ddh = rest_to_rest((t[inside] - ends[stage - 1]) / duration)
        x[inside, k] = start + change * h
        dx[inside, k] = change * dh / duration
        ddx[inside, k] = change * ddh / duration**2
    return t, x, dx, ddx


def feeding_cycle(
    feeder: Feeder, elevation: float, spec: CycleSpec | None = None
) -> CycleKinematics:
    """Sample the feeding cycle at ``elevation`` ε [rad].

    The independent coordinates follow :func:`prescribed_motion`; φ1, r2 come from the closed
    form (:func:`~feeder.kinematics.dependent_coordinates`); the payload's position, velocity
    and axis and the closure residual come from Pinocchio's forward kinematics of the URDF.

    Raises:
        ElevationError: ε outside the device's range.
        InputError: NaN, infinite or non-scalar ε, bad timing.
    """
    p = feeder.params
    spec = spec or CycleSpec()
    elevation = check_elevation(elevation, p.elevation_limits)
    t, x, dx, ddx = prescribed_motion(feeder, elevation, spec)
    loop = dependent_coordinates(p, x[:, 0], dx[:, 0], ddx[:, 0])
    q = np.column_stack([loop.phi1, loop.r2, x[:, 0], x[:, 1]])
    v = np.column_stack([loop.dphi1, loop.dr2, dx[:, 0], dx[:, 1]])
    a = np.column_stack([loop.ddphi1, loop.ddr2, ddx[:, 0], ddx[:, 1]])

    position, velocity, axis, residual = payload_kinematics(feeder, q, v)
    ends = spec.boundaries
    stage = np.where(t < ends[1], 1, np.where(t < ends[2], 2, 3))
    return CycleKinematics(
        elevation=elevation,
        spec=spec,
        t=t,
        stage=stage,
        payload=(t >= ends[1]).astype(int),
        q=q,
        v=v,
        a=a,
        projectile_position=position,
        projectile_velocity=velocity,
        projectile_axis=axis,
        transmission_angle=transmission_angle(p, x[:, 0]),
        closure_residual=residual,
    )
