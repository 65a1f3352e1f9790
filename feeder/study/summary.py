"""Text summaries for the command line: the kinematics, and the peaks of a cycle study with
notes on those that look implausible but follow from the parameters."""

from __future__ import annotations

import textwrap
from typing import TYPE_CHECKING

import numpy as np

from ..device.feeder import Feeder
from ..device.loop import arm_travel, required_stroke
from ..device.parameters import FeederParameters
from ..motion.cycle import CycleKinematics
from .columns import VECTORS
from .peaks import Peak

if TYPE_CHECKING:
    from ..dynamics.cycle import CycleDynamics
    from ..dynamics.loading import ControlledRun


def kinematics_summary(feeder: Feeder, cycle: CycleKinematics) -> str:
    """Stroke, travel, peak payload speed, transmission band and closure of a sampled cycle."""
    speed = np.linalg.norm(cycle.payload_velocity, axis=1)
    k = int(np.argmax(speed))
    mu = np.degrees(cycle.transmission_angle)
    return "\n".join(
        [
            f"{feeder.params.name} feeder, elevation {np.degrees(cycle.elevation):g}°",
            "  piston stroke needed over the range: "
            f"{required_stroke(feeder.params) * 1e3:.1f} mm",
            f"  piston travel this cycle: {(cycle.q[-1, 1] - cycle.q[0, 1]) * 1e3:.1f} mm",
            f"  arm travel: {np.degrees(arm_travel(cycle.elevation)):.1f}°",
            f"  peak payload speed: {speed[k]:.3f} m/s at t = {cycle.t[k]:.3f} s",
            f"  transmission angle: {mu.min():.1f}° … {mu.max():.1f}°",
            f"  max closure residual: {cycle.closure_residual.max():.2e} m",
        ]
    )


IMPLAUSIBLE_INERTIA_RATIO = 10.0
"""A payload whose largest moment of inertia is under a tenth of a uniform solid cylinder's of
its mass, length and calibre (about a transverse axis) gets a note under the grip moment's
peak: a real shell's or charge's transverse moment is of the order of that cylinder's (a thin
nose or a heavy base change it by tens of per cent, not tenfold)."""

WIDTH = 99
"""Width [characters] to which the summary's notes are wrapped."""


def peak_lines(peaks: list[Peak]) -> list[str]:
    """One line per peak: max |x| of a signed load with its sign there, max ‖x‖ of a vector
    (pressures in bar)."""
    vectors = {name for name, *_ in VECTORS}
    width = max(len(peak.name) for peak in peaks)
    lines = _wrapped(
        "peaks over the cycle: max |x| of each load and drive, with the sign it has there; "
        "max ‖x‖ of each joint reaction (signs: docs/REFERENCE.md)",
        "  ",
    )
    for peak in peaks:
        value, unit = (peak.value / 1e5, "bar") if peak.unit == "Pa" else (peak.value, peak.unit)
        if peak.name in vectors:
            size, sign = f"max ‖x‖ = {abs(value):10.3f}", ""
        else:
            size, sign = f"max |x| = {abs(value):10.3f}", _sign(value)
        lines.append(
            f"  peak {peak.name:<{width}} {size} {unit:<3} {sign:<8}  at t = {peak.time:.3f} s"
        )
    return lines


def peak_notes(params: FeederParameters, peaks: list[Peak]) -> list[str]:
    """Notes that explain peaks which look implausible but follow from the parameters."""
    peak = {p.name: p for p in peaks}
    payload = params.payload
    radius, length = params.payload_diameter / 2.0, params.payload_length
    uniform = payload.mass * (3.0 * radius**2 + length**2) / 12.0
    largest = max(payload.moments)
    if "grip_moment" not in peak or uniform < IMPLAUSIBLE_INERTIA_RATIO * largest:
        return []
    return _wrapped(
        f"note: grip_moment peaks at only {abs(peak['grip_moment'].value):.3g} N·m because "
        f"the {payload.mass:g} kg {params.payload_name}'s moments of inertia are tiny: at most "
        f"{largest:.3g} kg·m² ({payload.source}), where a uniform solid cylinder of its size "
        f"({params.payload_diameter:g} m × {length:g} m) has {uniform:.3g} kg·m² about a "
        f"transverse axis, {uniform / largest:.0f}× more. The tray's moment about the payload's "
        "centre of gravity is I·α + ω × I·ω: it scales with these moments (PARAMETERS.md).",
        "  ",
    )


def growth_lines(pairs: list[tuple[Peak, Peak]]) -> list[str]:
    """Each peak against the same quantity's peak in the cycle standing level (pairs of
    :meth:`~feeder.study.cycle_study.CycleStudy.against_level`): one line per quantity, by how
    much it grows (largest first)."""
    rows = []
    for peak, level in pairs:
        before = abs(level.value)
        after = abs(peak.value)
        change = (after - before) / before if before > 0.0 else (np.inf if after > 0.0 else 0.0)
        rows.append((change, peak, before))
    rows.sort(key=lambda row: -row[0] if np.isfinite(row[0]) else -np.inf)
    lines = ["  against the cycle standing level (peak on this base / peak standing):"]
    width = max(len(peak.name) for peak, _ in pairs)
    for change, peak, before in rows:
        scale, unit = (1e-5, "bar") if peak.unit == "Pa" else (1.0, peak.unit)
        growth = f"{change:+8.1%}" if np.isfinite(change) else "     new"
        lines.append(
            f"    {peak.name:<{width}} {abs(peak.value) * scale:10.3f} / {before * scale:10.3f} "
            f"{unit:<3} {growth}"
        )
    return lines


def _wrapped(text: str, indent: str) -> list[str]:
    return textwrap.wrap(
        text, WIDTH, initial_indent=indent, subsequent_indent=indent + "  ", break_on_hyphens=False
    )


def _sign(value: float) -> str:
    return "positive" if value > 0.0 else "negative" if value < 0.0 else "zero"


def controlled_lines(run: ControlledRun, dynamics: CycleDynamics) -> list[str]:
    """The controlled run (:mod:`feeder.dynamics.loading`): its gains, tracking, the loading
    pose against the rammer's line, the settling, the drives' peaks against the prescribed
    cycle's (the inverse dynamics on the same base) and where a drive saturates."""
    from ..dynamics.loading import LOAD_CASES  # here: only a cycle with the run imports it

    phi3, phi4 = run.tracking_error()
    pose = run.loading_pose()
    n = run.cycle_samples
    settle = (
        f"settles within {pose.position_tolerance * 1e3:g} mm and "
        f"{pose.angle_tolerance * 1e3:g} mrad in {pose.settle_time:.3f} s"
        if pose.settle_time is not None
        else f"does not settle within {pose.position_tolerance * 1e3:g} mm and "
        f"{pose.angle_tolerance * 1e3:g} mrad in the {run.t[-1] - run.end:g} s hold"
    )
    pressure, prescribed = run.pressures.peak()[:n].max(), dynamics.pressures.peak().max()
    rack, rack_prescribed = np.abs(run.rack_force[:n]).max(), np.abs(dynamics.rack_force).max()
    spans = run.saturation()
    saturation = (
        "none"
        if not spans
        else ", ".join(f"{name} {first:.3f}–{last:.3f} s" for name, first, last in spans)
    )
    return [
        f"  controlled run ({run.gains.describe()}):",
        *(
            f"    gains, {case}: piston Kp = {kp[0]:.4g} N/m, Kd = {kd[0]:.4g} N·s/m; forearm "
            f"Kp = {kp[1]:.4g} N·m/rad, Kd = {kd[1]:.4g} N·m·s/rad"
            for case, kp, kd in zip(LOAD_CASES, run.kp, run.kd, strict=True)
        ),
        f"    tracking over the cycle: |Δφ3| ≤ {phi3:.2e} rad, |Δφ4| ≤ {phi4:.2e} rad",
        f"    loading pose at t = {pose.time:g} s: {pose.off_line * 1e3:.3f} mm off the "
        f"rammer's line, {pose.along_line * 1e3:+.3f} mm along it, axis {pose.angle * 1e3:.3f} "
        f"mrad off; {settle}",
        f"    peak cylinder pressure {pressure / 1e5:.3f} bar (prescribed cycle "
        f"{prescribed / 1e5:.3f} bar), peak rack force {rack:.1f} N (prescribed "
        f"{rack_prescribed:.1f} N)",
        f"    drives saturated: {saturation}",
    ]
