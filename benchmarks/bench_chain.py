"""Time the generic closed-chain inverse dynamics (feeder.chain) per sample, in units of one bare
``constraintDynamics`` call on the same model (measured in the same run, so the ratio survives a
noisy machine; CPU times of this process, :func:`best_time`). Goals: issue 10, ≤ 3 calls per
sample for the loads with every joint's reaction; issue 15, ≤ 10 calls per sample for the whole
analysis: ``feeder.chain.track`` (continuation) plus ``inverse_dynamics`` (loads, idle
accelerations, every reaction). Each whole analysis says whether the continuation took the
batched path (``Trajectory.batched``).

Mechanisms: the example four-bar (revolute cut, 3 joints), the example slider-crank (revolute cut,
a prismatic slider among the dependent joints), the feeding device's open tree with its pin (point
cut, 4 joints, run through the generic layer), and two CAD exports read from their Extended-URDF
side-files: the Cassie-like leg (2 welds, 19 joints, two idle rod spins) and the biped
``battobot_6d`` (6 welds, 12 motors, ball and universal joints, 48 velocities).

Large mechanisms (issue 29): the IFToMM N-four-bar (examples/iftomm/n_four_bar.py) for N = 2 …
40, its first rocker driven through a swing of ±0.5 rad about the vertical (away from the flat
singular poses): the inverse dynamics as ``feeder analyze`` computes them (``inverse_dynamics``:
loads, every reaction; then ``ChainLoads.indeterminacy``, which the summaries and the tables'
columns ask for) against one bare ``constraintDynamics`` call per sample. A call of the inverse
dynamics costs a fixed part (a few hundred numpy calls of a few µs each, the indeterminacy's
subsample) plus a part per sample; each N is timed at two sample counts (``--large-samples``,
default 200, and ``--large-fit``, default 1000; the two counts' runs interleaved, so that a
change of the machine's load weighs on both) and the line time = fixed + per_sample × samples
through both gives the fixed cost per call [ms] and the marginal cost per sample [µs]. The goal,
≤ 2 × at every N, is judged on the marginal cost per sample against the bare call's (whose own
fixed part is nil); the ratio at the default count, which the fixed cost inflates at small N, is
printed beside, with the loads and reactions alone, and the growth exponents (least-squares slope
of log time over log N) of the bare call and of both per-sample costs.

Run: ``.venv/bin/python benchmarks/bench_chain.py [--samples N] [--json FILE]``.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import math
import tempfile
import time
from pathlib import Path

import numpy as np
import pinocchio as pin

from feeder.chain import (
    ChainDynamics,
    ClosedChain,
    Closure,
    Partition,
    inverse_dynamics,
    load_closed_chain,
    load_mechanism,
    read_spec,
    track,
)
from feeder.chain.dynamics.indeterminacy import indeterminacy
from feeder.chain.dynamics.inverse import check_motion
from feeder.chain.dynamics.loads_solve import solve_loads
from feeder.chain.dynamics.reactions import closure_wrenches, joint_reactions
from feeder.chain.readers.pose import pose_from_values
from feeder.device import CLOSURE, load_feeder

REPEATS = 5
GOAL = 3.0
ANALYSIS_GOAL = 10.0
LARGE_GOAL = 2.0
LOOPS = (2, 5, 10, 20, 40)
EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def best_time(function, repeats: int = REPEATS) -> float:
    """Smallest CPU time [s] of this process for one call over ``repeats`` calls: the work is on
    one thread (one BLAS thread, Pinocchio's serial calls), so on a free machine it is the wall
    time, and on a shared one it leaves out the waits for a core that other processes cause."""
    times = []
    for _ in range(repeats):
        start = time.process_time()
        function()
        times.append(time.process_time() - start)
    return min(times)


def best_times(functions, repeats: int = REPEATS) -> list[float]:
    """:func:`best_time` of each function, over ``repeats`` rounds that call every function once
    in turn: a change of the machine's load meanwhile weighs on all of them alike."""
    times = [math.inf] * len(functions)
    for _ in range(repeats):
        for i, function in enumerate(functions):
            start = time.process_time()
            function()
            times[i] = min(times[i], time.process_time() - start)
    return times


def four_bar(samples: int):
    chain = load_closed_chain(
        EXAMPLES / "four_bar" / "four_bar.urdf", [Closure("coupler_tip", "rocker_tip", "revolute")]
    )
    chain.model.gravity = pin.Motion(np.array([0.0, -9.81, 0.0]), np.zeros(3))
    partition = Partition(chain, ["crank_joint"])
    t = np.linspace(0.0, 1.0, samples)[:, None]
    x = math.radians(40.0) + 2.0 * math.pi * t
    q0 = partition.assemble(np.array([x[0, 0], -0.35, 1.0]))
    motion = track(partition, q0, x, np.full_like(x, 2.0 * math.pi), np.full_like(x, 1.0))
    return chain, ["crank_joint"], motion.q, motion.v, motion.a


def crank_turn(folder: str, cut: Closure, samples: int):
    """An example crank mechanism mounted from its zero pose, its crank turning once in 1 s."""
    chain = load_closed_chain(EXAMPLES / folder / f"{folder}.urdf", [cut])
    partition = Partition(chain, ["crank_joint"])
    q0 = partition.mount(np.zeros(chain.model.nq))
    t = np.linspace(0.0, 1.0, samples)[:, None]
    x = partition.independent_values(q0) + 2.0 * math.pi * t
    motion = (x, np.full_like(x, 2.0 * math.pi), np.zeros_like(x))
    return chain, ["crank_joint"], partition, q0, motion


def device(samples: int):
    from feeder.motion import feeding_cycle

    feeder = load_feeder("projectile")
    chain = ClosedChain(pin.Model(feeder.model), [CLOSURE])
    cycle = feeding_cycle(feeder, math.radians(-4.0))
    pick = np.linspace(0, cycle.t.size - 1, samples).round().astype(int)
    to_pin = feeder.to_pinocchio
    return (
        chain,
        ["piston_joint", "forearm_joint"],
        *(to_pin(x[pick]) for x in (cycle.q, cycle.v, cycle.a)),
    )


def bare_run(chain: ClosedChain, q: np.ndarray, v: np.ndarray, tau: np.ndarray):
    """A function that makes one bare ``constraintDynamics`` call per sample."""
    model, data = chain.model, chain.model.createData()
    pin.initConstraintDynamics(model, data, chain.constraint_models, chain.constraint_datas)
    settings = pin.ProximalSettings(1e-12, 1e-8, 20)

    def bare() -> None:
        for k in range(q.shape[0]):
            pin.constraintDynamics(
                model,
                data,
                q[k],
                v[k],
                tau[k],
                chain.constraint_models,
                chain.constraint_datas,
                settings,
            )

    return bare


def bare_call(chain: ClosedChain, q: np.ndarray, v: np.ndarray, tau: np.ndarray) -> float:
    """Best time [s] of one bare ``constraintDynamics`` call, over every sample."""
    return best_time(bare_run(chain, q, v, tau)) / q.shape[0]


def cad(name: str, samples: int):
    """A CAD export mounted from its open pose, its motors on ±0.1 rad sinusoids over 1 s."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        spec = read_spec(EXAMPLES / "cad" / name / "robot.yaml")
        chain = load_mechanism(spec)
    partition = Partition(chain, spec.independent)
    q0 = partition.mount(pin.neutral(chain.model))
    t = np.linspace(0.0, 1.0, samples)[:, None]
    ones = np.ones(len(spec.independent))
    w = 2.0 * math.pi
    model = chain.model
    index = [model.joints[model.getJointId(j)].idx_q for j in spec.independent]
    low, high = model.lowerPositionLimit[index], model.upperPositionLimit[index]
    x0 = partition.independent_values(q0)
    centre = np.where((low == 0.0) & (high == 0.0), x0, np.clip(x0, low + 0.1, high - 0.1))
    x = centre + 0.1 * np.sin(w * t) * ones
    dx, ddx = 0.1 * w * np.cos(w * t) * ones, -0.1 * w**2 * np.sin(w * t) * ones
    return chain, list(spec.actuated), partition, q0, (x, dx, ddx)


def measure_analysis(name: str, chain, actuated, partition, q0, motion) -> dict:
    """Track + loads + every reaction per sample, in bare constraintDynamics calls."""
    trajectory = track(partition, q0, *motion)
    q, v, a = trajectory.q, trajectory.v, trajectory.a
    dyn = ChainDynamics(chain, actuated)
    loads = inverse_dynamics(dyn, q, v, a)
    n = q.shape[0]
    tau = np.zeros((n, chain.model.nv))
    tau[:, dyn.columns] = np.column_stack([loads.actuators[j] for j in actuated])
    call = bare_call(chain, q, v, tau)
    per_track = best_time(lambda: track(partition, q0, *motion), repeats=2) / n
    per_loads = best_time(lambda: inverse_dynamics(dyn, q, v, a), repeats=3) / n
    ratio = (per_track + per_loads) / call
    path = "batched" if trajectory.batched else "sequential"
    print(f"{name}: {n} samples, bare constraintDynamics {call * 1e6:.2f} µs")
    print(f"  {'track, ' + path:28}{per_track * 1e6:8.2f} µs/sample = {per_track / call:6.2f}")
    print(
        f"  inverse_dynamics (all)      {per_loads * 1e6:8.2f} µs/sample = {per_loads / call:6.2f}"
    )
    print(
        f"  track + loads + reactions   {(per_track + per_loads) * 1e6:8.2f} µs/sample = "
        f"{ratio:6.2f} calls (goal ≤ {ANALYSIS_GOAL:g}): "
        f"{'PASS' if ratio <= ANALYSIS_GOAL else 'MISS'}"
    )
    return {
        "call_us": call * 1e6,
        "track_calls": per_track / call,
        "analysis_calls": ratio,
        "batched": trajectory.batched,
    }


def measure(name: str, chain: ClosedChain, actuated, q, v, a) -> dict:
    dyn = ChainDynamics(chain, actuated)
    n = q.shape[0]
    tau = np.zeros((n, chain.model.nv))
    q, v, a, motion, rows = check_motion(dyn, q, v, a)
    loads, _ = solve_loads(dyn, motion, rows)
    tau[:, dyn.columns] = loads

    def loads_only() -> None:
        _, _, _, motion, rows = check_motion(dyn, q, v, a)
        solve_loads(dyn, motion, rows)

    def everything() -> None:
        _, _, _, motion, rows = check_motion(dyn, q, v, a)
        _, lam = solve_loads(dyn, motion, rows)
        _, terms = closure_wrenches(chain, rows, lam)
        joint_reactions(dyn.chain, motion, terms)
        indeterminacy(dyn.chain, q)  # what the self-stresses leave undetermined

    call = bare_call(chain, q, v, tau)
    per_loads = best_time(loads_only) / n
    per_all = best_time(everything) / n
    ratio = per_all / call
    print(f"{name}: {n} samples, bare constraintDynamics {call * 1e6:.2f} µs")
    print(
        f"  loads + closure forces      {per_loads * 1e6:8.2f} µs/sample = {per_loads / call:5.2f}"
    )
    print(
        f"  + every joint's reaction    {per_all * 1e6:8.2f} µs/sample = {ratio:5.2f} calls "
        f"(goal ≤ {GOAL:g}): {'PASS' if ratio <= GOAL else 'MISS'}"
    )
    return {"call_us": call * 1e6, "loads_calls": per_loads / call, "all_calls": ratio}


def n_four_bar(n: int, samples: int, folder: Path):
    """The N-four-bar (module docstring) written into ``folder``, its first rocker swinging
    θ = π/2 + 0.5 sin(2π t) over 1 s, tracked; returns (chain, actuated, q, v, a)."""
    script = EXAMPLES / "iftomm" / "n_four_bar.py"
    loaded = importlib.util.spec_from_file_location("n_four_bar", script)
    module = importlib.util.module_from_spec(loaded)
    loaded.loader.exec_module(module)
    _, toml = module.write(n, folder)
    spec = read_spec(toml)
    chain = load_mechanism(spec)
    partition = Partition(chain, ["r0"])
    q0 = partition.mount(pose_from_values(list(spec.pose), chain.model))
    t = np.linspace(0.0, 1.0, samples)[:, None]
    w = 2.0 * math.pi
    x = math.pi / 2.0 + 0.5 * np.sin(w * t)
    motion = track(partition, q0, x, 0.5 * w * np.cos(w * t), -0.5 * w**2 * np.sin(w * t))
    return chain, ["r0"], motion.q, motion.v, motion.a


def _large_runs(n: int, samples: int, folder: Path) -> tuple:
    """The N-four-bar ``n`` at ``samples`` samples: functions that make the bare calls (one
    per sample), the inverse dynamics with their indeterminacy, and without it."""
    chain, actuated, q, v, a = n_four_bar(n, samples, folder)
    dyn = ChainDynamics(chain, actuated)
    loads = inverse_dynamics(dyn, q, v, a)
    tau = np.zeros((q.shape[0], chain.model.nv))
    tau[:, dyn.columns] = loads.actuators["r0"][:, None]
    run = lambda: inverse_dynamics(dyn, q, v, a)  # noqa: E731
    return bare_run(chain, q, v, tau), lambda: run().indeterminacy, run


def measure_large(samples: int, loops: tuple[int, ...] = LOOPS, fit: int = 1000) -> dict:
    """The inverse dynamics with their indeterminacy (module docstring) over the bare call for
    the N-four-bars of ``loops``: per sample at ``samples`` samples, and split into a fixed cost
    per call and a marginal cost per sample by a second count ``fit`` (the goal's measure); the
    loads and reactions alone, and the growth exponents."""
    bare, feeder, loads_only, fixed, marginal = [], [], [], [], []
    with tempfile.TemporaryDirectory() as folder:
        for n in loops:
            (call, whole, alone), (call_fit, whole_fit, _) = (
                _large_runs(n, count, Path(folder)) for count in (samples, fit)
            )
            call, whole, alone, call_fit, whole_fit = best_times(
                [call, whole, alone, call_fit, whole_fit]
            )
            bare.append(min(call / samples, call_fit / fit))  # no fixed part: per sample
            feeder.append(whole / samples)
            loads_only.append(alone / samples)
            marginal.append((whole_fit - whole) / (fit - samples))
            fixed.append(whole - marginal[-1] * samples)
            ratio = marginal[-1] / bare[-1]
            print(
                f"N-four-bar N = {n:2d}: bare {bare[-1] * 1e6:7.1f} µs; inverse dynamics "
                f"{fixed[-1] * 1e3:6.2f} ms + {marginal[-1] * 1e6:7.1f} µs/sample = "
                f"{ratio:5.2f} × per sample (goal ≤ {LARGE_GOAL:g}): "
                f"{'PASS' if ratio <= LARGE_GOAL else 'MISS'}; at {samples} samples "
                f"{feeder[-1] / bare[-1]:5.2f} ×, without the indeterminacy "
                f"{loads_only[-1] / bare[-1]:5.2f} ×"
            )
    logs = np.log(np.array(loops, dtype=float))
    growth = {
        name: float(np.polyfit(logs, np.log(np.maximum(times, 1e-12)), 1)[0])
        for name, times in (
            ("bare", bare),
            ("inverse_dynamics", feeder),
            ("per_sample", marginal),
        )
    }
    print(
        f"  growth exponents over N = {loops[0]} … {loops[-1]}: bare constraintDynamics "
        f"N^{growth['bare']:.2f}, inverse dynamics per sample N^{growth['per_sample']:.2f} "
        f"(marginal), N^{growth['inverse_dynamics']:.2f} (at {samples} samples)"
    )
    ratios = np.array(marginal) / np.array(bare)
    worst = int(np.argmax(ratios))
    verdict = "PASS" if ratios.max() <= LARGE_GOAL else "MISS"
    print(
        f"  goal ≤ {LARGE_GOAL:g} × per sample (marginal cost) at every N: {verdict} "
        f"(worst N = {loops[worst]}: {ratios[worst]:.2f} ×)"
    )
    return {
        "loops": list(loops),
        "samples": [samples, fit],
        "bare_us": [x * 1e6 for x in bare],
        "inverse_dynamics_us": [x * 1e6 for x in feeder],
        "loads_us": [x * 1e6 for x in loads_only],
        "fixed_ms": [x * 1e3 for x in fixed],
        "per_sample_us": [x * 1e6 for x in marginal],
        "per_sample_ratio": ratios.tolist(),
        "growth": growth,
    }


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--samples", type=int, default=1000, help="samples per motion (default 1000)"
    )
    parser.add_argument("--json", help="also write the figures to this JSON file")
    parser.add_argument(
        "--large-samples", type=int, default=200, help="samples per N-four-bar (default 200)"
    )
    parser.add_argument(
        "--large-only", action="store_true", help="only the N-four-bars (issue 29's scaling)"
    )
    parser.add_argument(
        "--large-fit",
        type=int,
        default=1000,
        help="the second sample count per N-four-bar, for the fixed and per-sample costs "
        "(default 1000)",
    )
    args = parser.parse_args(argv)
    if args.large_fit == args.large_samples:
        parser.error("--large-fit must differ from --large-samples (two counts make the fit)")
    if args.large_only:
        figures = {"n_four_bar": measure_large(args.large_samples, fit=args.large_fit)}
        if args.json:
            Path(args.json).write_text(json.dumps(figures, indent=2) + "\n", encoding="utf-8")
        return
    figures = {
        "four_bar": measure("four-bar (revolute cut)", *four_bar(args.samples)),
        "device": measure("feeding device (point cut)", *device(args.samples)),
    }
    for name, folder, cut in (
        ("four_bar", "four_bar", Closure("coupler_tip", "rocker_tip", "revolute")),
        ("slider_crank", "slider_crank", Closure("rod_tip", "slider_pin", "revolute")),
    ):
        figures[f"{name}_analysis"] = measure_analysis(
            f"{name.replace('_', '-')}, whole analysis", *crank_turn(folder, cut, args.samples)
        )
    for name in ("cassie_like", "battobot_6d"):
        figures[name] = measure_analysis(f"{name}, whole analysis", *cad(name, args.samples))
    figures["n_four_bar"] = measure_large(args.large_samples, fit=args.large_fit)
    if args.json:
        Path(args.json).write_text(json.dumps(figures, indent=2) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
