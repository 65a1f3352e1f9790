"""benchmarks/bench_controlled.py's lean run (the floor its ratio is read against) computes the
same closed loop as the engine's controlled cycle: an independent check of both, the lean one
written with four Pinocchio calls around SciPy's DOP853 and nothing of the engine's run."""

from __future__ import annotations

import importlib.util
import math

import numpy as np

from feeder import CycleSpec, load_feeder
from feeder.chain import BaseMotion, Terrain
from feeder.device.parameters import VEHICLE_FORWARD
from feeder.dynamics.cycle import cycle_dynamics
from feeder.dynamics.loading import RTOL, controlled_cycle
from feeder.dynamics.models import FeederDynamics
from feeder.dynamics.servo import ServoGains

from ..conftest import REPO


def test_the_lean_run_is_the_engines_controlled_cycle_on_terrain(monkeypatch):
    """On the hull riding over terrain at ε = 30°, the lean run's states at the cycle's and the
    hold's samples against the engine's: both integrate the same equations at rtol 1e-6, on
    other steps (the engine also integrates the work), so they differ by their integration
    errors, at most rtol of the largest coordinate (~1.6 rad; measured 1.7e-8), where a wrong
    base term or servo would move the payload by millimetres."""
    monkeypatch.syspath_prepend(str(REPO / "benchmarks"))  # the script imports bench_chain
    spec = importlib.util.spec_from_file_location(
        "bench_controlled", REPO / "benchmarks" / "bench_controlled.py"
    )
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    device = load_feeder("projectile")
    standing = cycle_dynamics(device, math.radians(30.0), CycleSpec(), forward=False)
    feedforward = np.column_stack([standing.loads.piston_force, standing.loads.forearm_torque])
    dyn = FeederDynamics(device, BaseMotion((Terrain(),), VEHICLE_FORWARD))
    run = controlled_cycle(dyn, standing.kinematics, feedforward, ServoGains())
    lean = bench.lean_run(dyn, standing.kinematics, feedforward, ServoGains())
    assert lean.shape == run.q.shape
    assert np.abs(run.q - run.reference).max() > 1e-3  # the hull moves the device off its path
    np.testing.assert_allclose(lean, run.q, rtol=0.0, atol=RTOL * np.abs(run.q).max())
