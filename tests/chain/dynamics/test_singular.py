"""Forward runs through singular positions of the closure (feeder.chain.dynamics.singular): the
instant found on the dense output against an independent measure of the pose (the delta's rod
lining up), the energy kept across it, the loads flagged there and solved elsewhere, the choice
between passing and stopping, and the projection that keeps its branch next to the pose."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from feeder.chain import ChainDynamics, Partition, simulate
from feeder.chain.dynamics.forward_equations import IntegrationError
from feeder.chain.dynamics.projection import project
from feeder.exceptions import InputError
from feeder.study.analyze import mount_mechanism

from ...conftest import REPO
from .delta import rod3_angle

FOUR_BAR = REPO / "examples" / "iftomm" / "n_four_bar_2.toml"


def test_the_undriven_delta_passes_its_dead_centre(delta):
    """Released, the delta falls through the pose where its third rod's links line up: the run
    passes it, naming the instant where that angle goes through zero (found here from the
    samples alone, by interpolation), keeps its energy across it, and flags only the samples
    around it, whose loads read zero; the others are solved."""
    dyn, q0 = delta
    t = np.linspace(0.0, 0.06, 121)
    run = simulate(dyn, t, q0, np.zeros(dyn.chain.model.nv))
    assert len(run.singular) == 1
    singular = run.singular[0]
    assert singular.rank_at < singular.rank_before == singular.rank_after
    angles = np.array([rod3_angle(dyn.chain, q) for q in run.q])
    # the rod lines up once: |angle| has one minimum, at the singular instant (the angle falls
    # linearly there, so the samples' linear interpolation of |angle| finds it within ~1e-5 s:
    # the samples are 5e-4 s apart and the angle's rate changes slowly)
    k = int(np.argmin(np.abs(angles)))
    lo, hi = (k - 1, k) if abs(angles[k - 1]) < abs(angles[k + 1]) else (k, k + 1)
    if angles[lo] * angles[hi] < 0.0:  # a sign change between them: interpolate the zero
        crossing = t[lo] + (t[hi] - t[lo]) * angles[lo] / (angles[lo] - angles[hi])
    else:  # the rod only touches the line: the sample itself
        crossing = t[k]
    assert abs(singular.time - crossing) <= 2e-5
    # no work is done: the energy is kept to the integrator's tolerance across the pass
    # (measured 6e-7 of the kinetic energy at 61 samples)
    assert run.energy_error() <= 1e-5 * run.kinetic.max()
    flagged = np.flatnonzero(run.indeterminate)
    assert flagged.size and np.all(np.diff(flagged) == 1)  # one run of samples around it
    assert t[flagged[0]] <= singular.time <= t[flagged[-1]]
    forces = run.loads.closure_forces
    assert np.all(forces[flagged] == 0.0) and np.all(np.isfinite(forces))
    assert np.abs(forces[~run.indeterminate]).max() > 0.0


def test_a_driven_run_stops_at_the_pose_and_the_choice_is_checked(delta):
    """A run with an actuation stops there by default (the stop is today's behaviour, named by
    its time); singular='pass' takes it through; other values are refused."""
    dyn, q0 = delta
    zero = np.zeros(dyn.chain.model.nv)
    t = np.linspace(0.0, 0.06, 7)

    def idle(_t, _q, _v):
        return np.zeros(len(dyn.columns))

    with pytest.raises(IntegrationError, match=r"singular pose .* at t = 0\.04"):
        simulate(dyn, t, q0, zero, idle)
    run = simulate(dyn, t, q0, zero, idle, singular="pass")
    assert len(run.singular) == 1
    with pytest.raises(InputError, match="singular must be one of"):
        simulate(dyn, t, q0, zero, singular="through")


def test_the_projection_next_to_a_flat_pose_keeps_its_branch():
    """A parallelogram a microradian from lying flat, its rockers nudged apart by 1e-12 rad: the
    projection closes the loops and stays on the parallelogram (every rocker at the same angle,
    within round-off), where the cut-off of the assembly's Newton steps (1e-9 of the largest
    singular value) would step along the vanishing one, moving them apart by r/σ (measured
    4.4e-10 rad) towards the crossing branch."""
    _, chain, _, _, _ = mount_mechanism(FOUR_BAR, None, None)
    model = chain.model
    theta = 1e-6
    q = pin.neutral(model)
    rockers = [model.joints[model.getJointId(f"r{i}")] for i in range(3)]
    for i, joint in enumerate(rockers):
        angle = theta + 1e-12 * i
        q[joint.idx_q : joint.idx_q + 2] = [math.cos(angle), math.sin(angle)]
    for i in (1, 2):
        joint = model.joints[model.getJointId(f"c{i}")]
        q[joint.idx_q : joint.idx_q + 2] = [math.cos(-theta), math.sin(-theta)]
    rate = np.zeros(model.nv)  # the parallelogram's: rockers at −5 rad/s, couplers at +5
    for name in ("r0", "r1", "r2", "c1", "c2"):
        rate[model.joints[model.getJointId(name)].idx_v] = -5.0 if name[0] == "r" else 5.0
    y = project(chain, np.concatenate([q, rate, [0.0]]))
    angles = [math.atan2(y[j.idx_q + 1], y[j.idx_q]) for j in rockers]
    assert np.ptp(angles) <= 1e-11
    assert abs(angles[0] - theta) <= 1e-11
    # the rates stay those of the parallelogram (all rockers together)
    rates = [y[model.nq + j.idx_v] for j in rockers]
    assert np.ptp(rates) <= 1e-9 * 5.0


@pytest.mark.parametrize("after", [1e-3, 5e-5])
def test_a_run_that_ends_just_past_a_flat_pose_lists_it(after):
    """The N-four-bar (N = 2) run to a little after its first flat pose (from the reference's
    1-DOF equation): the pass is listed at its time though no step follows it (its last step
    may be the coast across it, cut at the run's end)."""
    from ..test_iftomm import _four_bar_reference

    spec, chain, _, _, q0 = mount_mechanism(FOUR_BAR, None, None)
    v0 = Partition(chain, spec.independent).velocity(q0, np.array([-1.0]))
    flat = float(_four_bar_reference(2, np.linspace(0.0, 1.0, 11))[2][0])
    t = np.linspace(0.0, flat + after, 11)
    run = simulate(ChainDynamics(chain, spec.actuated), t, q0, v0, rtol=1e-10, atol=1e-12)
    assert [round(p.time, 6) for p in run.singular] == [round(flat, 6)]


def test_every_flat_pose_is_crossed_by_the_expansion_not_by_a_step(monkeypatch):
    """The step that would carry the margin past the coast's threshold is shortened to end
    inside it (RankWatch.landing): each pass of the N = 2 four-bar over 3 s (three flat poses)
    lies inside one of the run's coasts, none inside a step of the equations — without the
    landing, DOP853's 40 ms steps crossed the N = 40 four-bar's first flat pose whole."""
    from feeder.chain.dynamics import forward

    coasts = []

    def recorded(*args, **kwargs):
        path, y = coast(*args, **kwargs)
        coasts.append((path.t_min, path.t_max))
        return path, y

    coast = forward.coast
    monkeypatch.setattr(forward, "coast", recorded)
    spec, chain, _, _, q0 = mount_mechanism(FOUR_BAR, None, None)
    v0 = Partition(chain, spec.independent).velocity(q0, np.array([-1.0]))
    t = np.linspace(0.0, 3.0, 301)
    run = simulate(ChainDynamics(chain, spec.actuated), t, q0, v0, rtol=1e-10, atol=1e-12)
    assert len(run.singular) == 3
    for singular in run.singular:
        assert any(start <= singular.time <= end for start, end in coasts), singular.text()
