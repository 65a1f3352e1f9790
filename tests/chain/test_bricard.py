"""Bricard's orthogonal 6R linkage (``examples/bricard``): a redundant constraint. Its mobility is
1 where Grübler–Kutzbach counts 0, and it runs forward from rest with its energy kept and its
velocities on the one-dimensional tangent (a projection that trusted lstsq's default rank cut-off
took the round-off singular value of the redundant row for a real one and zeroed them)."""

from __future__ import annotations

import numpy as np

from feeder.chain import ChainDynamics, mobility, simulate
from feeder.study.analyze import mount_mechanism

from ..conftest import REPO

FILE = REPO / "examples" / "bricard" / "bricard.toml"


def test_mobility_is_one_where_the_count_says_zero():
    spec, chain, _, _, q = mount_mechanism(FILE, None, None)
    text = mobility(chain, q, spec.independent).text()
    assert "Grübler–Kutzbach mobility 6 − 6 = 0" in text
    assert "actual mobility 6 − 5 = 1" in text and "self-stresses of the closures: 1;" in text


def test_it_runs_forward_keeping_its_energy():
    spec, chain, _, _, q = mount_mechanism(FILE, None, None)
    run = simulate(ChainDynamics(chain, spec.actuated), np.linspace(0.0, 1.0, 101), q,
                   np.zeros(6), rtol=1e-10, atol=1e-12)  # fmt: skip
    assert run.kinetic.max() > 1.0  # it does move (3.4 J of kinetic energy measured)
    # no work is done: the energy is kept to the integrator's tolerance (2.6e-8 J measured at
    # rtol 1e-10, 1.5e-6 J at 1e-8: it converges with the tolerance); the lost-velocity bug
    # made it 0.13 J
    assert run.energy_error() <= 1e-6 * run.kinetic.max()
    assert run.drift() <= 1e-10
    # the undriven independent joint needs no drive in the run's inverse dynamics
    assert np.abs(run.loads.actuators["j2"]).max() <= 1e-6
