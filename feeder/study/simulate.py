"""A forward run of a user's closed-chain mechanism (``feeder simulate``): started from its
assembled pose, at rest or at the initial rates given, under gravity and its force elements, run
with error control.

Data flow: side-file and model (:mod:`feeder.chain.readers`, with the side-file's force elements
and those of an optional ``--forces`` file) → :class:`~feeder.chain.ClosedChain` → the closed
pose nearest to the reference pose (the side-file's ``pose``, a pose file, or the model's zero)
→ the initial rates there (the side-file's ``rates`` and ``--rate``, closed or projected onto the
closure: :func:`~feeder.chain.initial_rates`) → mobility report there →
:func:`~feeder.chain.simulate`, the actuated joints of the side-file's ``[[control]]`` tables (or
a ``--control`` file's) driven by a computed-torque controller
(:mod:`feeder.chain.dynamics.control`) → the table (:meth:`Simulation.columns`) and its summary.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..chain.assembly.rates import InitialRates, initial_rates
from ..chain.dynamics.budget import check_sample_count
from ..chain.dynamics.control import ComputedTorque, ControlRecord
from ..chain.dynamics.forward import ATOL, RTOL, simulate
from ..chain.dynamics.forward_run import ForwardRun
from ..chain.dynamics.inverse import ChainDynamics
from ..chain.kinematics.frames import point_motion
from ..chain.mobility import MobilityReport, mobility
from ..chain.model.closure import ClosedChain
from ..chain.model.forces import ForceElement
from ..chain.readers.control import read_control_file
from ..chain.readers.forces import read_force_file
from ..chain.readers.spec import MechanismSpec
from ..exceptions import FeederWarning, InputError
from ..validation import check_number
from .analyze import (
    base_text,
    gravity_text,
    mount_lines,
    mount_mechanism,
    warn_if_gravity_idle,
)
from .mechanism_table import (
    joint_columns,
    load_columns,
    load_peaks,
    merge_columns,
    point_columns,
)

SAMPLES = 1001
"""Default number of output samples over the run (both ends included)."""


@dataclass(frozen=True)
class Simulation:
    """A mechanism's forward run.

    Attributes:
        spec: The side-file's content (its force elements, plus those of ``--forces``, are in
            :attr:`elements`).
        elements: The force elements that acted.
        chain: The closed chain.
        run: The run (states, accelerations, loads, drift, energy and work).
        report: Mobility at the assembled pose, where the run starts.
        reference: The pose the mechanism was mounted from (nq,).
        assembled: The closed pose nearest to it, where the run starts (nq,).
        method, rtol, atol: The integrator and its tolerances.
        start: The initial rates: given, used (closed) and how they changed.
        singular: What the run did at singular positions: ``"pass"`` or ``"stop"``
            (:func:`~feeder.chain.simulate`).
        control: What the controller of the controlled joints did, or None (none).
    """

    spec: MechanismSpec
    elements: tuple[ForceElement, ...]
    chain: ClosedChain
    run: ForwardRun
    report: MobilityReport
    reference: np.ndarray
    assembled: np.ndarray
    method: str
    rtol: float
    atol: float
    start: InitialRates
    singular: str = "stop"
    control: ControlRecord | None = None

    def columns(self) -> dict[str, np.ndarray]:
        """The state table, each column (N,), SI units, world axes: ``t``; every joint's
        coordinates, rates and accelerations
        (:func:`~feeder.study.mechanism_table.joint_columns`); the mechanism file's points'
        positions, velocities and accelerations
        (:func:`~feeder.study.mechanism_table.point_columns`); the loads
        (:func:`~feeder.study.mechanism_table.load_columns`: the actuated joints' drive — the
        controller's, zero for those it does not drive — the closure forces, every joint's
        reaction and every force element's force); per controlled joint its reference, error,
        the law's force and the limits' flags (:meth:`control_columns`); ``drift`` (the
        closure residual before projection [m, rad]), ``energy`` (kinetic, gravitational and
        elastic [J]; on a moving base the absolute motion's), ``work`` (of the non-conservative
        forces since t = 0 [J]), on a moving base ``base_work`` (the work of the base's motion
        on the mechanism since t = 0 [J], :mod:`~feeder.chain.dynamics.forward_base`),
        ``energy_balance`` (energy − energy(0) − work − base_work [J], zero for an exact run)
        and ``loads_indeterminate`` (1 where the sample is so near a singular position that its
        loads are unbounded or indeterminate: they read 0 there, not a value; 0 elsewhere)."""
        run = self.run
        points = point_motion(self.chain, self.spec.points, run.q, run.v, run.a)
        cols = merge_columns(
            {"t": run.t},
            joint_columns(self.chain.model, run.q, run.v, run.a),
            point_columns(points),
            load_columns(run.loads),
        )
        cols["drift"] = run.residual
        cols["energy"] = run.energy
        cols["work"] = run.work
        if run.base_work is not None:
            cols["base_work"] = run.base_work
        cols["energy_balance"] = run.balance()
        cols["loads_indeterminate"] = run.indeterminate.astype(float)
        return merge_columns(cols, self.control_columns())

    def control_columns(self) -> dict[str, np.ndarray]:
        """Per controlled joint J: ``q_ref_J``, ``v_ref_J`` (the reference [rad or m, per s]),
        ``error_J``, ``error_rate_J`` (reference − state), ``demand_J`` (the law's force before
        the limits [N or N·m]), ``command_J`` (within them), ``saturated_J`` (1 where the demand
        is beyond them), ``rate_limited_J`` (1 where a lagged actuator's force rate is at its
        limit), for a joint with a piston area, ``pressure_J`` (its force / the area [Pa]) and,
        for a joint a Cylinder element's push drives, ``cap_pressure_J`` and ``rod_pressure_J``
        (the chamber pressures that give the push [Pa], one of them zero); none without control
        (:class:`~feeder.chain.results.ControlRecord`). A pushed joint's demand and command are
        the element's push [N]."""
        record, cols = self.control, {}
        for j, joint in enumerate(() if record is None else record.joints):
            cols[f"q_ref_{joint}"] = record.reference[:, j]
            cols[f"v_ref_{joint}"] = record.reference_rate[:, j]
            cols[f"error_{joint}"] = record.error[:, j]
            cols[f"error_rate_{joint}"] = record.error_rate[:, j]
            cols[f"demand_{joint}"] = record.demand[:, j]
            cols[f"command_{joint}"] = record.command[:, j]
            cols[f"saturated_{joint}"] = record.saturated[:, j].astype(float)
            cols[f"rate_limited_{joint}"] = record.rate_limited[:, j].astype(float)
            if joint in record.pressure:
                cols[f"pressure_{joint}"] = record.pressure[joint]
            if joint in record.chambers:
                cols[f"cap_pressure_{joint}"], cols[f"rod_pressure_{joint}"] = record.chambers[
                    joint
                ]
        return cols

    def summary(self) -> str:
        """The mobility report, the assembled pose, the run's statistics, its drift and energy
        balance, and the peaks of the loads, as text."""
        run = self.run
        t = run.t
        lines = mount_lines(self.report, self.chain.model, self.reference, self.assembled)
        lines += self.start.lines()
        origin = "at the initial rates above" if self.start.given else "from rest"
        lines.append(
            f"forward run: {t[-1] - t[0]:.4g} s {origin}, {t.size} output samples; "
            f"{self.method} at rtol {self.rtol:g}, atol {self.atol:g}: {run.steps} steps, "
            f"{run.evaluations} right-hand sides, {run.projections} projections onto the "
            "constraints"
        )
        lines.append(
            "  force elements: "
            + (", ".join(element.name for element in self.elements) or "none")
            + f"; {gravity_text(self.spec, self.chain)}"
        )  # fmt: skip
        lines.append(f"  {base_text(self.spec)}")
        lines.append(f"  largest drift (closure residual before projection): {run.drift():.3g}")
        lines += self.singular_lines()
        lines.append(self.energy_line())
        free = [name for name in run.loads.actuators if name not in self.controlled]
        if free:
            worst = max(float(np.abs(run.loads.actuators[name]).max()) for name in free)
            lines.append(
                f"  actuated joints {free}: not driven (the inverse dynamics of the run give them "
                f"{worst:.2g}: a check of the run)"
            )
        if self.control is not None:
            lines += self.control.lines()
        drives = self.control is not None
        peaks = load_peaks(self.chain.model, t, run.loads, self.elements, drives=drives)
        return "\n".join(lines + peaks)

    @property
    def controlled(self) -> tuple[str, ...]:
        """The joints under control (none without)."""
        return () if self.control is None else self.control.joints

    def singular_lines(self) -> list[str]:
        """The singular positions the run passed (closure rank before → at → after, the time to
        its bracket) and the samples whose loads are indeterminate, as lines of the summary."""
        run = self.run
        if self.singular == "stop":
            return ["  singular positions: the run stops at one (--singular stop); it met none"]
        lines = [f"  singular positions passed: {len(run.singular)}"]
        lines += [f"    {singular.text()}" for singular in run.singular]
        count = int(run.indeterminate.sum())
        if count:
            times = run.t[run.indeterminate]
            lines.append(
                f"  loads unbounded or indeterminate at {count} samples near them (column "
                f"loads_indeterminate = 1, their loads read 0), from t = {times[0]:.6g} s to "
                f"{times[-1]:.6g} s"
            )
        return lines

    def energy_line(self) -> str:
        """The run's energy balance, as a line of the summary: relative to the largest energy
        the run moves (:meth:`~feeder.chain.results.ForwardRun.energy_scales`), or, for a mechanism
        that stays at rest (it moves no more than the integrator's tolerance on q,
        atol + rtol max |q|), in joules alone: it has no energy to compare with."""
        run = self.run
        error = run.energy_error()
        text = f"  energy balance: max |E − E(0) − W| = {error:.3g} J"
        if run.base_work is not None:
            text = (
                "  energy balance of the absolute motion (E its kinetic, gravitational and "
                f"elastic energy, W_B the base's work): max |E − E(0) − W − W_B| = {error:.3g} J"
            )
        moved = run.displacement(self.chain.model)
        resolution = self.atol + self.rtol * float(np.abs(run.q).max())
        if moved <= resolution:
            return (
                f"{text}; the mechanism stays at rest (it moves {moved:.2g} rad or m at most, "
                f"within the integrator's tolerance atol + rtol max |q| = {resolution:.2g}): no "
                "energy to compare the balance with"
            )
        scales = run.energy_scales()
        parts = ", ".join(f"{key} {value:.4g} J" for key, value in scales.items())
        return (
            f"{text}, {error / max(scales.values()):.2g} of the energy the run moves (the largest "
            f"of: {parts})"
        )


def simulate_mechanism(
    spec_path: str | Path,
    duration: float,
    model: str | Path | None = None,
    pose: str | Path | None = None,
    forces: str | Path | None = None,
    samples: int = SAMPLES,
    method: str = "DOP853",
    rtol: float = RTOL,
    atol: float = ATOL,
    progress: bool = False,
    rates: Mapping[str, float] | None = None,
    singular: str | None = None,
    control: str | Path | None = None,
) -> Simulation:
    """Run the mechanism forward from its assembled pose, at rest or at the initial rates of the
    side-file's ``rates`` and ``rates``.

    Args:
        spec_path: The mechanism file (TOML with closures and force elements, or YAML).
        duration: Length of the run [s] (> 0).
        model: The model file, overriding the side-file's.
        pose: A pose file that picks the assembly branch (default: the side-file's pose, or
            the model's zero pose).
        forces: A TOML file of more ``[[force]]`` tables.
        samples: Output samples over [0, duration] (≥ 2, at most
            :func:`~feeder.chain.dynamics.budget.max_samples` for the mechanism).
        method, rtol, atol: The integrator (:func:`~feeder.chain.simulate`).
        progress: Show the run's progress line on a terminal (:func:`~feeder.chain.simulate`).
        rates: Joint name → initial rate [rad/s, m/s] (``--rate``), over the side-file's entry of
            that joint; rates of the independent joints are closed by the closure, rates of
            more joints projected onto it (:func:`~feeder.chain.initial_rates`, a
            :class:`~feeder.exceptions.FeederWarning` when that changes them beyond round-off).
        singular: ``"pass"`` through singular positions or ``"stop"`` there (default: pass;
            :func:`~feeder.chain.simulate`).
        control: A TOML file of ``[[control]]`` tables (:func:`~feeder.chain.readers.
            read_control_file`), instead of the side-file's: the joints they name are driven
            toward their references by a computed-torque controller
            (:class:`~feeder.chain.dynamics.control.ComputedTorque`); the run must lie within
            every reference's times.

    Raises:
        FeederError: Bad files or settings, an unreachable pose, an integration that fails
            (each with its own message).
    """
    duration = check_number("duration [s]", duration)
    if not duration > 0.0:
        raise InputError(f"the duration must be > 0 s, got {duration!r}")
    if not isinstance(samples, int) or samples < 2:
        raise InputError(f"samples must be a whole number ≥ 2, got {samples!r}")
    if rates is not None and not isinstance(rates, Mapping):
        raise InputError(f"rates must map joint names to rates [rad/s, m/s], got {rates!r}")
    spec, chain, _, reference, assembled = mount_mechanism(spec_path, model, pose)
    check_sample_count("samples", samples, chain.model.nv)
    elements = spec.forces + (read_force_file(Path(forces)) if forces is not None else ())
    dyn = ChainDynamics(chain, spec.actuated, spec.stiffness, elements, spec.base)
    t = np.linspace(0.0, duration, samples)
    if np.any(np.diff(t) <= 0.0):
        raise InputError(
            f"the duration {duration!r} s is too short for {samples} distinct sample times "
            "(double precision): a longer duration or fewer samples"
        )
    singular = "pass" if singular is None else singular
    start = initial_rates(
        chain, assembled, {name: x for name, x, _ in spec.rates} | {**(rates or {})}
    )
    if start.projected():
        warnings.warn("; ".join(x.strip() for x in start.lines()), FeederWarning, stacklevel=2)
    specs = read_control_file(control) if control is not None else spec.control
    controller = ComputedTorque(dyn, specs) if specs else None
    if controller is not None:
        controller.check_covers(0.0, duration)
    run = simulate(
        dyn,
        t,
        assembled,
        start.v,
        controller,
        method=method,
        rtol=rtol,
        atol=atol,
        progress=progress,
        singular=singular,
    )
    warn_if_gravity_idle(spec, chain, run.q)
    report = mobility(chain, assembled, spec.independent)
    record = None
    if controller is not None:
        record = controller.record(run.t, run.q, run.v, run.controller)
    return Simulation(
        spec,
        elements,
        chain,
        run,
        report,
        reference,
        assembled,
        method,
        float(rtol),
        float(atol),
        start,
        singular,
        record,
    )
