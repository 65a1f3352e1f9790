"""Batched continuation (feeder.chain.assembly.batch) against the sequential one, sample by
sample: the same poses, rates, accelerations and gains, on a planar four-bar turning twice
(redundant rows, wrapped angles), a slider-crank (a prismatic joint) and on the CAD biped (ball
and universal joints, 6 welds)."""

from __future__ import annotations

import warnings

import numpy as np
import pinocchio as pin
import pytest

import feeder.chain.assembly.batch as batch
import feeder.chain.assembly.tracking as tracking
from feeder.chain import Closure, Partition, load_closed_chain, load_mechanism, read_spec, track
from feeder.chain.assembly.batch import MIN_SAMPLES
from feeder.exceptions import FeederWarning

from ...conftest import REPO

AGREEMENT = 1e-10
"""[rad, rad/s, rad/s²] Both paths solve the same closure to 1e-13 from different starts: the
poses agree to the Newton tolerance times the velocity gain; rates and accelerations, computed
from the same Jacobians, to round-off times the gain (measured ≤ 9e-12)."""


def four_bar():
    chain = load_closed_chain(
        REPO / "examples" / "four_bar" / "four_bar.urdf",
        [Closure("coupler_tip", "rocker_tip", "revolute")],
    )
    partition = Partition(chain, ["crank_joint"])
    q0 = partition.mount(np.zeros(3))
    t = np.linspace(0.0, 1.0, 300)[:, None]
    x = partition.independent_values(q0) + 3.0 * np.pi * t  # 1.5 turns, inside its ±4π
    return chain, ["crank_joint"], q0, (x, np.full_like(x, 3.0 * np.pi), np.zeros_like(x))


def slider_crank():
    """A prismatic joint among the dependent ones: its gain counts the slider's speed in units
    of the reach, fixed for the mechanism, so the batched path takes it."""
    chain = load_closed_chain(
        REPO / "examples" / "slider_crank" / "slider_crank.urdf",
        [Closure("rod_tip", "slider_pin", "revolute")],
    )
    partition = Partition(chain, ["crank_joint"])
    q0 = partition.mount(np.zeros(3))
    t = np.linspace(0.0, 1.0, 300)[:, None]
    x = partition.independent_values(q0) + 3.0 * np.pi * t
    return chain, ["crank_joint"], q0, (x, np.full_like(x, 3.0 * np.pi), np.zeros_like(x))


def biped():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FeederWarning)
        spec = read_spec(REPO / "examples" / "cad" / "battobot_6d" / "robot.yaml")
        chain = load_mechanism(spec)
    partition = Partition(chain, spec.independent)
    q0 = partition.mount(pin.neutral(chain.model))
    model = chain.model
    index = [model.joints[model.getJointId(name)].idx_q for name in spec.independent]
    low, high = model.lowerPositionLimit[index], model.upperPositionLimit[index]
    centre = np.clip(partition.independent_values(q0), low + 0.1, high - 0.1)
    t = np.linspace(0.0, 1.0, 200)[:, None]
    w, ones = 2.0 * np.pi, np.ones(len(spec.independent))
    x = centre + 0.05 * np.sin(w * t) * ones
    return chain, list(spec.independent), q0, (x, 0.05 * w * np.cos(w * t) * ones, None)


@pytest.mark.parametrize(
    "case", [four_bar, slider_crank, biped], ids=["four_bar", "slider_crank", "biped"]
)
def test_batched_and_sequential_continuation_agree(case, monkeypatch):
    chain, independent, q0, (x, dx, ddx) = case()
    assert x.shape[0] >= MIN_SAMPLES
    batched = track(Partition(chain, independent), q0, x, dx, ddx)
    assert batched.batched, "the batched path fell back"
    monkeypatch.setattr(tracking, "MIN_SAMPLES", x.shape[0] + 1)
    sequential = track(Partition(chain, independent), q0, x, dx, ddx)
    assert not sequential.batched
    gaps = [
        pin.difference(chain.model, a, b) for a, b in zip(batched.q, sequential.q, strict=True)
    ]
    assert np.abs(gaps).max() <= AGREEMENT
    for name in ("v", "a", "gain"):
        mine, theirs = getattr(batched, name), getattr(sequential, name)
        assert np.abs(mine - theirs).max() <= AGREEMENT * max(1.0, np.abs(theirs).max())


@pytest.mark.parametrize("redone", [0.25, 1.0], ids=["early", "after-the-redone-samples"])
def test_a_stride_too_long_for_the_motion_keeps_the_branch(redone, monkeypatch):
    """The four-bar's crank turning twice in 100 samples (14.4° a sample: a stride of 32 spans
    460°, where no cubic predicts the coupler): the batched path gives the poses of a fine
    sequential reference (1001 samples, every tenth; steps of 1.4°), or falls back — before,
    it closed loops on the other branch (5 rad off). With ``redone`` = 1 the many redone
    samples do not end it: the branch test of consecutive samples does."""
    monkeypatch.setattr(batch, "MAX_REDONE", redone)
    chain, independent, q0, _ = four_bar()
    x0 = Partition(chain, independent).independent_values(q0) - 2.0 * np.pi  # 2 turns in ±4π

    def run(samples: int):
        x = x0 + 4.0 * np.pi * np.linspace(0.0, 1.0, samples)[:, None]
        return track(Partition(chain, independent), q0, x, np.full_like(x, 4.0 * np.pi))

    coarse = run(101)
    monkeypatch.setattr(tracking, "MIN_SAMPLES", 10**6)  # the reference: sequential
    fine = run(1001)
    gaps = [pin.difference(chain.model, a, b) for a, b in zip(coarse.q, fine.q[::10], strict=True)]
    assert np.abs(gaps).max() <= AGREEMENT
