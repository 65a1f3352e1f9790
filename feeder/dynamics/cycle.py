"""The loading cycle's dynamics in one call: loads, every joint reaction, drives, force-rule run.

:func:`cycle_dynamics` samples the cycle (:func:`~feeder.motion.cycle.feeding_cycle`), solves
the closed chain's inverse dynamics (:mod:`feeder.dynamics.inverse`), the joint reactions
(:mod:`feeder.dynamics.reactions`) and the drives (:mod:`feeder.dynamics.drives`), and
integrates the forward dynamics driven by the computed piston force and forearm moment
(:mod:`feeder.dynamics.forward`). Vectors are in the world frame.

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
from typing import TYPE_CHECKING

import numpy as np
from tqdm import tqdm

from ..chain import BaseMotion
from ..device.feeder import Feeder
from ..device.parameters import VEHICLE_FORWARD
from ..exceptions import ForwardDivergenceError, InputError
from ..motion.cycle import CycleKinematics, feeding_cycle
from ..motion.laws import CycleSpec
from .drives import CylinderPressures, cylinder_pressures, rack_force
from .forward import ForceRule, ForwardMotion, simulate_feeder
from .inverse import ActuatorLoads, SampledMotion, actuator_loads
from .models import feeder_dynamics
from .reactions import JointReactions, pin_reactions
from .servo import ServoGains

if TYPE_CHECKING:
    from .loading import ControlledRun

FORWARD_TOLERANCE = 1e-4
"""Largest accepted |forward − prescribed| of φ3 and φ4 [rad] (issue 3's requirement). The
default cycle at 1 kHz tracks to < 1e-6 rad, at 500 Hz to 4e-5 rad (table above)."""


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
            forward run was skipped (``cycle_dynamics(..., forward=False)``, or a moving base).
        base: The vehicle's motion, None for standing level.
        controlled: The cycle run forward with the drives under position control
            (:mod:`feeder.dynamics.loading`), or None if not asked for.
    """

    kinematics: CycleKinematics
    loads: ActuatorLoads
    reactions: JointReactions
    pressures: CylinderPressures
    rack_force: np.ndarray
    forward: ForwardMotion | None
    base: BaseMotion | None = None
    controlled: ControlledRun | None = None

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


def _check_tracking(run: ForwardMotion, kinematics: CycleKinematics) -> None:
    drift = np.abs(run.q[:, 2:] - kinematics.q[:, 2:]).max(axis=0)
    if np.any(drift > FORWARD_TOLERANCE):
        raise ForwardDivergenceError(
            f"the force-rule forward run drifted from the prescribed motion by |Δφ3| = "
            f"{drift[0]:.2e} rad, |Δφ4| = {drift[1]:.2e} rad (tolerance {FORWARD_TOLERANCE:g} "
            f"rad) at {kinematics.spec.rate:g} Hz: the force-driven mechanism is unstable and "
            f"amplifies the integration error; sample faster (e.g. --rate "
            f"{2 * kinematics.spec.rate:g}), shorten the stages, or skip the forward run "
            "(feeder cycle --no-forward)"
        )


def cycle_dynamics(
    feeder: Feeder,
    elevation: float,
    spec: CycleSpec | None = None,
    *,
    base: BaseMotion | None = None,
    progress: bool = False,
    forward: bool = True,
    controlled: ServoGains | None = None,
) -> CycleDynamics:
    """Loads, joint reactions, drives and force-rule simulation of one loading cycle.

    The device's dynamics models on ``base`` are built at the first cycle and reused by the
    next ones of the same two objects in this thread (:func:`~.models.feeder_dynamics`).

    Args:
        feeder: The device.
        elevation: ε [rad].
        spec: Stage durations and sample rate (default :class:`~feeder.motion.laws.CycleSpec`).
        base: The vehicle's motion (:class:`~feeder.chain.BaseMotion`, its forward
            axis :data:`~feeder.device.parameters.VEHICLE_FORWARD`), None for standing level.
            The cycle's motion is relative to the hull; every vector is in the device's axes
            as they move with it (the mount's also in the level axes).
        progress: Show a progress bar over the phases on a terminal (none when stderr is not
            one, e.g. in CI logs).
        forward: Integrate the forward dynamics driven by the computed loads (the force-rule
            check); False skips it (``CycleDynamics.forward`` is then None). It runs on a
            standing or tilted base only: on a moving one it is skipped (the base's motion is
            not a force the run can take).
        controlled: Run the cycle forward with the cylinder and the rack drive under these
            position loops (:func:`~feeder.dynamics.loading.controlled_cycle`, on any base;
            the feedforward is the cycle's loads standing level), None to skip it.

    Raises:
        ElevationError, InputError: Bad elevation or timing, ``controlled`` not a ServoGains.
        SingularPoseError: A pose within 5° of the toggle.
        ForwardDivergenceError: The forward run left the joints' end stops, or ended farther
            than :data:`FORWARD_TOLERANCE` from the prescribed motion.
        IntegrationError: The controlled run failed (a singular pose on the way).
    """
    spec = spec or CycleSpec()
    if base is not None and not isinstance(base, BaseMotion):
        raise InputError(f"base must be a BaseMotion, got {base!r}")
    if base is not None and base.forward != VEHICLE_FORWARD:
        raise InputError(
            f"the device's vehicle faces {list(VEHICLE_FORWARD)} (the turret at 0° azimuth): "
            f"BaseMotion(..., forward=VEHICLE_FORWARD), got forward {list(base.forward)}"
        )
    if controlled is not None and not isinstance(controlled, ServoGains):
        raise InputError(f"controlled must be a ServoGains or None, got {controlled!r}")
    forward = forward and (base is None or not base.timed)
    steps = ["kinematics", "inverse dynamics", "joint reactions"]
    if forward:
        steps.append("forward simulation")
    if controlled is not None:
        steps.append("controlled run")
    quiet = None if progress else True  # None: tqdm shows the bar only on a terminal
    with tqdm(total=len(steps), desc="cycle", disable=quiet) as bar:
        bar.set_postfix_str(steps[0])
        kinematics = feeding_cycle(feeder, elevation, spec)
        dyn = feeder_dynamics(feeder, base)
        bar.update()
        bar.set_postfix_str(steps[1])
        # The sampled cycle closes the loop away from the toggle by construction: the device's
        # travel was checked when it was loaded (check_device), so no check_cycle_motion here.
        motion = SampledMotion(kinematics.q, kinematics.v, kinematics.a, kinematics.gripped)
        loads = actuator_loads(dyn, motion, kinematics.t)
        bar.update()
        bar.set_postfix_str(steps[2])
        reactions = pin_reactions(dyn, loads)
        bar.update()
        run = None
        if forward:
            bar.set_postfix_str(steps[3])
            rule = ForceRule(
                t=kinematics.t,
                stage=kinematics.stage,
                gripped=kinematics.gripped,
                piston_force=loads.piston_force,
                forearm_torque=loads.forearm_torque,
            )
            run = simulate_feeder(dyn, rule, kinematics.q[0], kinematics.v[0])
            _check_tracking(run, kinematics)
            bar.update()
        servo_run = None
        if controlled is not None:
            from .loading import controlled_cycle  # here: only this run imports the engine's

            bar.set_postfix_str(steps[-1])
            standing = loads if base is None else actuator_loads(feeder_dynamics(feeder), motion)
            feedforward = np.column_stack([standing.piston_force, standing.forearm_torque])
            servo_run = controlled_cycle(dyn, kinematics, feedforward, controlled)
            bar.update()
    return CycleDynamics(
        kinematics=kinematics,
        loads=loads,
        reactions=reactions,
        pressures=cylinder_pressures(feeder.params, loads.piston_force),
        rack_force=rack_force(feeder.params, loads.forearm_torque),
        forward=run,
        base=base,
        controlled=servo_run,
    )
