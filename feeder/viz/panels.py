"""What the figures of a user mechanism's analysis (``feeder analyze``) and forward run
(``feeder simulate``) show, without drawing anything (no matplotlib): each figure a stack of
:class:`Panel` against time (the drive loads, every joint's reaction, the cut forces, the distance
to a singular pose, the motion, the force elements, the run's energy balance and drift), by file
name. :mod:`feeder.viz.analysis` draws them, in this process or in a process forked before the
run (:mod:`feeder.viz.mechanism_figures`), to which the panels are sent.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..chain.kinematics.tree import reach
from ..study.mechanism_table import load_unit

if TYPE_CHECKING:
    from ..chain.dynamics.inverse import ChainLoads
    from ..study.analyze import Analysis
    from ..study.simulate import Simulation


@dataclass(frozen=True)
class Panel:
    """One panel of a figure against time.

    Attributes:
        title: Panel title (also what its note, if it is left out, is about).
        ylabel: Axis label with its unit.
        unit: The series' unit, for the notes.
        series: (legend, values (N,)) pairs, one quantity.
        scale: Size of the terms the series are computed from [unit], for their round-off
            level (:func:`~feeder.viz.axes.round_off`).
        log: A log axis for positive series; values below round-off are drawn at it.
        reference: A value marked by a dashed grey line, or None.
    """

    title: str
    ylabel: str
    unit: str
    series: tuple[tuple[str, np.ndarray], ...]
    scale: float = 0.0
    log: bool = False
    reference: float | None = None


Stack = tuple[np.ndarray, tuple[Panel, ...]]
"""One figure's times [s], (N,), and its panels, top to bottom."""


def _unit(analysis: Analysis, joint: str) -> str:
    return load_unit(analysis.chain.model, joint)


def loads_panels(analysis: Analysis) -> Stack:
    """The actuated joints' generalized forces and the velocity gain against time (no gain for
    an open tree: without a closure there is no singular pose to be near)."""
    units = {name: _unit(analysis, name) for name in analysis.loads.actuators}
    shared = ", ".join(sorted(set(units.values())))
    loads = Panel(
        "Actuator loads (inverse dynamics)",
        f"drive load [{shared}]",
        shared,
        tuple((f"{name} [{units[name]}]", v) for name, v in analysis.loads.actuators.items()),
    )
    gain = Panel(
        "Distance to a singular pose (gain → ∞ at a toggle; dashed: 1)",
        "velocity gain [–]",
        "",
        (("velocity gain", analysis.gain),),
        log=True,
        reference=1.0,
    )
    return analysis.motion.t, (loads, gain) if analysis.chain.nc else (loads,)


def reactions_panels(t: np.ndarray, loads: ChainLoads, size: float) -> Stack:
    """Magnitude of every joint's reaction force and moment against time (two panels); ``size``
    is the mechanism's [m] (:func:`reach`)."""
    return _wrench_panels(
        t,
        loads.joints,
        size,
        "Joint reaction forces (parent on child)",
        "Joint reaction moments about each joint's origin",
    )


def closures_panels(t: np.ndarray, loads: ChainLoads, size: float) -> Stack:
    """Magnitude of each cut's force and moment (on the body of its first frame) against time;
    statically indeterminate components are the minimum-norm choice (the summary says which);
    ``size`` is the mechanism's [m] (:func:`reach`)."""
    return _wrench_panels(t, loads.closures, size, "Closure (cut) forces", "Closure (cut) moments")


def _wrench_panels(
    t: np.ndarray, wrenches: dict, size: float, force_title: str, moment_title: str
) -> Stack:
    """|force| and |moment| of each named wrench against time, two panels. A moment's terms are
    the largest force times the mechanism's ``size`` [m]: its round-off scale, so that moments
    that are all round-off are recognised as such."""
    forces = tuple((name, np.linalg.norm(w.force, axis=1)) for name, w in wrenches.items())
    moments = tuple((name, np.linalg.norm(w.moment, axis=1)) for name, w in wrenches.items())
    largest_force = max((float(f.max(initial=0.0)) for _, f in forces), default=0.0)
    return t, (
        Panel(force_title, "|force| [N]", "N", forces),
        Panel(moment_title, "|moment| [N·m]", "N·m", moments, scale=largest_force * size),
    )


def analysis_stacks(analysis: Analysis) -> dict[str, Stack]:
    """The panels of every figure of an analysis, by file name."""
    t = analysis.motion.t
    size = reach(analysis.chain.model, analysis.q)
    figures = {
        "actuator_loads.png": loads_panels(analysis),
        "joint_reactions.png": reactions_panels(t, analysis.loads, size),
    }
    if analysis.loads.closures:
        figures["closure_forces.png"] = closures_panels(t, analysis.loads, size)
    return figures


def motion_panels(simulation: Simulation) -> Stack:
    """The one-coordinate joints' values and rates against time (two panels)."""
    run, model = simulation.run, simulation.chain.model
    values, rates = [], []
    for j in range(1, model.njoints):
        joint = model.joints[j]
        if joint.nv != 1:
            continue
        q = run.q[:, joint.idx_q]
        if joint.nq == 2:
            q = np.unwrap(np.arctan2(run.q[:, joint.idx_q + 1], q))
        values.append((model.names[j], q))
        rates.append((model.names[j], run.v[:, joint.idx_v]))
    return run.t, (
        Panel(
            "Joint coordinates (forward run from "
            + ("its initial rates)" if simulation.start.given else "rest)"),
            "joint value [rad or m]",
            "rad or m",
            tuple(values),
        ),
        Panel("Joint rates", "joint rate [rad/s or m/s]", "rad/s or m/s", tuple(rates)),
    )


def balance_panels(simulation: Simulation, size: float) -> Stack:
    """The energy, the work of the non-conservative forces, their balance and the drift;
    ``size`` is the mechanism's [m] (:func:`reach`). The energy's terms are its largest |value|
    (the balance subtracts energies that large); the drift's are the mechanism's size (lengths)
    or a radian (angles)."""
    run = simulation.run
    energy = float(np.abs(run.energy).max(initial=0.0))
    change = run.energy - run.energy[0]
    return run.t, (
        Panel(
            "Energy (kinetic, gravitational, elastic) and work",
            "energy [J]",
            "J",
            (("E − E(0)", change), ("W (non-conservative work)", run.work)),
            scale=energy,
        ),
        Panel(
            "Energy balance (zero for an exact run)",
            "E − E(0) − W [J]",
            "J",
            (("E − E(0) − W", run.balance()),),
            scale=energy,
        ),
        Panel(
            "Closure drift before projection",
            "residual [m, rad]",
            "m, rad",
            (("closure residual", run.residual),),
            scale=max(size, 1.0),
            log=True,
        ),
    )


def elements_panels(simulation: Simulation) -> Stack:
    """Each force element's force against time."""
    run = simulation.run
    forces = Panel(
        "Force elements",
        "force [N] (tension +) or resistance [N·m, N]",
        "N or N·m",
        tuple(run.loads.elements.items()),
    )
    return run.t, (forces,)


def simulation_stacks(simulation: Simulation) -> dict[str, Stack]:
    """The panels of every figure of a forward run, by file name."""
    run = simulation.run
    size = reach(simulation.chain.model, run.q)
    figures = {
        "motion.png": motion_panels(simulation),
        "energy_balance.png": balance_panels(simulation, size),
        "joint_reactions.png": reactions_panels(run.t, run.loads, size),
    }
    if run.loads.closures:
        figures["closure_forces.png"] = closures_panels(run.t, run.loads, size)
    if run.loads.elements:
        figures["force_elements.png"] = elements_panels(simulation)
    return figures
