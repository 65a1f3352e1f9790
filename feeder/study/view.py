"""What the viewer shows of a user's mechanism (``feeder view MODEL``): its poses over a motion
and the table of its loads, from one of three sources:

* its assembled pose alone, with the static loads there (gravity and the force elements at
  rest: :func:`pose_view`);
* a motion table, analysed as ``feeder analyze`` does (:func:`motion_view`);
* the output folder of an earlier ``feeder analyze`` or ``feeder simulate`` run, read back from
  its ``loads.csv`` or ``states.csv`` (:func:`run_view`);

or from a result in memory (:func:`analysis_view`, :func:`simulation_view`: the report pages).
The loads are the table's columns, named as in ``loads.csv`` (``tau_<joint>``,
``<joint>_force_x|y|z``, ``mount_force_vehicle_x|y|z``): one way to the arrows, whatever the
source. A mechanism file with a ``[base]`` puts the mechanism on a vehicle: the view carries the
base's motion at its samples (:attr:`MechanismView.base`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..chain.dynamics.inverse import ChainDynamics, inverse_dynamics
from ..chain.model.base import BaseState
from ..chain.model.closure import ClosedChain
from ..chain.readers.spec import MechanismSpec
from ..exceptions import FeederError, InputError
from ..files import verified_output
from .analyze import Analysis, analyze, mount_mechanism
from .csv import read_csv
from .mechanism_table import load_columns, q_from_columns
from .simulate import Simulation

RUN_TABLES = ("loads.csv", "states.csv")
"""The tables a run folder may hold: ``feeder analyze``'s and ``feeder simulate``'s."""


@dataclass(frozen=True)
class MechanismView:
    """A mechanism's poses and loads for the viewer, N samples.

    Attributes:
        spec: The side-file's content (the model file, for its visuals).
        chain: The closed chain.
        t: Times [s], (N,) (a single 0 for a pose).
        q: Configurations, (N, nq).
        columns: The loads table (``tau_<joint>`` [N or N·m], ``<joint>_force_x|y|z`` [N], …),
            each (N,); empty when there are no loads to show.
        source: What is shown, for the page's title (e.g. "motion of motion.csv").
        note: What the loads are, or why there are none.
        base: The base's motion at the samples (the file's ``[base]``: the model's moving axes
            and origin in the level axes, …), None for a base at rest.
    """

    spec: MechanismSpec
    chain: ClosedChain
    t: np.ndarray
    q: np.ndarray
    columns: dict[str, np.ndarray]
    source: str
    note: str
    base: BaseState | None


def base_state(spec: MechanismSpec, chain: ClosedChain, t: np.ndarray) -> BaseState | None:
    """The base's motion (the file's ``[base]``) at the times t [s] (N,), as the inverse dynamics
    take it (:class:`~feeder.chain.dynamics.inverse.ChainDynamics`); None for a base at rest."""
    if spec.base is None or not spec.base.profiles:
        return None
    return spec.base.state(t, chain.model.gravity.linear)


def pose_view(
    spec_path: str | Path, model: str | Path | None = None, pose: str | Path | None = None
) -> MechanismView:
    """The mechanism at its assembled pose with its static loads (at rest: gravity and the
    force elements at t = 0). A mechanism without actuated joints that gravity moves has no
    static loads: then none are shown, and the note says why."""
    spec, chain, _, _, assembled = mount_mechanism(spec_path, model, pose)
    q, zero, t = assembled[None, :], np.zeros((1, chain.model.nv)), np.zeros(1)
    try:
        dyn = ChainDynamics(chain, spec.actuated, spec.stiffness, spec.forces, spec.base)
        loads = inverse_dynamics(dyn, q, zero, zero, t=t)
    except FeederError as exc:
        columns, note = {}, f"no static loads: {exc}"
    else:
        columns, note = load_columns(loads), "static loads at rest (gravity, force elements)"
    base = base_state(spec, chain, t)
    return MechanismView(spec, chain, t, q, columns, "assembled pose", note, base)


def analysis_view(analysis: Analysis, source: str = "analysis") -> MechanismView:
    """The view of an analysis (``feeder analyze``): its motion and loads."""
    return MechanismView(
        analysis.spec,
        analysis.chain,
        analysis.motion.t,
        analysis.q,
        analysis.columns(),
        source,
        "loads of the prescribed motion (inverse dynamics)",
        analysis.loads.base,
    )


def simulation_view(simulation: Simulation, source: str = "forward run") -> MechanismView:
    """The view of a forward run (``feeder simulate``): its motion and loads."""
    run = simulation.run
    return MechanismView(
        simulation.spec,
        simulation.chain,
        run.t,
        run.q,
        simulation.columns(),
        source,
        "loads of the forward run (reactions from its inverse dynamics)",
        run.loads.base,
    )


def motion_view(
    spec_path: str | Path,
    motion_path: str | Path,
    model: str | Path | None = None,
    pose: str | Path | None = None,
) -> MechanismView:
    """The view of a motion table, analysed as ``feeder analyze`` does."""
    analysis = analyze(spec_path, motion_path, model, pose)
    return analysis_view(analysis, f"motion of {Path(motion_path).name}")


def run_view(
    spec_path: str | Path,
    folder: str | Path,
    model: str | Path | None = None,
    pose: str | Path | None = None,
) -> MechanismView:
    """The view of an earlier run's output folder (its ``loads.csv`` or ``states.csv``), as the
    run wrote it: its manifest (:func:`~feeder.files.verified_output`) says the run completed
    and the table is unchanged since.

    Raises:
        InputError: No such folder, or no table of a run in it, a table edited since its run
            (or a run that did not complete, or a folder without a manifest), times that do not
            increase strictly, or a table of another model.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise InputError(f"run folder not found: {folder}")
    tables = [name for name in RUN_TABLES if (folder / name).is_file()]
    if not tables:
        raise InputError(
            f"{folder} holds no {' or '.join(RUN_TABLES)}: give the output folder of "
            "feeder analyze or feeder simulate"
        )
    table = verified_output(folder, tables[0])
    spec, chain, *_ = mount_mechanism(spec_path, model, pose)
    columns = read_csv(table)
    if "t" not in columns:
        raise InputError(f"{table} has no column 't': it is not a table of a feeder run")
    _check_times(table, columns["t"])
    q = q_from_columns(chain.model, columns)
    gap = float(np.abs(chain.residual(q[0])).max(initial=0.0)) if q.size else 0.0
    if gap > 1e-6:  # a run's table closes its loops to ~1e-12: this is another mechanism's
        raise InputError(
            f"{table} does not close this mechanism's loops (residual {gap:.3g}): it is a "
            "run of another mechanism or pose"
        )
    return MechanismView(
        spec,
        chain,
        columns["t"],
        q,
        columns,
        f"run {folder.name}/{table.name}",
        f"loads of the run in {table.name}",
        base_state(spec, chain, columns["t"]),
    )


def _check_times(table: Path, t: np.ndarray) -> None:
    """Raise :class:`InputError` unless the times t [s] (N,) of ``table`` increase strictly."""
    steps = np.flatnonzero(np.diff(t) <= 0.0)
    if steps.size:
        k = int(steps[0])
        raise InputError(
            f"{table}: times must increase strictly from row to row, but t = {t[k + 1]:g} s "
            f"follows t = {t[k]:g} s (data rows {k + 1} and {k + 2})"
        )
