"""Forward simulation of any closed chain: energy balance, drift control, and the inverse
dynamics' loads reproducing their motion."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from feeder.chain import Closure, load_closed_chain
from feeder.chain.assembly.partition import POSITION_TOLERANCE, Partition
from feeder.chain.dynamics.forward import simulate
from feeder.chain.dynamics.inverse import ChainDynamics, inverse_dynamics
from feeder.exceptions import InputError

from ...conftest import REPO

STEP = 1e-3  # [s]
ENERGY = 1e-6
"""[J] Energy balance of a 1 s RK4 run at 1 ms of a ~0.4 kg four-bar whose energy swings by
~0.1 J: RK4's error is O(h⁴) per unit time (~1e-8 J measured), Baumgarte's corrector does no
work on a closed loop; 1e-6 J leaves room and still fails a first-order integrator (~1e-3 J)."""

WORK = 1e-5
"""[J] Energy balance of the driven run (~3 J of motor work): the trapezoidal rule's O(h²) error
on the work, 2.6e-6 J measured at 1 ms, 1.0e-5 J at 2 ms, 6.5e-7 J at 0.5 ms."""

DRIFT = 1e-8
"""[m] Closure residual of a Baumgarte-stabilised run (~2e-9 m measured at ω = 20 /s)."""

TRACKING = 5e-8
"""[rad] A run driven by the inverse dynamics' torque, sampled exactly at RK4's nodes and
midpoints, follows its motion over a turn to RK4's O(h⁴) error: 1.6e-8 rad measured at 1 ms,
2.8e-7 at 2 ms, 1.0e-9 at 0.5 ms (a ratio of 16–17 per halving). Without gravity:
under gravity the 40 mm crank's open-loop motion is unstable (deviations grow like e^(13 t),
√(g/ℓ)), so a force-driven run can only be compared over a fraction of a second."""


@pytest.fixture(scope="module")
def four_bar():
    chain = load_closed_chain(
        REPO / "examples" / "four_bar" / "four_bar.urdf",
        [Closure("coupler_tip", "rocker_tip", "revolute")],
    )
    chain.model.gravity = pin.Motion(np.array([0.0, -9.81, 0.0]), np.zeros(3))
    partition = Partition(chain, ["crank_joint"])
    q0 = partition.assemble(np.array([math.radians(40.0), -0.35, 1.0]))
    return chain, partition, q0


def test_a_free_swing_keeps_its_energy_and_its_loop(four_bar):
    chain, _, q0 = four_bar
    dyn = ChainDynamics(chain, ["crank_joint"])
    t = np.arange(0.0, 1.0 + STEP / 2, STEP)
    run = simulate(dyn, lambda time, q, v: np.zeros(1), t, q0, np.zeros(chain.model.nv))
    assert np.ptp(run.energy) > 0.0 and np.abs(run.work).max() == 0.0
    assert np.ptp(run.q[:, 0]) > 0.5  # it does swing (about half a radian or more)
    assert run.energy_error() <= ENERGY
    assert run.drift() <= DRIFT


def test_projection_holds_the_loop_to_newton_accuracy(four_bar):
    chain, partition, q0 = four_bar
    dyn = ChainDynamics(chain, ["crank_joint"])
    t = np.arange(0.0, 0.2 + STEP / 2, STEP)
    free = lambda time, q, v: np.zeros(1)  # noqa: E731
    run = simulate(dyn, free, t, q0, np.zeros(chain.model.nv), rate=0.0, projection=partition)
    assert run.drift() <= 10 * POSITION_TOLERANCE  # one residual norm, one max-abs row


def test_the_inverse_dynamics_torque_drives_its_motion(four_bar):
    chain, partition, q0 = four_bar
    gravity = chain.model.gravity
    chain.model.gravity = pin.Motion.Zero()
    try:
        run, q = _driven_run(chain, partition, q0)
    finally:
        chain.model.gravity = gravity
    assert run.tracking(chain.model, q[::2]).max() <= TRACKING
    assert run.energy_error() <= WORK  # the motor's work is the change of energy


def _driven_run(chain, partition, q0):
    """The one-turn motion's inverse dynamics torque, fed back to a forward run."""
    dyn = ChainDynamics(chain, ["crank_joint"])
    fine = np.arange(0.0, 1.0 + STEP / 4, STEP / 2)  # the steps' nodes and midpoints
    x = (q0[0] + 2.0 * math.pi * fine + math.pi * fine**2)[:, None]
    dx = (2.0 * math.pi + 2.0 * math.pi * fine)[:, None]
    q, v, a, _ = partition.track(q0, x, dx, np.full_like(x, 2.0 * math.pi))
    torque = inverse_dynamics(dyn, q, v, a).actuators["crank_joint"]
    drive = lambda time, q, v: np.array([np.interp(time, fine, torque)])  # noqa: E731
    return simulate(dyn, drive, fine[::2], q[0], v[0]), q


def test_refusals(four_bar):
    chain, _, q0 = four_bar
    dyn = ChainDynamics(chain, ["crank_joint"])
    free = lambda time, q, v: np.zeros(1)  # noqa: E731
    with pytest.raises(InputError, match="increasing"):
        simulate(dyn, free, np.array([0.0, 0.0, 1.0]), q0, np.zeros(3))
    with pytest.raises(InputError, match="actuation at t = 0 s"):
        simulate(dyn, lambda time, q, v: np.array([np.nan]), np.array([0.0, 0.1]), q0, np.zeros(3))
    with pytest.raises(InputError, match="shape"):
        simulate(dyn, lambda time, q, v: np.zeros(2), np.array([0.0, 0.1]), q0, np.zeros(3))
    with pytest.raises(InputError, match="Baumgarte"):
        simulate(dyn, free, np.array([0.0, 0.1]), q0, np.zeros(3), rate=-1.0)
