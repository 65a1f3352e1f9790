"""The output samples of a forward run (feeder.chain.dynamics.forward_samples): the batched loop
test against Pinocchio's, and a controller's u taken at all the samples at once."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder.chain import ChainDynamics, Partition, load_mechanism, read_spec, simulate
from feeder.chain.dynamics.forward_samples import loops
from feeder.chain.readers.pose import pose_from_values
from feeder.exceptions import InputError

from ...conftest import REPO

ROUND_OFF = 1e-14
"""[m, m/s] numpy's placements and Jacobians against Pinocchio's for a ~0.4 m four-bar: round-off
of a few products of 3 × 3 rotations (1e-16 relative) on lengths and rates below 10."""


def test_the_loops_of_many_samples_are_pinocchios(four_bar, rng):
    """The largest closure error and |J q̇| of each sample, off the loop and at any rates,
    against ClosedChain.residual and ClosedChain.jacobian (Pinocchio) one sample at a time."""
    chain, _, q0 = four_bar
    q = q0 + rng.normal(scale=0.05, size=(6, q0.size))
    v = rng.normal(size=(6, q0.size))
    gap, opening = loops(chain, q, v)
    for k in range(q.shape[0]):
        assert gap[k] == pytest.approx(np.abs(chain.residual(q[k])).max(), abs=ROUND_OFF)
        rates = chain.jacobian(q[k]) @ v[k]
        assert opening[k] == pytest.approx(np.abs(rates).max(), abs=ROUND_OFF)
    np.testing.assert_array_equal(loops(chain, q)[0], gap)  # without rates, the same errors
    assert gap.min() > 1e-3  # the samples are off the loop: the test sees the errors


def test_the_loops_of_unit_circles_off_unit_length_are_pinocchios(rng):
    """The N = 2 four-bar of the IFToMM examples (continuous joints: q holds each rocker's
    (cos θ, sin θ)) with its q scaled off unit length by 1e-6: the drift a run's own steps see
    (ClosedChain.residual: Pinocchio takes the circle's values as they are), ~1e-6 m, not the
    closed loop of their unit directions."""
    spec = read_spec(REPO / "examples" / "iftomm" / "n_four_bar_2.toml")
    chain = load_mechanism(spec)
    q0 = Partition(chain, ["r0"]).mount(pose_from_values(list(spec.pose), chain.model))
    q = np.vstack([q0 * (1.0 + 1e-6), q0 * (1.0 - 1e-6), q0])
    v = rng.normal(size=(3, chain.model.nv))
    gap, opening = loops(chain, q, v)
    for k in range(q.shape[0]):
        assert gap[k] == pytest.approx(np.abs(chain.residual(q[k])).max(), abs=ROUND_OFF)
        rates = chain.jacobian(q[k]) @ v[k]
        assert opening[k] == pytest.approx(np.abs(rates).max(), abs=ROUND_OFF)
    assert gap[:2].min() > 1e-7 and gap[2] < 1e-12  # off unit length: the loop opens


class _Drive:
    """A controller without states: u = 0.02 sin 3t − 0.001 q̇_crank [N·m]; with ``many``, it
    also gives u at many samples at once (``at_samples``), or a wrong answer there."""

    n_states = 0

    def __init__(self, many: str | None = None):
        if many is not None:
            self.at_samples = getattr(self, f"_{many}")

    def start(self, t0, q0, v0):
        return np.zeros(0)

    def __call__(self, t, q, v, x):
        return np.array([0.02 * math.sin(3.0 * t) - 0.001 * v[0]]), np.zeros(0)

    @staticmethod
    def _right(t, q, v, x):
        return (0.02 * np.sin(3.0 * t) - 0.001 * v[:, 0])[:, None]

    @staticmethod
    def _misshaped(t, q, v, x):
        return np.zeros(t.size)

    @staticmethod
    def _nan(t, q, v, x):
        return np.full((t.size, 1), math.nan)


def test_a_controller_gives_its_samples_at_once_or_one_by_one(four_bar):
    """The run's actuation from ``at_samples`` is the one from ``__call__`` at each sample (the
    same law, the same integration); an answer of the wrong shape or not finite is refused."""
    chain, _, q0 = four_bar
    dyn = ChainDynamics(chain, ["crank_joint"])
    t = np.linspace(0.0, 0.5, 51)
    one_by_one = simulate(dyn, t, q0, np.zeros(3), _Drive(), loads=False)
    at_once = simulate(dyn, t, q0, np.zeros(3), _Drive("right"), loads=False)
    np.testing.assert_array_equal(at_once.q, one_by_one.q)
    # sin of an array (SIMD) and math.sin agree to an ulp: u ~ 0.02 N·m
    np.testing.assert_allclose(at_once.actuation, one_by_one.actuation, rtol=0, atol=1e-17)
    assert np.abs(one_by_one.actuation).max() > 1e-3  # a drive that acts
    with pytest.raises(InputError, match=r"must be \(51, 1\)"):
        simulate(dyn, t, q0, np.zeros(3), _Drive("misshaped"), loads=False)
    with pytest.raises(InputError, match="must be finite"):
        simulate(dyn, t, q0, np.zeros(3), _Drive("nan"), loads=False)
