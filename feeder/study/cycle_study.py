"""The standard study of one loading cycle: Pinocchio's loads cross-checked by the hand-derived
Lagrange equations (the ``feeder cycle`` command; :func:`feeder.outputs.write_cycle_outputs`
writes it as ``cycle.csv`` and the paper's Figs. 4, 8, 10–15)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..device.feeder import Feeder
from ..dynamics.cycle import CycleDynamics, cycle_dynamics
from ..motion.laws import CycleSpec
from ..paper.lagrange import LagrangeLoads, inverse_dynamics
from .columns import cycle_columns
from .peaks import Peak, cycle_peaks
from .summary import peak_lines, peak_notes


@dataclass(frozen=True)
class CycleStudy:
    """One cycle's results from both computations.

    Attributes:
        feeder: The device.
        dynamics: Pinocchio: kinematics, loads, reactions, drives, forward run.
        lagrange: The hand-derived equations' loads and multipliers on the same motion.
    """

    feeder: Feeder
    dynamics: CycleDynamics
    lagrange: LagrangeLoads

    def columns(self) -> dict[str, np.ndarray]:
        """Every column of ``cycle.csv`` (:data:`~feeder.study.columns.COLUMNS`), each (N,)."""
        return cycle_columns(self.dynamics, self.lagrange)

    def peaks(self) -> list[Peak]:
        """Peak of every actuator load, drive and joint reaction, with its time."""
        return cycle_peaks(self.dynamics)

    def cross_check(self) -> tuple[float, float]:
        """Largest |Lagrange − Pinocchio| of the piston force [N] and forearm moment [N·m]."""
        loads = self.dynamics.loads
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
        peaks = self.peaks()
        lines += peak_lines(peaks)
        lines += peak_notes(self.feeder.params, peaks)
        if d.forward is None:
            lines.append("  forward run (force rule): skipped")
        else:
            phi3, phi4 = d.tracking_error()
            lines.append(
                f"  forward run (force rule): |Δφ3| ≤ {phi3:.2e} rad, |Δφ4| ≤ {phi4:.2e} rad, "
                f"pin gap ≤ {d.closure_residual():.2e} m"
            )
        force, torque = self.cross_check()
        lines.append(
            f"  Lagrange equations vs Pinocchio: piston force within {force:.1e} N, forearm "
            f"moment within {torque:.1e} N·m"
        )
        return "\n".join(lines)


def run_cycle_study(
    feeder: Feeder,
    elevation: float,
    spec: CycleSpec | None = None,
    progress: bool = False,
    forward: bool = True,
) -> CycleStudy:
    """Dynamics of one cycle at ``elevation`` [rad] by Pinocchio and by the Lagrange equations.

    Args:
        feeder: The device.
        elevation: ε [rad], inside the device's range.
        spec: Stage durations and sample rate (default :class:`~feeder.motion.laws.CycleSpec`).
        progress: Show a progress bar on a terminal.
        forward: Run the force-rule forward simulation (False skips it and its ``forward_*``
            columns).

    Raises:
        ElevationError, InputError: Bad elevation or timing.
        ForwardDivergenceError: The forward run drifted (sample faster, or ``forward=False``).
    """
    dynamics = cycle_dynamics(feeder, elevation, spec, progress=progress, forward=forward)
    k = dynamics.kinematics
    return CycleStudy(feeder, dynamics, inverse_dynamics(feeder.params, k.q, k.v, k.a, k.gripped))
