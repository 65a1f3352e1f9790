"""Time the computed-torque controller (feeder.chain.dynamics.control) against an open-loop
drive measured in the same run, on the four-bar following its motion table (a crank turn per
second, under gravity):

* one right-hand side of the forward run driven by the controller, against one driven by the
  reference's inverse-dynamics torque as a cubic spline (the open-loop feedforward alone): the
  law's cost is its extra ``constraintDynamics`` calls (the undriven accelerations and one per
  controlled joint) and the reference's evaluation;
* the whole 1 s run (101 samples, default tolerances) with each, and the controller's record of
  its samples.

Run: ``.venv/bin/python benchmarks/bench_control.py [--json FILE]``.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
import pinocchio as pin
import scipy.interpolate
from bench_chain import best_time  # the script's folder is on the path

from feeder.chain import ChainDynamics, Closure, Partition, load_closed_chain, simulate, track
from feeder.chain.dynamics.control import ComputedTorque
from feeder.chain.dynamics.forward_equations import ForwardEquations
from feeder.chain.dynamics.inverse import inverse_dynamics
from feeder.chain.readers import ControlSpec, read_motion

FOUR_BAR = Path(__file__).resolve().parents[1] / "examples" / "four_bar"


def setting():
    """The four-bar's dynamics, its start on the table, the controller and the open-loop
    drive."""
    chain = load_closed_chain(
        FOUR_BAR / "four_bar.urdf", [Closure("coupler_tip", "rocker_tip", "revolute")]
    )
    chain.model.gravity = pin.Motion(np.array([0.0, -9.81, 0.0]), np.zeros(3))
    partition = Partition(chain, ["crank_joint"])
    table = read_motion(FOUR_BAR / "motion.csv", ("crank_joint",))
    dyn = ChainDynamics(chain, ["crank_joint"])
    q0 = partition.assemble(np.array([table.x[0, 0], -0.35, 1.0]))
    v0 = partition.velocity(q0, table.dx[0])
    columns = table.x[:, 0], table.dx[:, 0], table.ddx[:, 0]
    spec = ControlSpec("crank_joint", FOUR_BAR / "motion.csv", table.t, *columns, 400.0, 40.0)
    controller = ComputedTorque(dyn, [spec])
    motion = track(partition, q0, table.x, table.dx, table.ddx)
    torque = inverse_dynamics(dyn, motion.q, motion.v, motion.a).actuators["crank_joint"]
    spline = scipy.interpolate.CubicSpline(table.t, torque)
    return dyn, q0, v0, controller, lambda t, q, v: np.array([spline(t)])


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--json", help="also write the figures to this JSON file")
    args = parser.parse_args(argv)
    dyn, q0, v0, controller, open_loop = setting()
    y0 = np.concatenate([q0, v0, [0.0]])
    closed = ForwardEquations(dyn, controller, 20.0)
    opened = ForwardEquations(dyn, open_loop, 20.0)
    calls = 200
    closed_rhs = best_time(lambda: [closed(0.3, y0) for _ in range(calls)]) / calls
    open_rhs = best_time(lambda: [opened(0.3, y0) for _ in range(calls)]) / calls
    t = np.linspace(0.0, 1.0, 101)
    closed_run = best_time(lambda: simulate(dyn, t, q0, v0, controller), repeats=3)
    open_run = best_time(lambda: simulate(dyn, t, q0, v0, open_loop), repeats=3)
    run = simulate(dyn, t, q0, v0, controller)
    record = best_time(lambda: controller.record(t, run.q, run.v, run.controller), repeats=3)
    figures = {
        "rhs_controlled_ms": 1e3 * closed_rhs,
        "rhs_open_loop_ms": 1e3 * open_rhs,
        "rhs_ratio": closed_rhs / open_rhs,
        "run_controlled_s": closed_run,
        "run_open_loop_s": open_run,
        "run_ratio": closed_run / open_run,
        "record_101_samples_s": record,
    }
    print(
        f"one right-hand side: controlled {1e3 * closed_rhs:.3f} ms, open loop "
        f"{1e3 * open_rhs:.3f} ms ({closed_rhs / open_rhs:.2f} ×)\n"
        f"1 s run, 101 samples: controlled {closed_run:.3f} s, open loop {open_run:.3f} s "
        f"({closed_run / open_run:.2f} ×); the record of its samples {record:.3f} s"
    )
    if args.json:
        Path(args.json).write_text(json.dumps(figures, indent=2) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
