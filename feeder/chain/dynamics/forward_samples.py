"""The output samples of a forward run (:func:`~feeder.chain.dynamics.forward.simulate`): each
sample's state, its accelerations, the loads of the sampled motion and the energies.

Every output sample whose loops are open by more than ``drift_tolerance`` (positions,
or velocities per second; the integrator's dense output between step ends), or whose quaternions
are off unit length, or where Baumgarte's corrector pulled the run's accelerations by more than
a tenth of what the inverse dynamics of the samples accept (:func:`closed`), is projected onto
the constraints (the drift before the projection is reported), and every sample in a step near
a singular position (where a velocity off the branch hides from these tests:
:data:`~feeder.chain.dynamics.singular.NEAR`); a sample kept as integrated has its unit circles
and quaternions normalised. Their accelerations, the closed chain's own without the corrector
(:meth:`~.forward_equations.ForwardEquations.sample_accelerations`), are evaluated, and the
inverse dynamics of the sampled motion give the
closure forces, the drive loads (equal to the applied ones: a check), every joint's reaction and
every force element's force, like the tables of ``feeder analyze``. The loops' tests take all
the samples in one batched pass (:func:`loops`), and the actuation at the samples is asked of a
controller in one call where it can answer so (its ``at_samples``).

A run asked for its motion alone (``loads=False``: a controller's study, where the loads are
not wanted) keeps each sample as integrated unless its loops are open, or a quaternion off unit
length, by more than ``drift_tolerance`` (the test of the run's own steps), and evaluates
neither the accelerations, the loads nor the energies: of the device's controlled cycle on a
moving hull (4 501 samples) they were two thirds of the run (measured).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ...exceptions import InputError, SingularPoseError
from ..kinematics.rows import closure_kinematics
from ..kinematics.tree import tree_motion
from .budget import sample_progress
from .forward_equations import IntegrationError
from .forward_run import ForwardRun
from .inverse import CLOSURE_TOLERANCE, inverse_dynamics
from .projection import project
from .singular import determinate_loads


def closed(
    equations, y: np.ndarray, a: np.ndarray, residual: float, opening: float, tolerance: float
) -> bool:
    """Whether the state y, with accelerations a (nv,), loop residual ``residual`` [m, rad] and
    loop opening |J q̇| ``opening`` [m/s, rad/s] (:func:`loops`), needs no projection
    (:func:`results`): its loops closed to ``tolerance`` (the run's ``drift_tolerance``;
    velocities per second, relative to the largest rate beyond 1), its quaternions of unit
    length, and the pull that Baumgarte's corrector put on the run's accelerations there (at
    most ω² r + 2ω |J q̇|) a tenth of what the inverse dynamics of the samples accept
    (:data:`~feeder.chain.dynamics.inverse.CLOSURE_TOLERANCE` of the motion's scale): the sample
    is then the motion through it to the loads' accuracy."""
    model = equations.model
    q, v = y[: model.nq], y[model.nq : model.nq + model.nv]
    if residual > tolerance or not pin.isNormalized(model, q, tolerance):
        return False
    speed = float(np.abs(v).max(initial=0.0))
    if opening > tolerance * max(1.0, speed):
        return False
    baumgarte = equations.constraints[0].m_baumgarte_parameters if equations.constraints else None
    pull = (
        0.0
        if baumgarte is None
        else float(baumgarte.Kp) * residual + float(baumgarte.Kd) * opening
    )
    scale = max(1.0, speed**2, float(np.abs(a).max(initial=0.0)))
    return pull <= 0.1 * CLOSURE_TOLERANCE * scale


def loops(chain, q: np.ndarray, v: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The largest closure error [m, rad] of each configuration q (N, nq) and, given the
    velocities v (N, nv), the largest opening |J q̇| of its loops [m/s, rad/s] (zero without),
    (N,) each: the rows of :meth:`~feeder.chain.model.closure.ClosedChain.residual` and
    :meth:`~feeder.chain.model.closure.ClosedChain.jacobian`, the run's own test of its steps.
    A chain whose q is a vector takes all the samples in one pass of the batched kinematics
    (:func:`~feeder.chain.kinematics.rows.closure_kinematics`, equal to Pinocchio's to
    round-off), where one call each per sample cost 16 and 15 µs on the device (measured); one
    with unit circles or quaternions is evaluated sample by sample by Pinocchio, which takes a
    q off unit length as it is where the batched kinematics would take its unit direction."""
    model = chain.model
    if model.nq != model.nv:
        gap = np.array([np.abs(chain.residual(x)).max(initial=0.0) for x in q])
        if v is None:
            return gap, np.zeros(q.shape[0])
        pairs = zip(q, v, strict=True)
        return gap, np.array([np.abs(chain.jacobian(x) @ y).max(initial=0.0) for x, y in pairs])
    motion = tree_motion(model, q, v)
    rows = closure_kinematics(chain, motion, v, with_jacobian=v is not None)
    return np.abs(rows.residual).max(axis=1, initial=0.0), np.abs(rows.rate).max(
        axis=1, initial=0.0
    )


def normalized(equations, y: np.ndarray) -> np.ndarray:
    """The state y with its unit circles and quaternions normalised (a kept sample: its
    accelerations are those of the nearest unit ones, as the run's right-hand side takes them,
    whose loops Baumgarte's corrector keeps closed); y itself when q has none."""
    if equations.rate is None:
        return y
    out = y.copy()
    out[: equations.nq] = pin.normalize(equations.model, y[: equations.nq])
    return out


def results(
    equations,
    t: np.ndarray,
    states: np.ndarray,
    steps: int,
    projections: int,
    progress: bool,
    watch,
    drift_tolerance: float,
    loads: bool = True,
) -> ForwardRun:
    """The run's tables from the states at the output times t [s] (N,), (N, size) (module
    docstring); ``progress``: show the samples' progress line
    (:func:`~feeder.chain.dynamics.budget.sample_progress`); ``watch``: the singular instants
    passed (:class:`~feeder.chain.dynamics.singular.RankWatch`, or None); ``drift_tolerance``:
    the closure residual [m, rad] above which a sample is projected; ``loads``: with the
    accelerations, loads and energies (False: the motion alone)."""
    dyn, nq, nv = equations.dyn, equations.nq, equations.nv
    residual = np.empty(t.size)
    with sample_progress(t.size, progress) as line:
        if loads:
            projected, a = _samples(equations, t, states, watch, drift_tolerance, residual, line)
        else:
            projected, a = _motion(equations, states, drift_tolerance, residual, line), None
    q, v, work = projected[:, :nq], projected[:, nq : nq + nv], projected[:, nq + nv]
    held = equations.states(projected)
    # the drives and the pushed elements' pushes (the controller's u) at the samples
    commands = np.zeros((t.size, len(dyn.columns) + len(equations.pushed)))
    if equations.actuation is not None:
        commands[:] = equations.sample_commands(t, q, v, held)
    u, pushes = np.split(commands, [len(dyn.columns)], axis=1)
    indeterminate = np.zeros(t.size, dtype=bool)
    table, kinetic, energy = None, None, None
    if loads:
        table, indeterminate = _loads(equations, t, q, v, a, watch, pushes)
        kinetic, energy = _energies(equations, t, q, v)
    return ForwardRun(
        t=t,
        q=q,
        v=v,
        a=a,
        loads=table,
        residual=residual,
        energy=energy,
        kinetic=kinetic,
        work=work,
        steps=steps,
        evaluations=equations.count,
        projections=projections,
        singular=() if watch is None else tuple(watch.passes),
        indeterminate=indeterminate,
        controller=held,
        actuation=u,
        base_work=None if equations.moving is None else projected[:, -1],
    )


def _samples(equations, t, states, watch, drift_tolerance, residual, line):
    """The samples' states (N, size), projected where :func:`closed` says, and their
    accelerations (N, nv); ``residual`` (N,) receives each sample's drift."""
    chain, nq, nv = equations.dyn.chain, equations.nq, equations.nv
    projected = np.empty_like(states)
    a = np.empty((t.size, nv))
    if equations.moving is not None:  # the base's motion at every sample in one pass
        equations.moving.prepare(t)
    # near a singular position the test does not see a velocity off the branch: projected
    near = np.zeros(t.size, dtype=bool) if watch is None else watch.near_samples(t)

    def accelerations(k: int, y: np.ndarray) -> np.ndarray:  # of the sample k at the state y
        return equations.sample_accelerations(t[k], y[:nq], y[nq : nq + nv], equations.states(y))

    residual[:], opening = loops(chain, states[:, :nq], states[:, nq : nq + nv])
    kept_states = [None if near[k] else normalized(equations, y) for k, y in enumerate(states)]
    # the corrector acted on the nearest unit circles where the run normalised them
    closure = residual
    if equations.normalize:
        units = np.array([y if y is not None else states[k] for k, y in enumerate(kept_states)])
        closure = loops(chain, units[:, :nq])[0]
    for k, y in enumerate(states):
        kept = kept_states[k]
        if kept is not None:
            a[k] = accelerations(k, kept)
            if not closed(equations, y, a[k], closure[k], opening[k], drift_tolerance):
                kept = None
        if kept is None:
            kept = project(chain, y)
            a[k] = accelerations(k, kept)
        projected[k] = kept
        line.update()
    return projected, a


def _motion(equations, states, drift_tolerance, residual, line):
    """The samples' states (N, size) of a run asked for its motion alone (module docstring):
    projected where the loops are open, or a quaternion off unit length, beyond
    ``drift_tolerance``; ``residual`` (N,) receives each sample's drift."""
    chain, model, nq = equations.dyn.chain, equations.model, equations.nq
    projected = states.copy()
    residual[:] = loops(chain, states[:, :nq])[0]
    for k, y in enumerate(states):
        unit = equations.rate is None or pin.isNormalized(model, y[:nq], drift_tolerance)
        if residual[k] > drift_tolerance or not unit:
            projected[k] = project(chain, y)
        line.update()
    return projected


def _loads(equations, t, q, v, a, watch, pushes):
    """The inverse dynamics of the sampled motion and the samples whose loads are
    indeterminate (bool (N,)), or an :class:`IntegrationError` naming where they cannot be
    computed; ``pushes``: those the controller applied to force elements at the samples (N,
    n_pushed), carried by them in the loads
    (:meth:`~feeder.chain.dynamics.forward_equations.ForwardEquations.loads_dynamics`)."""
    dyn = equations.loads_dynamics(t, pushes)
    try:
        if watch is not None and watch.passes:
            return determinate_loads(dyn, t, q, v, a, watch.passes)
        return inverse_dynamics(dyn, q, v, a, t=t), np.zeros(t.size, dtype=bool)
    except SingularPoseError as exc:
        if watch is not None:  # a singular pose of the loads alone: flag every such sample
            return determinate_loads(dyn, t, q, v, a, None)
        if exc.sample is None:
            raise IntegrationError(f"the run's loads cannot be computed: {exc}") from exc
        raise IntegrationError(
            f"the run's loads cannot be computed at t = {t[exc.sample]:.6g} s: {exc}; end "
            f"the run before t = {t[exc.sample]:.6g} s"
        ) from exc
    except InputError as exc:
        raise IntegrationError(f"the run's samples are not a consistent motion: {exc}") from exc


def _energies(equations, t, q, v):
    """The kinetic and the total (kinetic, gravitational, elastic) energy [J], (N,) each: the
    absolute motion's on a moving base (:mod:`~feeder.chain.dynamics.forward_base`)."""
    dyn, model, data = equations.dyn, equations.model, equations.data
    elastic = np.array([dyn.elements.energy(x) for x in q])
    if equations.moving is None:
        pairs = zip(q, v, strict=True)
        kinetic = np.array([pin.computeKineticEnergy(model, data, x, y) for x, y in pairs])
        pairs = zip(q, elastic, strict=True)
        potential = np.array([pin.computePotentialEnergy(model, data, x) + e for x, e in pairs])
    else:
        kinetic, potential = equations.moving.energies(t, q, v)
        potential = potential + elastic
    return kinetic, kinetic + potential
