"""The loading cycle run forward with the drives under position control, on any base: does the
payload arrive on the rammer's line when the hull rocks?

:func:`controlled_cycle` integrates the device's closed chain on the generic engine
(:func:`feeder.chain.simulate`, the device's :class:`~feeder.chain.ChainDynamics` with its base)
with the lift cylinder and the rack drive under the computed-torque law of
:mod:`feeder.dynamics.servo`, one smooth piece at a time — stage 1 without the payload, stages 2
and 3 with it, then a hold at the loading pose (:data:`HOLD`) — the state (and a lagged drive's
force) carried across each switch. The grip happens at rest in the reference; the run grips the
payload where the forearm is at that instant, with no impact modelled.

**The loading pose** is the pose at the end of stage 3, where the payload's axis lies along the
barrel (REFERENCE.md, "The feeding cycle"; :mod:`feeder.motion.workspace` calls it the ramming
pose). The *rammer's line* is the line the rammer pushes the payload along: through the
reference's payload centre of gravity at that instant, along its axis (the barrel's, at
elevation ε). In the device's axes as they move with the hull — the barrel and the device's
frame both sit on it. The run reports (:class:`LoadingPose`): the distance of the payload's
centre of gravity from the line [m], its offset along it [m], the angle between the payload's
axis and the line [rad], and the time after the end of stage 3 until both stay within
:data:`POSITION_TOLERANCE` and :data:`ANGLE_TOLERANCE` for the rest of the hold.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..exceptions import InputError
from ..motion.cycle import CycleKinematics, payload_kinematics
from ..validation import check_finite, check_number
from .drives import CylinderPressures, cylinder_pressures, rack_force
from .integrator import ADAMS_ORDER, lagrange_weights
from .models import FeederDynamics
from .servo import CycleServo, ServoGains

HOLD = 0.5
"""Time [s] the reference holds the loading pose after stage 3, over which the settling is
measured: 2.5 periods of the default 5 Hz position loop."""

POSITION_TOLERANCE = 1e-3
"""Accepted distance [m] of the payload's centre of gravity from the rammer's line (assumed: a
tenth of the radial clearance a 152 mm projectile's driving band meets in a loading tray)."""

ANGLE_TOLERANCE = 1e-3
"""Accepted angle [rad] between the payload's axis and the rammer's line (assumed: 1 mm over a
1 m tray)."""

RTOL, ATOL = 1e-6, 1e-8
"""The integrator's tolerances (per step, on q [rad, m], q̇ and the work [J]), looser than the
engine's defaults (1e-8, 1e-10): the closed loop damps the integration error instead of
amplifying it (unlike the force rule), so at ε = −4° and 70°, standing, over a bump and
rocking after a shot, the loading pose's distance from the rammer's line moves by at most
2.4e-9 m against rtol 1e-9 (the tolerance is 1e-3 m) and the standing cycle holds to 8.5e-8 rad
(the requirement is 1e-4), in a third of the time (measured)."""

MIN_STAGE_SAMPLES = ADAMS_ORDER + 1
"""Fewest steps in a stage: the feedforward's left limit at the grip is extrapolated (quartic)
from the stage's last five samples, as the force-rule run does."""

INERTIA_SAMPLES = 41
"""Poses along the cycle at which the reduced inertia of the gains is evaluated (its largest)."""

LOAD_CASES = ("empty tray", "payload gripped")
"""The load cases the gains are set for, in the order of ``FeederDynamics.cases`` (its
``gripped`` flag): stage 1, then stages 2 and 3 and the hold."""


@dataclass(frozen=True)
class LoadingPose:
    """The payload against the rammer's line at the end of stage 3 (module docstring).

    Attributes:
        time: End of stage 3 [s].
        off_line: Distance of the payload's centre of gravity from the rammer's line [m].
        along_line: Its offset along the line [m], positive towards the payload's nose.
        angle: Angle between the payload's axis and the line [rad].
        settle_time: Time [s] after ``time`` from which both stay within the tolerances until
            the end of the hold; None if they do not (within the hold).
        position_tolerance, angle_tolerance: The tolerances [m], [rad].
    """

    time: float
    off_line: float
    along_line: float
    angle: float
    settle_time: float | None
    position_tolerance: float = POSITION_TOLERANCE
    angle_tolerance: float = ANGLE_TOLERANCE


@dataclass(frozen=True)
class ControlledRun:
    """The cycle run forward under control, and the hold after it; M samples (the cycle's N
    samples, then the hold's), paper order, the device's axes as they move with the hull.

    Attributes:
        t: Times [s], (M,). cycle_samples: N, the samples that are the cycle's.
        q, v: [φ1, r2, φ3, φ4] and their rates, (M, 4). reference: The reference's q, (M, 4).
        applied: The drives' forces [piston N, forearm N·m], (M, 2).
        command: The commanded forces before the limits [N, N·m], (M, 2).
        saturated: Where the command passes a limit, bool (M, 2).
        pressures: The cylinder's chamber pressures of ``applied`` [Pa].
        rack_force: The rack force of ``applied`` [N], (M,).
        payload_error: |payload CG − reference's| [m], (M,).
        axis_error: Angle between the payload's axis and the reference's [rad], (M,).
        off_line: Distance of the payload CG from the rammer's line [m], (M,).
        closure_residual: Pin gap before projection [m], (M,).
        gains: The servo's settings; kp, kd: its gains [N/m, N·m/rad], [N·s/m, N·m·s/rad],
            (2, 2): a row per load case (:data:`LOAD_CASES`), a column per drive.
        inertia: The reduced inertias the gains were set for [kg, kg·m²], (2, 2), as kp.
        end: End of stage 3 [s].
    """

    t: np.ndarray
    cycle_samples: int
    q: np.ndarray
    v: np.ndarray
    reference: np.ndarray
    applied: np.ndarray
    command: np.ndarray
    saturated: np.ndarray
    pressures: CylinderPressures
    rack_force: np.ndarray
    payload_error: np.ndarray
    axis_error: np.ndarray
    off_line: np.ndarray
    along_line: np.ndarray
    closure_residual: np.ndarray
    gains: ServoGains
    kp: np.ndarray
    kd: np.ndarray
    inertia: np.ndarray
    end: float

    def tracking_error(self) -> tuple[float, float]:
        """Largest |Δφ3|, |Δφ4| [rad] over the cycle (the hold excluded)."""
        n = self.cycle_samples
        error = np.abs(self.q[:n] - self.reference[:n]).max(axis=0)
        return float(error[2]), float(error[3])

    def loading_pose(self) -> LoadingPose:
        """The errors at the end of stage 3 and the settling over the hold."""
        k = self.cycle_samples - 1
        within = (self.off_line[k:] <= POSITION_TOLERANCE) & (
            self.axis_error[k:] <= ANGLE_TOLERANCE
        )
        settle = None
        if within[-1]:
            outside = np.flatnonzero(~within)
            settle = 0.0 if outside.size == 0 else float(self.t[k + outside[-1] + 1] - self.end)
        return LoadingPose(
            time=self.end,
            off_line=float(self.off_line[k]),
            along_line=float(self.along_line[k]),
            angle=float(self.axis_error[k]),
            settle_time=settle,
        )

    def saturation(self) -> list[tuple[str, float, float]]:
        """The intervals where a drive's command passes its limit: (drive, first, last sample
        time [s]), in time order."""
        spans = []
        for i, name in enumerate(("cylinder", "rack drive")):
            flag = np.concatenate([[False], self.saturated[:, i], [False]]).astype(int)
            starts = np.flatnonzero(np.diff(flag) == 1)
            stops = np.flatnonzero(np.diff(flag) == -1) - 1
            spans += [
                (name, float(self.t[a]), float(self.t[b]))
                for a, b in zip(starts, stops, strict=True)
            ]
        return sorted(spans, key=lambda span: span[1])


def reduced_inertia(dyn: FeederDynamics, q: np.ndarray, gripped: bool = True) -> np.ndarray:
    """Largest diagonal of the device's inertia reduced to the actuated coordinates, Gᵀ M G
    (G: the velocity map from the actuated rates [ṙ2, φ̇4]), over the poses q (K, 4), paper
    order, with the payload gripped or the tray empty: [kg, kg·m²] (2,)."""
    case = dyn.cases[int(gripped)]
    partition = case.dynamics.partition
    model, data = case.model, case.data
    largest = np.zeros(2)
    for pose in dyn.to_pinocchio(q):
        g = np.column_stack([partition.velocity(pose, e) for e in np.eye(2)])
        mass = pin.crba(model, data, pose)
        mass = np.triu(mass) + np.triu(mass, 1).T
        largest = np.maximum(largest, np.diag(g.T @ mass @ g))
    return largest


def _pieces(kinematics: CycleKinematics) -> list[tuple[int, int]]:
    """(first, last) sample of each stage; consecutive stages share their boundary sample."""
    edges = np.flatnonzero(np.diff(kinematics.stage)) + 1
    firsts = np.concatenate([[0], edges])
    lasts = np.concatenate([edges, [kinematics.t.size - 1]])
    return [(int(a), int(b)) for a, b in zip(firsts, lasts, strict=True)]


def controlled_cycle(
    dyn: FeederDynamics,
    kinematics: CycleKinematics,
    feedforward: np.ndarray,
    gains: ServoGains,
    hold: float = HOLD,
    rtol: float = RTOL,
    atol: float = ATOL,
) -> ControlledRun:
    """Run the cycle forward with the drives under control (module docstring).

    Args:
        dyn: The device's dynamics models, on its base (``dyn.base``).
        kinematics: The reference: the prescribed cycle.
        feedforward: The reference's drive loads [piston force N, forearm moment N·m], (N, 2)
            (the inverse dynamics of the cycle standing level: the controller does not sense
            the hull).
        gains: The position loops.
        hold: Time [s] the loading pose is held after stage 3.
        rtol, atol: The integrator's tolerances (:func:`feeder.chain.simulate`; default
            :data:`RTOL`, :data:`ATOL`).

    Raises:
        InputError: Feedforward not finite or not (N, 2), a stage of fewer than
            :data:`MIN_STAGE_SAMPLES` samples, a hold that is not a positive time.
        IntegrationError: The run failed (a singular pose, unbounded accelerations).
    """
    from ..chain import simulate  # here: a cycle without this run skips the engine's import

    k = kinematics
    feedforward = check_finite("the controlled run's feedforward [N, N·m]", feedforward)
    if feedforward.shape != (k.t.size, 2):
        raise InputError(
            f"the controlled run's feedforward must be (N, 2) = ({k.t.size}, 2) [piston force "
            f"N, forearm moment N·m], got {feedforward.shape}"
        )
    if not check_number("the hold [s]", hold) > 0.0:
        raise InputError(f"the hold must be a positive time [s], got {hold!r}")
    shortest = min(b - a for a, b in _pieces(k))
    if shortest < MIN_STAGE_SAMPLES:
        raise InputError(
            f"the controlled run needs at least {MIN_STAGE_SAMPLES} steps a stage (the "
            f"feedforward's value before the grip is extrapolated from them), got {shortest} at "
            f"{k.spec.rate:g} Hz: sample faster"
        )
    actuated = [int(i) for i in dyn.index[[1, 3]]]  # r2, φ4 in Pinocchio's v
    poses = k.q[np.linspace(0, k.t.size - 1, INERTIA_SAMPLES).astype(int)]
    inertia = np.array([reduced_inertia(dyn, poses, gripped) for gripped in (False, True)])
    kp, kd = gains.gains(inertia)
    low, high = gains.limits(dyn.feeder.params)
    step = 1.0 / k.spec.rate
    hold_t = k.t[-1] + step * np.arange(max(round(hold / step), 1) + 1)
    segments = [
        (k.t[a : b + 1], k.q[a : b + 1], k.v[a : b + 1], k.a[a : b + 1], feedforward[a : b + 1],
         int(k.gripped[a]), k.gripped[b] != k.gripped[a])
        for a, b in _pieces(k)
    ]  # fmt: skip
    still = np.zeros((hold_t.size, 4))
    segments.append(
        (hold_t, np.tile(k.q[-1], (hold_t.size, 1)), still, still,
         np.tile(feedforward[-1], (hold_t.size, 1)), int(k.gripped[-1]), False)
    )  # fmt: skip
    q0, v0 = dyn.to_pinocchio(k.q[0]), dyn.to_pinocchio(k.v[0])
    x0 = None
    times, qs, vs, applied, commands, residuals = [], [], [], [], [], []
    for t, q, v, a, u, flag, grip in segments:
        if grip:  # the loads' left limit at the grip: extrapolated from the piece (quartic)
            u = u.copy()
            u[-1] = (
                lagrange_weights(np.arange(ADAMS_ORDER) - ADAMS_ORDER, 0.0)
                @ u[-1 - ADAMS_ORDER : -1]
            )
        servo = CycleServo(
            t, q[:, [1, 3]], v[:, [1, 3]], a[:, [1, 3]], u, actuated, kp[flag], kd[flag], low,
            high, gains.actuator_hz, x0,
        )  # fmt: skip
        run = simulate(
            dyn.cases[flag].dynamics, t, q0, v0, servo, rtol=rtol, atol=atol, loads=False
        )
        q0, v0 = run.q[-1], run.v[-1]
        if servo.n_states:
            x0 = run.controller[-1]
        force = run.actuation
        command = servo.command(t, run.q, run.v)
        for store, value in zip(
            (times, qs, vs, applied, commands, residuals),
            (t, run.q, run.v, force, command, run.residual),
            strict=True,
        ):
            if store:  # the boundary sample belongs to the piece it starts
                store[-1] = store[-1][:-1]
            store.append(value)
    t = np.concatenate(times)
    q, v = (dyn.to_paper(np.concatenate(x)) for x in (qs, vs))
    applied, command = np.concatenate(applied), np.concatenate(commands)
    reference = np.concatenate([k.q, np.tile(k.q[-1], (hold_t.size - 1, 1))])
    position, _, axis, _ = payload_kinematics(dyn.feeder, q, v)
    hold_rows = hold_t.size - 1
    reference_position = np.concatenate(
        [k.payload_position, np.tile(k.payload_position[-1], (hold_rows, 1))]
    )
    reference_axis = np.concatenate([k.payload_axis, np.tile(k.payload_axis[-1], (hold_rows, 1))])
    offset = position - k.payload_position[-1]
    line = k.payload_axis[-1]
    along = offset @ line
    return ControlledRun(
        t=t,
        cycle_samples=k.t.size,
        q=q,
        v=v,
        reference=reference,
        applied=applied,
        command=command,
        saturated=(command < low - 1e-9 * np.abs(low)) | (command > high + 1e-9 * np.abs(high)),
        pressures=cylinder_pressures(dyn.feeder.params, applied[:, 0]),
        rack_force=rack_force(dyn.feeder.params, applied[:, 1]),
        payload_error=np.linalg.norm(position - reference_position, axis=1),
        axis_error=_angle(axis, reference_axis),
        off_line=np.linalg.norm(offset - along[:, None] * line, axis=1),
        along_line=along,
        closure_residual=np.concatenate(residuals),
        gains=gains,
        kp=kp,
        kd=kd,
        inertia=inertia,
        end=float(k.t[-1]),
    )


def _angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angle [rad] between unit vectors, row by row, (M,): atan2(|a × b|, a · b), accurate
    near zero (arccos of the dot product loses half the digits there)."""
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.einsum("ij,ij->i", a, b))
