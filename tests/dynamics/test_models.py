"""The device's dynamics models (feeder.dynamics.models): built once per device, vehicle and
thread, and reused without changing a result."""

from __future__ import annotations

import dataclasses
import threading

import numpy as np
import pytest

from feeder.chain import BaseMotion
from feeder.chain.model.profiles import Slope, Terrain
from feeder.device.feeder import load_feeder
from feeder.device.parameters import VEHICLE_FORWARD
from feeder.dynamics import models
from feeder.dynamics.cycle import cycle_dynamics
from feeder.dynamics.inverse import SampledMotion, actuator_loads
from feeder.dynamics.models import DYNAMICS_KEPT, FeederDynamics, feeder_dynamics
from feeder.dynamics.servo import ServoGains
from feeder.motion.cycle import feeding_cycle
from feeder.motion.laws import CycleSpec

SPEC = CycleSpec(rate=200.0)

RUN_SPEC = CycleSpec(rate=1000.0)
"""The forward runs' rate (the force rule needs 1 kHz to track the cycle: FORWARD_TOLERANCE)."""


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


def test_the_cycles_of_a_device_build_its_models_once(feeder, monkeypatch):
    built = []
    monkeypatch.setattr(models, "FeederDynamics", lambda *a: built.append(a) or FeederDynamics(*a))
    monkeypatch.setattr(models._KEPT, "kept", {})
    for elevation in (0.0, 0.3, 0.6):
        cycle_dynamics(feeder, elevation, SPEC, forward=False)
    assert len(built) == 1


def _arrays(value: object, seen: set[int] | None = None) -> list[np.ndarray]:
    """Copies of every array in a result (its dataclasses, dicts and tuples, depth first)."""
    seen = set() if seen is None else seen
    if id(value) in seen:
        return []
    seen.add(id(value))
    if isinstance(value, np.ndarray):
        return [value.copy()]
    if isinstance(value, dict):
        value = list(value.values())
    elif dataclasses.is_dataclass(value) and not isinstance(value, type):
        value = [getattr(value, f.name) for f in dataclasses.fields(value)]
    if isinstance(value, list | tuple):
        return [a for item in value for a in _arrays(item, seen)]
    return []


@pytest.mark.parametrize(
    "case",
    [
        {"forward": True},
        {"forward": False, "controlled": ServoGains()},
        {
            "forward": False,
            "controlled": ServoGains(),
            "base": BaseMotion((Terrain(),), forward=VEHICLE_FORWARD),
        },
        {"forward": True, "base": BaseMotion((Slope(pitch=0.05),), forward=VEHICLE_FORWARD)},
    ],
    ids=["force-rule", "controlled", "controlled-on-terrain", "force-rule-on-a-slope"],
)
def test_a_cycle_is_not_changed_by_the_next_on_its_models(feeder, case):
    """Every array of a cycle's results (forward and controlled runs, on a moving base too) is
    the same after another cycle ran on the same models, and equal to that of the cycle on
    models built for it alone: nothing of the models' scratch data is kept in a result."""
    models._KEPT.kept = {}
    first = cycle_dynamics(feeder, np.radians(30.0), RUN_SPEC, **case)
    before = _arrays(first)
    cycle_dynamics(feeder, np.radians(55.0), RUN_SPEC, **case)
    after = _arrays(first)
    assert len(before) == len(after) > 20
    for a, b in zip(before, after, strict=True):
        np.testing.assert_array_equal(a, b)
    models._KEPT.kept = {}
    fresh = _arrays(cycle_dynamics(feeder, np.radians(30.0), RUN_SPEC, **case))
    for a, b in zip(before, fresh, strict=True):
        np.testing.assert_array_equal(a, b)
