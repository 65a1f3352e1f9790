"""The loading cycle's dynamics in one call: loads, every joint reaction, drives, force-rule run.

:func:`cycle_dynamics` samples the cycle (:func:`~feeder.cycle.feeding_cycle`), solves the
closed chain's inverse dynamics (:mod:`feeder.dynamics`), the joint reactions
(:mod:`feeder.reactions`) and the drives (:mod:`feeder.hydraulics`), and integrates the forward
dynamics driven by the computed piston force and forearm moment (:mod:`feeder.simulation`).
:meth:`CycleDynamics.columns` gives the ``cycle.csv`` contract columns (REFERENCE.md) except
the ``lagrange_*`` ones; vectors are in the world frame.

The forward run is a check, and it needs a fine enough step: the force-driven mechanism is
unstable (a deviation grows like e^(4…6 t)), so the integration error at a coarse step is
amplified over the cycle. Largest |Δφ3|, |Δφ4| [rad] over both devices and ε = −4°, 10°, 30°,
50°, 70° with the default stage durations (1, 1, 2) s, by sample rate:

=========  ======  ======  ======  ======  ======  ======  ======
rate [Hz]  50      100     200     300     400     500     1000
=========  ======  ======  ======  ======  ======  ======  ======
error      1.6     8.7e-2  3.4e-3  4.8e-4  1.2e-4  3.8e-5  7.1e-7
=========  ======  ======  ======  ======  ======  ======  ======

(at 10–20 Hz, and at 50 Hz for ε = −4°, the run diverges past the piston's end stop). Longer
stages give the instability more time: with durations (2, 2, 4) s the run drifts by radians even
at 1 kHz. So the run is checked: a forward motion that leaves :data:`FORWARD_TOLERANCE` of the
prescribed one raises :class:`~feeder.exceptions.ForwardDivergenceError` saying so (sample
faster, shorten the stages, or skip the run with ``forward=False``). The kinematics, loads and
reactions are exact at each sample and need no minimum rate.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from tqdm import tqdm

from .cycle import CycleKinematics, CycleSpec, feeding_cycle
from .device import Feeder
from .dynamics import ActuatorLoads, FeederDynamics, inverse_dynamics
from .exceptions import ForwardDivergenceError, InputError
from .hydraulics import CylinderPressures, cylinder_pressures, rack_force
from .reactions import JointReactions, joint_reactions
from .simulation import ForceRule, ForwardMotion, simulate

FORWARD_TOLERANCE = 1e-4
"""Largest accepted |forward − prescribed| of φ3 and φ4 [rad] (issue 3's requirement). The
default cycle at 1 kHz tracks to < 1e-6 rad, at 500 Hz to 4e-5 rad (table above)."""


@dataclass(frozen=True)
class Peak:
    """Largest magnitude of one quantity over the cycle.

    Attributes:
        name: Column name.
        value: Value at the peak (signed for signed quantities) [unit].
        unit: SI unit.
        time: Time of the peak [s].
    """

    name: str
    value: float
    unit: str
    time: float


@dataclass(frozen=True)
class CycleDynamics:
    """Kinematics, loads, joint reactions, drives and forward run of one loading cycle.

    Attributes:
        kinematics: The prescribed motion.
        loads: Piston force, forearm moment and pin force (inverse dynamics).
        reactions: Reaction wrenches of every joint and the grip.
        pressures: Lift-cylinder chamber pressures.
        rack_force: Forearm rack force [N], shape (N,).
        forward: Motion integrated from the piston force and forearm moment, or None if the
            forward run was skipped (``cycle_dynamics(..., forward=False)``).
    """

    kinematics: CycleKinematics
    loads: ActuatorLoads
    reactions: JointReactions
    pressures: CylinderPressures
    rack_force: np.ndarray
    forward: ForwardMotion | None

    def _vectors(self) -> dict[str, tuple[np.ndarray, str]]:
        """World-frame vector quantities by column name, with their units."""
        joints = self.reactions.joints
        return {
            "cylinder_frame_force": (joints["cylinder_frame"].force, "N"),
            "piston_cylinder_force": (joints["piston_cylinder"].constraint_force, "N"),
            "piston_cylinder_moment": (joints["piston_cylinder"].moment, "N·m"),
            "piston_arm_force": (self.reactions.closure_force, "N"),
            "arm_frame_force": (joints["arm_frame"].force, "N"),
            "arm_frame_moment": (joints["arm_frame"].constraint_moment, "N·m"),
            "forearm_joint_force": (joints["forearm_arm"].force, "N"),
            "forearm_joint_moment": (joints["forearm_arm"].constraint_moment, "N·m"),
            "grip_force": (self.reactions.grip_force, "N"),
            "grip_moment": (self.reactions.grip_moment, "N·m"),
        }

    def columns(self) -> dict[str, np.ndarray]:
        """Every contract column but ``lagrange_*``, plus the extra reactions and drives.

        Magnitude columns are followed by their ``_x``, ``_y``, ``_z`` world components:

        * ``cylinder_frame_force``, ``arm_frame_force``, ``forearm_joint_force``: the force the
          frame (or the arm) exerts on the cylinder (arm, forearm) through the joint [N];
        * ``arm_frame_moment``, ``forearm_joint_moment``: the constraint moment about the joint
          origin, the joint's own axis excluded [N·m]. The cylinder–frame joint has no such
          column: its constraint moment is zero by construction (the cylinder and piston move
          in the x–y plane and the out-of-plane pin force is taken as λz = 0, see
          :mod:`feeder.dynamics`);
        * ``piston_cylinder_force``: the guides' side force on the piston (axial part, the
          piston force, excluded) [N]; ``piston_cylinder_moment``: their moment on the piston
          about its centre of gravity S [N·m];
        * ``piston_arm_force``: the force the piston exerts on the arm at the pin [N];
        * ``grip_force``, ``grip_moment``: the wrench the forearm exerts on the payload, about
          its centre of gravity (zero before the grip) [N], [N·m].

        Drives: ``cylinder_cap_pressure``, ``cylinder_rod_pressure`` [Pa], ``rack_force`` [N].
        Forward run: ``forward_q_phi3``, ``forward_q_phi4`` [rad], ``forward_closure_residual``
        [m], absent if the run was skipped.
        """
        cols = dict(self.kinematics.columns())
        cols["piston_force"] = self.loads.piston_force
        cols["forearm_torque"] = self.loads.forearm_torque
        for name, (vector, _) in self._vectors().items():
            cols[name] = np.linalg.norm(vector, axis=1)
            for k, axis in enumerate("xyz"):
                cols[f"{name}_{axis}"] = vector[:, k]
        cols["cylinder_cap_pressure"] = self.pressures.cap
        cols["cylinder_rod_pressure"] = self.pressures.rod
        cols["rack_force"] = self.rack_force
        if self.forward is not None:
            cols["forward_q_phi3"] = self.forward.q[:, 2]
            cols["forward_q_phi4"] = self.forward.q[:, 3]
            cols["forward_closure_residual"] = self.forward.closure_residual
        return cols

    def _forward_run(self) -> ForwardMotion:
        if self.forward is None:
            raise InputError("this cycle has no forward run (computed with forward=False)")
        return self.forward

    def tracking_error(self) -> tuple[float, float]:
        """Largest |forward − prescribed| of φ3 and φ4 over the cycle [rad].

        Raises:
            InputError: The forward run was skipped.
        """
        error = np.abs(self._forward_run().q - self.kinematics.q).max(axis=0)
        return float(error[2]), float(error[3])

    def closure_residual(self) -> float:
        """Largest pin gap of the forward run [m].

        Raises:
            InputError: The forward run was skipped.
        """
        return float(self._forward_run().closure_residual.max())

    def peaks(self) -> list[Peak]:
        """Peak of each actuator load, drive and joint reaction magnitude, with its time."""
        t = self.kinematics.t
        signed = {
            "piston_force": (self.loads.piston_force, "N"),
            "cylinder_cap_pressure": (self.pressures.cap, "Pa"),
            "cylinder_rod_pressure": (self.pressures.rod, "Pa"),
            "forearm_torque": (self.loads.forearm_torque, "N·m"),
            "rack_force": (self.rack_force, "N"),
        }
        magnitudes = {
            name: (np.linalg.norm(vector, axis=1), unit)
            for name, (vector, unit) in self._vectors().items()
        }
        peaks = []
        for name, (values, unit) in (signed | magnitudes).items():
            k = int(np.argmax(np.abs(values)))
            peaks.append(Peak(name, float(values[k]), unit, float(t[k])))
        return peaks

    def summary(self) -> str:
        """Peaks and the forward run's accuracy as text, one quantity per line."""
        lines = [
            f"feeding cycle at elevation {np.degrees(self.kinematics.elevation):.2f}°, "
            f"{self.kinematics.t.size} samples over {self.kinematics.t[-1]:.3f} s"
        ]
        peaks = self.peaks()
        width = max(len(peak.name) for peak in peaks)
        for peak in peaks:
            value = (
                f"{peak.value / 1e5:12.3f} bar"
                if peak.unit == "Pa"
                else (f"{peak.value:12.3f} {peak.unit}")
            )
            lines.append(f"  peak {peak.name:<{width}} {value}  at t = {peak.time:.3f} s")
        if self.forward is None:
            lines.append("  forward run (force rule): skipped")
        else:
            phi3, phi4 = self.tracking_error()
            lines.append(
                f"  forward run (force rule): |Δφ3| ≤ {phi3:.2e} rad, |Δφ4| ≤ {phi4:.2e} rad, "
                f"pin gap ≤ {self.closure_residual():.2e} m"
            )
        return "\n".join(lines)


def _check_tracking(run: ForwardMotion, kinematics: CycleKinematics) -> None:
    drift = np.abs(run.q[:, 2:] - kinematics.q[:, 2:]).max(axis=0)
    if np.any(drift > FORWARD_TOLERANCE):
        raise ForwardDivergenceError(
            f"the force-rule forward run drifted from the prescribed motion by |Δφ3| = "
            f"{drift[0]:.2e} rad, |Δφ4| = {drift[1]:.2e} rad (tolerance {FORWARD_TOLERANCE:g} "
            f"rad) at {kinematics.spec.rate:g} Hz: the force-driven mechanism is unstable and "
            "amplifies the integration error; sample faster (≥ 500 Hz for the default stages), "
            "shorten the stages, or skip the forward run (feeder cycle --no-forward)"
        )


def cycle_dynamics(
    feeder: Feeder,
    elevation: float,
    spec: CycleSpec | None = None,
    *,
    progress: bool = False,
    forward: bool = True,
) -> CycleDynamics:
    """Loads, joint reactions, drives and force-rule simulation of one loading cycle.

    Args:
        feeder: The device.
        elevation: ε [rad].
        spec: Stage durations and sample rate (default :class:`~feeder.cycle.CycleSpec`).
        progress: Show a progress bar over the phases on a terminal (none when stderr is not
            one, e.g. in CI logs).
        forward: Integrate the forward dynamics driven by the computed loads (the force-rule
            check); False skips it (``CycleDynamics.forward`` is then None).

    Raises:
        ElevationError, InputError: Bad elevation or timing.
        SingularPoseError: A pose within 5° of the toggle.
        ForwardDivergenceError: The forward run left the joints' end stops, or ended farther
            than :data:`FORWARD_TOLERANCE` from the prescribed motion.
    """
    spec = spec or CycleSpec()
    steps = ["kinematics", "inverse dynamics", "joint reactions"]
    if forward:
        steps.append("forward simulation")
    quiet = None if progress else True  # None: tqdm shows the bar only on a terminal
    with tqdm(total=len(steps), desc="cycle", disable=quiet) as bar:
        bar.set_postfix_str(steps[0])
        kinematics = feeding_cycle(feeder, elevation, spec)
        dyn = FeederDynamics(feeder)
        bar.update()
        bar.set_postfix_str(steps[1])
        loads = inverse_dynamics(dyn, kinematics.q, kinematics.v, kinematics.a, kinematics.payload)
        bar.update()
        bar.set_postfix_str(steps[2])
        reactions = joint_reactions(dyn, loads)
        bar.update()
        run = None
        if forward:
            bar.set_postfix_str(steps[3])
            rule = ForceRule(
                t=kinematics.t,
                stage=kinematics.stage,
                payload=kinematics.payload,
                piston_force=loads.piston_force,
                forearm_torque=loads.forearm_torque,
            )
            run = simulate(dyn, rule, kinematics.q[0], kinematics.v[0])
            _check_tracking(run, kinematics)
            bar.update()
    return CycleDynamics(
        kinematics=kinematics,
        loads=loads,
        reactions=reactions,
        pressures=cylinder_pressures(feeder.params, loads.piston_force),
        rack_force=rack_force(feeder.params, loads.forearm_torque),
        forward=run,
    )
