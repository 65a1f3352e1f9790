"""What a computed-torque controller did at a run's samples (:class:`ControlRecord`, made by
:meth:`~feeder.chain.dynamics.control.ComputedTorque.record`): the references, errors, forces,
flags and pressures, and the summary's lines."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class ControlRecord:
    """What the controller did at a run's samples (:meth:`ComputedTorque.record`), one column
    per controlled joint (in the order of :attr:`joints`).

    Attributes:
        joints: The controlled joints.
        units: Each one's unit of position: "rad" or "m".
        elements: The force element pushing each one (None: its own actuator).
        t: Times [s], (N,).
        reference, reference_rate: q_ref [rad or m] and q̇_ref, (N, n).
        error, error_rate: e = q_ref − q and ė, (N, n) (a continuous joint's e wrapped).
        demand: The law's force before the limits [N or N·m], (N, n).
        command: The demand clipped to the force limits, (N, n).
        force: The acting force (the command, or the lagged actuator's state), (N, n).
        saturated: Demand outside the force limits (bool, (N, n)).
        rate_limited: A lagged actuator's force rate at its limit (bool, (N, n)).
        pressure: Joint → the acting force / the piston area [Pa] (N,), for the joints with
            an area (hydraulic cylinders).
        chambers: Joint → the cap and rod chambers' pressures [Pa] ((N,), (N,)) that give the
            acting push, for the joints a Cylinder element drives (module docstring).
    """

    joints: tuple[str, ...]
    units: tuple[str, ...]
    t: np.ndarray
    reference: np.ndarray
    reference_rate: np.ndarray
    error: np.ndarray
    error_rate: np.ndarray
    demand: np.ndarray
    command: np.ndarray
    force: np.ndarray
    saturated: np.ndarray
    rate_limited: np.ndarray
    pressure: dict[str, np.ndarray]
    elements: tuple[str | None, ...]
    chambers: dict[str, tuple[np.ndarray, np.ndarray]]

    def peak_error(self) -> np.ndarray:
        """Largest |e| per joint [rad or m], (n,)."""
        return np.abs(self.error).max(axis=0)

    def rms_error(self) -> np.ndarray:
        """Root mean square of e over the run (trapezoidal in time) per joint [rad or m], (n,)."""
        span = self.t[-1] - self.t[0]
        return np.sqrt(np.trapezoid(self.error**2, self.t, axis=0) / span)

    def time_saturated(self) -> np.ndarray:
        """Time [s] with the demand outside the force limits per joint, (n,): the trapezoidal
        integral of the flag over the samples (each flag held for its half intervals)."""
        return np.trapezoid(self.saturated.astype(float), self.t, axis=0)

    def lines(self) -> list[str]:
        """The summary's lines: per joint (and the element pushing it) the peak and RMS error,
        the time saturated, the time rate-limited and the peak pressures."""
        span = self.t[-1] - self.t[0]
        lines = []
        saturated_time = self.time_saturated()
        rows = zip(self.joints, self.units, self.peak_error(), self.rms_error(), saturated_time,
                   strict=True)  # fmt: skip
        for j, (joint, unit, peak, rms, saturated) in enumerate(rows):
            flags = self.saturated[:, j]
            pushed = "" if self.elements[j] is None else f" by the push of {self.elements[j]!r}"
            text = (
                f"  control of {joint!r}{pushed}: peak error {peak:.3g} {unit}, RMS error "
                f"{rms:.3g} {unit}; saturated {saturated:.4g} s ({saturated / span:.1%} of the "
                "run)"
            )
            if flags.any():
                times = self.t[flags]
                text += f", from t = {times[0]:.6g} s to {times[-1]:.6g} s"
            if self.rate_limited[:, j].any():
                text += f"; rate-limited at {int(self.rate_limited[:, j].sum())} samples"
            if joint in self.pressure:
                text += f"; peak pressure {np.abs(self.pressure[joint]).max() / 1e6:.4g} MPa"
            if joint in self.chambers:
                cap, rod = (pressure.max() / 1e6 for pressure in self.chambers[joint])
                text += f"; peak cap pressure {cap:.4g} MPa, peak rod pressure {rod:.4g} MPa"
            lines.append(text)
        return lines
