"""The loading cycle run forward under position control (feeder.dynamics.loading): standing it
reproduces the prescribed cycle, on a moving hull its accelerations satisfy MuJoCo's equations
with the servo's forces, and the loading pose's measures mean what they say."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pinocchio as pin
import pytest

import feeder
from feeder.chain import BaseMotion, Terrain
from feeder.chain.dynamics.forward_equations import ForwardEquations
from feeder.chain.dynamics.projection import project
from feeder.device.parameters import VEHICLE_FORWARD
from feeder.dynamics.cycle import FORWARD_TOLERANCE, cycle_dynamics
from feeder.dynamics.loading import (
    ANGLE_TOLERANCE,
    POSITION_TOLERANCE,
    controlled_cycle,
    reduced_inertia,
)
from feeder.dynamics.models import FeederDynamics
from feeder.dynamics.servo import ServoGains
from feeder.exceptions import FeederWarning, InputError

RATE = 250.0
"""[Hz] The runs' samples: the engine's steps are its own, the samples only where it reports
(and the reference's interpolation nodes: its error at 250 Hz is still ~1e-10 of the loads)."""


@pytest.fixture(scope="module")
def standing(feeder):
    """The 30° cycle standing level at :data:`RATE`: its dynamics and feedforward."""
    d = cycle_dynamics(feeder, math.radians(30.0), feeder_spec(), forward=False)
    return d, np.column_stack([d.loads.piston_force, d.loads.forearm_torque])


def feeder_spec() -> feeder.CycleSpec:
    return feeder.CycleSpec(rate=RATE)


@pytest.fixture(scope="module")
def terrain_run(feeder, standing):
    """The 30° cycle riding over terrain under the default gains."""
    d, feedforward = standing
    dyn = FeederDynamics(feeder, BaseMotion((Terrain(),), VEHICLE_FORWARD))
    return controlled_cycle(dyn, d.kinematics, feedforward, ServoGains())


def test_standing_cycle_is_held_and_its_loads_are_the_prescribed_ones(feeder, standing):
    """Zero disturbance and exact feedforward: the reference is a solution of the closed loop,
    so the run departs from it only by the integration error (rtol 1e-11 here) and the
    reference's interpolation between samples (quintic Hermite for q, O(h⁶); a cubic spline
    for the loads, O(h⁴): ~1e-9 N at 250 Hz, i.e. 1e-15 m through K_p ~ 1e6 N/m). Measured:
    9e-13 rad; 1e-9 leaves a margin for the integrator's per-step control."""
    d, feedforward = standing
    run = controlled_cycle(
        FeederDynamics(feeder), d.kinematics, feedforward, ServoGains(), rtol=1e-11, atol=1e-13
    )
    phi3, phi4 = run.tracking_error()
    assert max(phi3, phi4) <= FORWARD_TOLERANCE  # the requirement
    assert max(phi3, phi4) <= 1e-9
    n = run.cycle_samples
    # the drives apply the inverse dynamics of the prescribed motion (an independent solve)
    scale = np.abs(feedforward).max(axis=0)
    assert np.all(np.abs(run.applied[:n] - feedforward).max(axis=0) <= 1e-6 * scale)
    pose = run.loading_pose()
    assert pose.off_line <= 1e-9 and pose.angle <= 1e-9 and pose.settle_time == 0.0
    assert not run.saturated.any() and run.saturation() == []
    # the hold holds: the reference's last pose, at rest
    hold = run.t > run.end
    np.testing.assert_allclose(
        run.q[hold], np.tile(d.kinematics.q[-1], (hold.sum(), 1)), atol=1e-9
    )


def test_the_rammers_line_is_the_barrels_axis(feeder, standing):
    """At the end of stage 3 the prescribed payload axis lies along the barrel: ±(−cos ε,
    sin ε, 0) (REFERENCE.md), the line the error is measured against."""
    k = standing[0].kinematics
    barrel = np.array([-math.cos(k.elevation), math.sin(k.elevation), 0.0])
    assert abs(abs(k.payload_axis[-1] @ barrel) - 1.0) < 1e-12


@pytest.mark.parametrize("gripped", [False, True])
def test_reduced_inertia_is_twice_the_kinetic_energy_of_a_unit_actuated_rate(
    feeder, standing, gripped
):
    """Gᵀ M G's diagonal against Pinocchio's kinetic energy of the closed-chain velocity with
    one actuated rate 1 (another algorithm: the bodies' spatial velocities, not CRBA), with the
    tray empty and with the payload gripped."""
    dyn = FeederDynamics(feeder)
    q = standing[0].kinematics.q[[0, 500, 875]]
    case = dyn.cases[int(gripped)]
    partition = case.dynamics.partition
    largest = np.zeros(2)
    for pose in dyn.to_pinocchio(q):
        for i in range(2):
            velocity = partition.velocity(pose, np.eye(2)[i])
            energy = pin.computeKineticEnergy(case.model, case.data, pose, velocity)
            largest[i] = max(largest[i], 2.0 * energy)
    np.testing.assert_allclose(reduced_inertia(dyn, q, gripped), largest, rtol=1e-12)


def test_each_load_case_has_its_loops_bandwidth(terrain_run):
    """The gains of each load case put each drive alone (its reduced inertia m, K_p, K_d) at
    the loop's natural frequency and damping: the roots of m s² + K_d s + K_p."""
    run = terrain_run
    omega = 2.0 * math.pi * run.gains.bandwidth_hz
    assert run.inertia[1, 0] > run.inertia[0, 0] and run.inertia[1, 1] > run.inertia[0, 1]
    for m, kp, kd in zip(run.inertia.ravel(), run.kp.ravel(), run.kd.ravel(), strict=True):
        poles = np.roots([m, kd, kp])
        # a double root (ζ = 1) splits by √(round-off) of the discriminant: 1e-7 relative
        np.testing.assert_allclose(np.abs(poles), omega, rtol=1e-7)
        np.testing.assert_allclose(-poles.real / np.abs(poles), run.gains.damping, rtol=1e-7)


def test_settling_is_the_last_entry_into_the_tolerances(feeder, standing):
    """The settling time against hand-placed errors over the hold."""
    d, feedforward = standing
    run = controlled_cycle(FeederDynamics(feeder), d.kinematics, feedforward, ServoGains())
    k = run.cycle_samples - 1
    off, angle = np.zeros(run.t.size), np.zeros(run.t.size)
    off[k + 10] = 2.0 * POSITION_TOLERANCE  # out at 40 ms
    angle[k + 30] = 2.0 * ANGLE_TOLERANCE  # out again at 120 ms: settles at 124 ms
    pose = dataclasses.replace(run, off_line=off, axis_error=angle).loading_pose()
    assert pose.settle_time == pytest.approx(31 / RATE, abs=1e-12)
    off[-1] = 2.0 * POSITION_TOLERANCE
    assert dataclasses.replace(run, off_line=off).loading_pose().settle_time is None


def test_moving_base_accelerations_satisfy_mujocos_equations(feeder, terrain_run):
    """At the run's gripped samples (every 25th), MuJoCo's M q̈ + b − Jᵀλ on the hull's six
    joints (tests/chain/dynamics/test_base_mujoco.py's converter, the hull driven by the same
    terrain) needs exactly the forces the servo applied: the engine's moving base, closure and
    the controller's forces agree with an independent engine at the accelerations the engine's
    equations give under those forces (the run keeps its motion alone: loads=False)."""
    from ..chain.dynamics.test_base_mujoco import BRACKET, mujoco_loads

    pytest.importorskip("mujoco")
    run = terrain_run
    keep = np.flatnonzero(run.t >= 1.0)[::25]
    base = BaseMotion((Terrain(),), VEHICLE_FORWARD)
    gripped = FeederDynamics(feeder, base).cases[1].dynamics
    t = run.t[keep]
    q, v = (feeder.to_pinocchio(x[keep]) for x in (run.q, run.v))
    # the samples as integrated close the loop to the drift tolerance (1e-10); the converter
    # checks its loop equations at round-off: compared on the nearest closed states
    closed = np.array([project(gripped.chain, y) for y in np.hstack([q, v])])
    q, v = closed[:, : q.shape[1]], closed[:, q.shape[1] :]
    a = np.array(
        [
            ForwardEquations(gripped, lambda *_, u=u: u, 0.0).sample_accelerations(*sample)
            for sample, u in zip(zip(t, q, v, strict=True), run.applied[keep], strict=True)
        ]
    )
    model = pin.Model(feeder.chain.model)
    model.inertias[0] = BRACKET  # MuJoCo refuses a massless moving body; the drives' loads
    chain = feeder.chain.__class__(model, feeder.chain.closures)  # do not depend on it
    ref = mujoco_loads(chain, base, t, q, v, a)
    scale = np.abs(run.applied[keep]).max(axis=0)
    # both engines solve the same rigid-body equations at the same (q, q̇, q̈): round-off of
    # the loads (the MuJoCo test's 1e-9)
    error = np.abs(ref.actuators - run.applied[keep]).max(axis=0) / scale
    assert np.all(error <= 1e-9), error
    assert run.loading_pose().off_line > POSITION_TOLERANCE  # the hull matters at 5 Hz


def test_terrain_moves_the_payload_off_the_line_and_the_drives_work_harder(standing, terrain_run):
    """What the moving hull changes (the notebook's finding, in its sign): the loading pose is
    off the line, the drives' peaks exceed the prescribed standing cycle's, the hull's motion
    continues, so the error does not settle within the hold at 5 Hz."""
    d, _ = standing
    run = terrain_run
    n = run.cycle_samples
    assert run.loading_pose().settle_time is None
    assert run.pressures.peak()[:n].max() > d.pressures.peak().max()
    assert np.abs(run.rack_force[:n]).max() > np.abs(d.rack_force).max()
    assert run.closure_residual.max() < 1e-9


def test_bad_inputs_are_refused_in_one_line(feeder, standing):
    d, feedforward = standing
    dyn, k = FeederDynamics(feeder), d.kinematics
    with pytest.raises(InputError, match=r"must be \(N, 2\)"):
        controlled_cycle(dyn, k, feedforward[:, :1], ServoGains())
    with pytest.raises(InputError, match="feedforward"):
        controlled_cycle(dyn, k, np.full_like(feedforward, np.nan), ServoGains())
    with pytest.raises(InputError, match="hold"):
        controlled_cycle(dyn, k, feedforward, ServoGains(), hold=0.0)
    coarse = cycle_dynamics(feeder, math.radians(30.0), _coarse_spec(4.0), forward=False)
    ff = np.column_stack([coarse.loads.piston_force, coarse.loads.forearm_torque])
    with pytest.raises(InputError, match="sample faster"):
        controlled_cycle(dyn, coarse.kinematics, ff, ServoGains())


def _coarse_spec(rate: float) -> feeder.CycleSpec:
    with pytest.warns(FeederWarning):  # the spec itself warns of the peaks it may miss
        return feeder.CycleSpec(rate=rate)
