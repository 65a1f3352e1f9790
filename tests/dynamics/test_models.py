"""The device's dynamics models (feeder.dynamics.models): built once per device, vehicle and
thread, and reused without changing a result."""

from __future__ import annotations

import threading

import numpy as np

from feeder.chain import BaseMotion
from feeder.chain.model.profiles import Slope
from feeder.device.feeder import load_feeder
from feeder.device.parameters import VEHICLE_FORWARD
from feeder.dynamics import models
from feeder.dynamics.cycle import cycle_dynamics
from feeder.dynamics.inverse import SampledMotion, actuator_loads
from feeder.dynamics.models import DYNAMICS_KEPT, FeederDynamics, feeder_dynamics
from feeder.motion.cycle import feeding_cycle
from feeder.motion.laws import CycleSpec

SPEC = CycleSpec(rate=200.0)


def test_one_models_per_device_base_and_thread(feeder):
    tilted = BaseMotion((Slope(pitch=0.05),), forward=VEHICLE_FORWARD)
    level = feeder_dynamics(feeder)
    assert feeder_dynamics(feeder) is level
    assert feeder_dynamics(feeder, tilted) is feeder_dynamics(feeder, tilted) is not level
    other = load_feeder(feeder.params)
    assert feeder_dynamics(other) is not level
    elsewhere = []  # a Dask worker's threads: the models' data are scratch space, not shared
    thread = threading.Thread(target=lambda: elsewhere.append(feeder_dynamics(feeder)))
    thread.start()
    thread.join()
    assert elsewhere[0] is not level and isinstance(elsewhere[0], FeederDynamics)


def test_the_least_recent_models_are_dropped(feeder):
    first = feeder_dynamics(feeder)
    devices = [load_feeder(feeder.params) for _ in range(DYNAMICS_KEPT)]
    for device in devices:
        feeder_dynamics(device)
    assert len(models._KEPT.kept) == DYNAMICS_KEPT
    assert feeder_dynamics(devices[-1]) is feeder_dynamics(devices[-1])
    assert feeder_dynamics(feeder) is not first  # dropped, built again


def test_reused_models_give_the_loads_of_new_ones(feeder):
    """A cycle after another on the same models (their partitions and scratch data used once)
    has exactly the loads and reactions of the same cycle on models built for it alone."""
    cycle_dynamics(feeder, np.radians(60.0), SPEC, forward=False)
    reused = cycle_dynamics(feeder, np.radians(10.0), SPEC, forward=False)
    k = feeding_cycle(feeder, np.radians(10.0), SPEC)
    fresh = actuator_loads(FeederDynamics(feeder), SampledMotion(k.q, k.v, k.a, k.gripped), k.t)
    np.testing.assert_array_equal(reused.loads.piston_force, fresh.piston_force)
    np.testing.assert_array_equal(reused.loads.forearm_torque, fresh.forearm_torque)
    np.testing.assert_array_equal(reused.loads.closure_force, fresh.closure_force)
    for a, b in zip(reused.loads.runs, fresh.runs, strict=True):
        for name, joint in a.loads.joints.items():
            np.testing.assert_array_equal(joint.force, b.loads.joints[name].force)
            np.testing.assert_array_equal(joint.moment, b.loads.joints[name].moment)
