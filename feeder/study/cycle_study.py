"""The standard study of one loading cycle: Pinocchio's loads cross-checked by the hand-derived
Lagrange equations (the ``feeder cycle`` command; :func:`feeder.outputs.write_cycle_outputs`
writes it as ``cycle.csv`` and the paper's Figs. 4, 8, 10–15)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..chain import BaseMotion
from ..device.feeder import Feeder
from ..dynamics.cycle import CycleDynamics, cycle_dynamics
from ..dynamics.servo import ServoGains
from ..motion.laws import CycleSpec
from ..paper.lagrange import LagrangeLoads, lagrange_loads
from .columns import cycle_columns
from .peaks import Peak, cycle_peaks
from .summary import controlled_lines, growth_lines, peak_lines, peak_notes


@dataclass(frozen=True)
class CycleStudy:
    """One cycle's results from both computations.

    Attributes:
        feeder: The device.
        dynamics: Pinocchio: kinematics, loads, reactions, drives, forward run.
        lagrange: The hand-derived equations' loads and multipliers on the same motion, the
            base standing level.
        standing: On a moving or tilted base, the same cycle standing level (the cross-check's
            and the comparison's); None when the base stands level (``dynamics`` is that).
    """

    feeder: Feeder
    dynamics: CycleDynamics
    lagrange: LagrangeLoads
    standing: CycleDynamics | None = None

    @property
    def level(self) -> CycleDynamics:
        """The cycle standing level."""
        return self.dynamics if self.standing is None else self.standing

    def columns(self) -> dict[str, np.ndarray]:
        """Every column of ``cycle.csv`` (:data:`~feeder.study.columns.COLUMNS`), each (N,)."""
        return cycle_columns(self.dynamics, self.lagrange)

    def peaks(self) -> list[Peak]:
        """Peak of every actuator load, drive and joint reaction, with its time."""
        return cycle_peaks(self.dynamics)

    def against_level(self) -> list[tuple[Peak, Peak]] | None:
        """On a moving or tilted base, every peak with the same quantity's peak in the cycle
        standing level (:meth:`peaks` order); None when the base stands level."""
        if self.standing is None:
            return None
        level = {peak.name: peak for peak in cycle_peaks(self.standing)}
        return [(peak, level[peak.name]) for peak in self.peaks()]

    def cross_check(self) -> tuple[float, float]:
        """Largest |Lagrange − Pinocchio| of the piston force [N] and forearm moment [N·m], the
        base standing level."""
        loads = self.level.loads
        return (
            float(np.abs(self.lagrange.piston_force - loads.piston_force).max()),
            float(np.abs(self.lagrange.forearm_torque - loads.forearm_torque).max()),
        )

    def summary(self) -> str:
        """Peaks, the forward run's accuracy and the cross-check as text, a quantity a line."""
        kinematics, d = self.dynamics.kinematics, self.dynamics
        lines = [
            f"feeding cycle at elevation {np.degrees(kinematics.elevation):.2f}°, "
            f"{kinematics.t.size} samples over {kinematics.t[-1]:.3f} s"
        ]
        if d.base is not None:
            lines.append(f"  base: {d.base.describe()} (vectors in the device's moving axes)")
        peaks = self.peaks()
        lines += peak_lines(peaks)
        lines += peak_notes(self.feeder.params, peaks)
        pairs = self.against_level()
        if pairs is not None:
            lines += growth_lines(pairs)
        if d.forward is None and d.controlled is None:
            reason = " (the base moves)" if d.base is not None and d.base.timed else ""
            lines.append(f"  forward run (force rule): skipped{reason}")
        elif d.forward is not None:
            phi3, phi4 = d.tracking_error()
            lines.append(
                f"  forward run (force rule): |Δφ3| ≤ {phi3:.2e} rad, |Δφ4| ≤ {phi4:.2e} rad, "
                f"pin gap ≤ {d.closure_residual():.2e} m"
            )
        if d.controlled is not None:
            lines += controlled_lines(d.controlled, d)
        force, torque = self.cross_check()
        level = "" if self.standing is None else " (the cycle standing level)"
        lines.append(
            f"  Lagrange equations vs Pinocchio{level}: piston force within {force:.1e} N, "
            f"forearm moment within {torque:.1e} N·m"
        )
        return "\n".join(lines)


def run_cycle_study(
    feeder: Feeder,
    elevation: float,
    spec: CycleSpec | None = None,
    progress: bool = False,
    forward: bool = True,
    base: BaseMotion | None = None,
    controlled: ServoGains | None = None,
) -> CycleStudy:
    """Dynamics of one cycle at ``elevation`` [rad] by Pinocchio and by the Lagrange equations.

    Args:
        feeder: The device.
        elevation: ε [rad], inside the device's range.
        spec: Stage durations and sample rate (default :class:`~feeder.motion.laws.CycleSpec`).
        progress: Show a progress bar on a terminal.
        forward: Run the force-rule forward simulation (False skips it and its ``forward_*``
            columns).
        base: The vehicle's motion (:func:`~feeder.dynamics.cycle.cycle_dynamics`); the cycle
            standing level is computed too, for the cross-check and the comparison.
        controlled: Run the cycle forward with the drives under these position loops
            (:func:`~feeder.dynamics.cycle.cycle_dynamics`), None to skip it.

    Raises:
        ElevationError, InputError: Bad elevation or timing.
        ForwardDivergenceError: The forward run drifted (sample faster, or ``forward=False``).
        IntegrationError: The controlled run failed.
    """
    dynamics = cycle_dynamics(
        feeder,
        elevation,
        spec,
        base=base,
        progress=progress,
        forward=forward,
        controlled=controlled,
    )
    standing = None
    if base is not None:
        standing = cycle_dynamics(feeder, elevation, spec, forward=False)
    k = dynamics.kinematics
    lagrange = lagrange_loads(feeder.params, k.q, k.v, k.a, k.gripped)
    return CycleStudy(feeder, dynamics, lagrange, standing)
