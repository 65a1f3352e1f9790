"""Time the device's controlled forward cycle on a moving hull against the standing inverse-
dynamics cycle of the same rate, both measured in this run (issue 31, goal ≤ 5 ×).

* the reference: ``cycle_dynamics(..., forward=False)`` standing level — the loads and every
  joint reaction of the prescribed cycle;
* the controlled run: :func:`feeder.dynamics.loading.controlled_cycle` on the hull riding over
  terrain (``Terrain()``), the default gains, from the same cycle's kinematics and feedforward
  (the engine's forward run, stage by stage, and its hold of 0.5 s at the loading pose).

Beside them, the floor of any Python run of the same closed loop: a lean Pinocchio + SciPy
integration (:func:`lean_run`): the same device models, servo law, base motion, tolerances and
output samples, its right-hand side the four Pinocchio calls the moving base needs and the
servo's interpolation (no work or base-work states, no checks, no projections, no loads, no
outputs beyond the states), SciPy's DOP853 stepped by hand as the engine steps it.

Each is the best of ``--repeats`` calls. Beside them, what a user waits for: the two as
commands, ``feeder cycle --no-forward --no-figures`` standing against ``feeder cycle
--base-motion terrain --forward controlled --no-figures`` (each a whole process: imports, the
prescribed cycle's loads on the hull, the table), wall times interleaved, their medians.

Run: ``.venv/bin/python benchmarks/bench_controlled.py [--rate HZ] [--elevation DEG]
[--repeats N] [--json FILE]``.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from bench_chain import best_time  # the script's folder is on the path

import feeder
from feeder.chain import BaseMotion, Terrain
from feeder.device.parameters import VEHICLE_FORWARD
from feeder.dynamics.cycle import cycle_dynamics
from feeder.dynamics.loading import controlled_cycle
from feeder.dynamics.models import FeederDynamics
from feeder.dynamics.servo import ServoGains

GOAL = 5.0
"""Issue 31's goal: the controlled cycle within five times the standing inverse dynamics."""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rate", type=float, default=1000.0, help="sample rate [Hz]")
    parser.add_argument("--elevation", type=float, default=30.0, help="ε [deg]")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--json", type=Path, help="also write the figures here")
    args = parser.parse_args()
    device = feeder.load_feeder("projectile")
    spec = feeder.CycleSpec(rate=args.rate)
    elevation = math.radians(args.elevation)
    standing = cycle_dynamics(device, elevation, spec, forward=False)
    feedforward = np.column_stack([standing.loads.piston_force, standing.loads.forearm_torque])
    dyn = FeederDynamics(device, BaseMotion((Terrain(),), VEHICLE_FORWARD))
    gains = ServoGains()

    reference = best_time(
        lambda: cycle_dynamics(device, elevation, spec, forward=False), args.repeats
    )
    controlled = best_time(
        lambda: controlled_cycle(dyn, standing.kinematics, feedforward, gains), args.repeats
    )
    run = controlled_cycle(dyn, standing.kinematics, feedforward, gains)
    # the same closed loop: the states agree to the integrators' tolerance (rtol 1e-6 on both;
    # the engine also integrates the work, which moves its steps)
    drift = float(np.abs(lean_run(dyn, standing.kinematics, feedforward, gains) - run.q).max())
    lean = best_time(lambda: lean_run(dyn, standing.kinematics, feedforward, gains), args.repeats)
    ratio = controlled / reference
    commands = _commands(args.rate, args.elevation, args.repeats)
    figures = {
        "rate_hz": args.rate,
        "elevation_deg": args.elevation,
        "standing_inverse_dynamics_s": reference,
        "controlled_on_terrain_s": controlled,
        "ratio": ratio,
        "goal": GOAL,
        "lean_s": lean,
        "lean_ratio": lean / reference,
        "lean_largest_difference": drift,
        "samples": int(run.t.size),
        "commands_wall_s": commands,
        "commands_ratio": commands["controlled"] / commands["standing"],
    }
    print(
        f"standing inverse-dynamics cycle: {reference * 1e3:.1f} ms; controlled forward cycle "
        f"on terrain (+0.5 s hold, {run.t.size} samples): {controlled * 1e3:.0f} ms; ratio "
        f"{ratio:.1f} × (goal ≤ {GOAL:g} ×: {'met' if ratio <= GOAL else 'not met'})"
    )
    print(
        f"lean Pinocchio + SciPy run of the same closed loop (its states within {drift:.1e} of "
        f"the engine's): {lean * 1e3:.0f} ms, {lean / reference:.1f} × the reference; the "
        f"engine's run is {controlled / lean:.1f} × the lean one"
    )
    print(
        f"as commands (wall, medians): standing {commands['standing']:.2f} s, controlled on "
        f"terrain {commands['controlled']:.2f} s; ratio "
        f"{commands['controlled'] / commands['standing']:.1f} ×"
    )
    if args.json is not None:
        args.json.write_text(json.dumps(figures, indent=2) + "\n", encoding="utf-8")


def lean_run(
    dyn: FeederDynamics, kinematics, feedforward: np.ndarray, gains: ServoGains
) -> np.ndarray:
    """The controlled cycle's states q (N + M, 4), paper order, at the cycle's N samples and its
    hold's M after them, by the leanest run of the same equations (module docstring): per piece
    (the stages, then the hold of :data:`~feeder.dynamics.loading.HOLD`), the servo of
    :func:`~feeder.dynamics.loading.controlled_cycle` (gains per load case, the feedforward's
    left limit at the grip), DOP853 at the controlled run's tolerances, its dense output at the
    samples."""
    from feeder.dynamics.integrator import ADAMS_ORDER, lagrange_weights
    from feeder.dynamics.loading import HOLD, INERTIA_SAMPLES, reduced_inertia
    from feeder.dynamics.servo import CycleServo

    k = kinematics
    poses = k.q[np.linspace(0, k.t.size - 1, INERTIA_SAMPLES).astype(int)]
    inertia = np.array([reduced_inertia(dyn, poses, gripped) for gripped in (False, True)])
    kp, kd = gains.gains(inertia)
    low, high = gains.limits(dyn.feeder.params)
    actuated = [int(i) for i in dyn.index[[1, 3]]]
    edges = np.flatnonzero(np.diff(k.stage)) + 1
    pieces = list(zip(np.concatenate([[0], edges]), np.append(edges, k.t.size - 1), strict=True))
    step = 1.0 / k.spec.rate
    hold_t = k.t[-1] + step * np.arange(round(HOLD / step) + 1)
    still = np.zeros((hold_t.size, 2))
    y = np.concatenate([dyn.to_pinocchio(k.q[0]), dyn.to_pinocchio(k.v[0])])
    states = []
    for n, (a, b) in enumerate([*pieces, (None, None)]):
        if b is None:  # the hold at the loading pose
            t, flag = hold_t, int(k.gripped[-1])
            reference = (np.tile(k.q[-1, [1, 3]], (hold_t.size, 1)), still, still)
            u = np.tile(feedforward[-1], (hold_t.size, 1))
        else:
            t, flag = k.t[a : b + 1], int(k.gripped[a])
            reference = tuple(x[a : b + 1, [1, 3]] for x in (k.q, k.v, k.a))
            u = feedforward[a : b + 1].copy()
            if k.gripped[b] != k.gripped[a]:  # the loads' left limit at the grip
                weights = lagrange_weights(np.arange(ADAMS_ORDER) - ADAMS_ORDER, 0.0)
                u[-1] = weights @ u[-1 - ADAMS_ORDER : -1]
        servo = CycleServo(t, *reference, u, actuated, kp[flag], kd[flag], low, high)
        piece = _lean_piece(dyn.cases[flag].dynamics, servo, t, y)
        y = piece[-1]
        states.append(piece[:-1] if n < len(pieces) else piece)
    return dyn.to_paper(np.concatenate(states)[:, :4])


def _lean_piece(chain_dynamics, servo, t: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The states (q, q̇) (n, 8) of one piece at its samples t (n,) from y (8,) (:func:`lean_run`):
    q̈ from ``constraintDynamics`` with the moving base's terms (the standing bias minus the
    rooted model's, as :mod:`feeder.chain.dynamics.forward_base` forms them)."""
    import pinocchio as pin
    import scipy.integrate

    from feeder.chain.dynamics.forward_base import stage_times
    from feeder.chain.dynamics.forward_equations import PROXIMAL, ForwardEquations
    from feeder.dynamics.loading import ATOL, RTOL

    equations = ForwardEquations(chain_dynamics, None, 20.0)  # its containers only
    model, data, moving = equations.model, equations.data, equations.moving
    constraints, datas = equations.constraints, equations.datas
    none, zero = np.zeros(0), np.zeros(4)

    def rhs(time: float, state: np.ndarray) -> np.ndarray:
        q, v = state[:4], state[4:]
        tau = np.zeros(4)
        tau[servo.columns] = servo(time, q, v, none)[0]
        q0, v0, a0 = moving.root(time)
        rooted_q, rooted_v = np.concatenate([q0, q]), np.concatenate([v0, v])
        rooted = pin.rnea(
            moving.rooted, moving.data, rooted_q, rooted_v, np.concatenate([a0, zero])
        )
        tau += pin.nonLinearEffects(model, data, q, v) - rooted[6:]
        acceleration = pin.constraintDynamics(model, data, q, v, tau, constraints, datas, PROXIMAL)
        return np.concatenate([v, acceleration])

    solver = scipy.integrate.DOP853(rhs, t[0], y, t[-1], rtol=RTOL, atol=ATOL)
    out = np.empty((t.size, y.size))
    out[0], i = y, 1
    while i < t.size:
        moving.prepare(stage_times(solver))
        solver.step()
        end = int(np.searchsorted(t, solver.t, side="right"))
        if end > i:
            out[i:end] = solver.dense_output()(t[i:end]).T
            i = end
    return out


def _commands(rate: float, elevation: float, repeats: int) -> dict[str, float]:
    """Median wall times [s] of the standing and the controlled ``feeder cycle`` commands
    (module docstring), run interleaved ``repeats`` times each."""
    common = ["--elevation", f"{elevation:g}", "--rate", f"{rate:g}", "--no-figures"]
    cases = {
        "standing": [*common, "--no-forward"],
        "controlled": [*common, "--base-motion", "terrain", "--forward", "controlled"],
    }
    walls: dict[str, list[float]] = {name: [] for name in cases}
    with tempfile.TemporaryDirectory() as folder:
        for k in range(repeats):
            for name, options in cases.items():
                out = Path(folder) / f"{name}{k}"
                start = time.perf_counter()
                subprocess.run(
                    [sys.executable, "-m", "feeder", "cycle", *options, "--out", str(out)],
                    check=True,
                    stdout=subprocess.DEVNULL,
                )
                walls[name].append(time.perf_counter() - start)
    return {name: statistics.median(times) for name, times in walls.items()}


if __name__ == "__main__":
    main()
