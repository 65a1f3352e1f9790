"""Time the IFToMM rigid benchmark examples (``examples/iftomm``) run by feeder against a lean
Pinocchio + SciPy script for the same problem, measured in the same run.

For each: the wall time of feeder's run (the API of ``feeder simulate``, the figures left out:
``simulate_mechanism``, or ``feeder.chain.simulate`` with the benchmark's initial rate for the
N-four-bar, whose mechanism file cannot carry it yet) beside the lean script — Pinocchio's
``constraintDynamics`` (its ``aba`` for the open pendulum) with Baumgarte inside SciPy's
``solve_ivp`` (DOP853), at the same tolerances, with no projection, no singular watch and no
loads — and both errors against the references of the tests (closed form, 1-DOF equation). The
lean script is not told about the N-four-bar's flat poses: its error there says whether it held
the branch (it is given up after :data:`LEAN_EVALUATIONS` right-hand sides: error NaN). Goals
(issue 28): N = 40 through 20 s in ≤ 10 s.

A04, Bricard's mechanism, is also timed as its README command, ``feeder simulate
examples/iftomm/bricard.urdf --closures examples/iftomm/bricard.toml --duration 10 --rtol 1e-10
--atol 1e-12 --no-figures`` in a fresh Python (wall time from the shell, start-up included),
beside Python's own start-up with feeder's command-line module imported: issue 28's goal is each
command within 1.5 s of that start-up plus twice the lean integration. Its reference is
``examples/iftomm/bricard_reference.py`` (numpy and SciPy only); the error is P3's [m]. The
spatial slider-crank (``slider_crank.*``, 5 s from the crank's 6 rad/s) is timed the same way
against ``slider_crank_reference.py``; the error is the slider's position [m].

The N = 40 four-bar over the benchmark's 20 s is also timed as its README command
(``--n40-full``, alone): ``feeder simulate examples/iftomm/n_four_bar_40.urdf --closures
examples/iftomm/n_four_bar_40.toml --duration 20 --samples 2001 --rtol 1e-10 --atol 1e-12
--no-figures`` in a fresh Python, its wall and CPU time (the child process's user + system), the
integrator's steps, right-hand sides and projections (from its summary), B0's error against the
reference and the flat poses passed; issue 28's goal is ≤ 10 s of wall on an idle machine.

Run: ``.venv/bin/python benchmarks/bench_iftomm.py [--json FILE] [--quick | --n40-full]``
(``--quick``: N = 40 over 3 s only; ``--n40-full``: only the N = 40 command over 20 s).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import math
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pinocchio as pin
import scipy.integrate
import scipy.special

from feeder.chain import ChainDynamics, Partition, simulate
from feeder.study.analyze import mount_mechanism
from feeder.study.csv import read_csv
from feeder.study.simulate import simulate_mechanism

FOLDER = Path(__file__).resolve().parents[1] / "examples" / "iftomm"
G, RATE, RTOL, ATOL = 9.81, 20.0, 1e-10, 1e-12
LEAN_EVALUATIONS = 50_000
"""Right-hand sides after which the lean script is given up (it crawls at a flat pose)."""


class GaveUp(Exception):
    """The lean script passed :data:`LEAN_EVALUATIONS`."""


def timed(function):
    start = time.perf_counter()
    result = function()
    return time.perf_counter() - start, result


def pendulum_reference(t):
    k = math.sin(math.pi / 4.0)
    sn, _, _, _ = scipy.special.ellipj(scipy.special.ellipk(k * k) - math.sqrt(G) * t, k * k)
    phi = 2.0 * np.arcsin(k * sn)
    return np.c_[np.sin(phi), -np.cos(phi)]


def four_bar_reference(n, t):
    inertia, moment = (4 * n + 1) / 3.0, (3 * n + 1) / 2.0
    solution = scipy.integrate.solve_ivp(
        lambda _, y: [y[1], -G * moment * math.cos(y[0]) / inertia],
        (t[0], t[-1]), [math.pi / 2.0, -1.0], method="DOP853", rtol=1e-13, atol=1e-13,
        t_eval=t,
    )  # fmt: skip
    return np.c_[np.cos(solution.y[0]), np.sin(solution.y[0])]


def lean(chain, q0, v0, t):
    """constraintDynamics (aba without closures) with Baumgarte in solve_ivp: q at the times t."""
    model = chain.model
    data = model.createData()
    models, datas = chain.corrected_constraints(data, RATE)  # Baumgarte's copies of the closures
    settings = pin.ProximalSettings(1e-13, 1e-10, 100)
    nq, nv = model.nq, model.nv
    zero = np.zeros(nv)

    count = [0]

    def rhs(_, y):
        count[0] += 1
        if count[0] > LEAN_EVALUATIONS:
            raise GaveUp
        q, v = y[:nq], y[nq:]
        if len(models):
            a = pin.constraintDynamics(model, data, q, v, zero, models, datas, settings)
        else:
            a = pin.aba(model, data, q, v, zero)
        if nq == nv:
            return np.concatenate([v, a])
        rate = pin.integrate(model, q, v * 1e-8)  # q̇ on the unit circles: (q(ε) − q)/ε
        return np.concatenate([(rate - q) / 1e-8, a])

    try:
        solution = scipy.integrate.solve_ivp(
            rhs, (t[0], t[-1]), np.concatenate([q0, v0]), method="DOP853", rtol=RTOL,
            atol=ATOL, t_eval=t,
        )  # fmt: skip
    except GaveUp:
        return None
    return solution.y[:nq].T if solution.success else None


def rocker(chain, q, name="r0"):
    joint = chain.model.joints[chain.model.getJointId(name)]
    return q[:, joint.idx_q : joint.idx_q + 2]


def pendulum_case():
    t = np.linspace(0.0, 10.0, 1001)
    wall, simulation = timed(
        lambda: simulate_mechanism(FOLDER / "pendulum.toml", 10.0, rtol=RTOL, atol=ATOL)
    )
    run, chain = simulation.run, simulation.chain
    reference = pendulum_reference(t)
    error = np.abs(np.c_[np.cos(run.q[:, 0]), np.sin(run.q[:, 0])] - reference).max()
    lean_wall, q = timed(lambda: lean(chain, simulation.assembled, np.zeros(chain.model.nv), t))
    lean_error = np.abs(np.c_[np.cos(q[:, 0]), np.sin(q[:, 0])] - reference).max()
    return "A01 pendulum, 10 s", wall, error, lean_wall, lean_error


def four_bar_case(n, duration):
    spec, chain, _, _, q0 = mount_mechanism(FOLDER / f"n_four_bar_{n}.toml", None, None)
    v0 = Partition(chain, spec.independent).velocity(q0, np.array([-1.0]))
    t = np.linspace(0.0, duration, int(round(duration * 100)) + 1)
    dyn = ChainDynamics(chain, spec.actuated)
    wall, run = timed(lambda: simulate(dyn, t, q0, v0, rtol=RTOL, atol=ATOL))
    reference = four_bar_reference(n, t)
    error = np.abs(rocker(chain, run.q) - reference).max()
    lean_wall, q = timed(lambda: lean(chain, q0, v0, t))
    lean_error = math.nan if q is None else np.abs(rocker(chain, q) - reference).max()
    name = f"A02 N-four-bar N = {n}, {duration:g} s ({len(run.singular)} passes)"
    return name, wall, error, lean_wall, lean_error


def example_reference(stem: str):
    """examples/iftomm/STEM_reference.py, loaded from its file (it is an example, not a
    package)."""
    spec = importlib.util.spec_from_file_location(
        f"{stem}_reference", FOLDER / f"{stem}_reference.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def command(*arguments: str) -> tuple[float, float, dict[str, np.ndarray], str]:
    """Wall and CPU time [s] (the child's user + system) of ``python -m feeder simulate
    ARGUMENTS --no-figures`` in a fresh Python, its states.csv and its summary."""
    with tempfile.TemporaryDirectory() as out:
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        subprocess.run(
            [sys.executable, "-m", "feeder", "simulate", *arguments, "--no-figures", "--out", out],
            check=True,
            capture_output=True,
        )
        wall = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
        summary = (Path(out) / "summary.txt").read_text(encoding="utf-8")
        return wall, cpu, read_csv(Path(out) / "states.csv"), summary


def start_up() -> float:
    """Wall time [s] of a fresh Python importing feeder's command-line module (the best of 3)."""
    walls = []
    for _ in range(3):
        start = time.perf_counter()
        subprocess.run([sys.executable, "-c", "import feeder.cli"], check=True)
        walls.append(time.perf_counter() - start)
    return min(walls)


def bricard_case():
    """A04 over the benchmark's 10 s: the API's run, the command's and the lean script's; their
    P3 against the reference."""
    t = np.linspace(0.0, 10.0, 1001)
    path = FOLDER / "bricard.toml"
    wall, simulation = timed(lambda: simulate_mechanism(path, 10.0, rtol=RTOL, atol=ATOL))
    chain = simulation.chain
    model, data = chain.model, chain.model.createData()
    bar2 = model.getFrameId("bar2")
    offset = np.array([0.0, -1.0, 0.0])  # P3 on bar2 (bricard.toml's [[point]])

    def p3(q):
        points = []
        for row in q:
            pin.framesForwardKinematics(model, data, row)
            points.append(data.oMf[bar2].act(offset))
        return np.array(points)

    reference = example_reference("bricard").Reference().p3(t)
    error = np.abs(p3(simulation.run.q) - reference).max()
    command_wall, _, states, _ = command(
        str(FOLDER / "bricard.urdf"), "--closures", str(path), "--duration", "10",
        "--rtol", str(RTOL), "--atol", str(ATOL),
    )  # fmt: skip
    run = np.c_[states["point_P3_x"], states["point_P3_y"], states["point_P3_z"]]
    command_error = np.abs(run - reference).max()
    lean_wall, q = timed(lambda: lean(chain, simulation.assembled, np.zeros(model.nv), t))
    lean_error = math.nan if q is None else np.abs(p3(q) - reference).max()
    name = "A04 Bricard, 10 s"
    return (name, wall, error, lean_wall, lean_error), (name, command_wall, command_error)


def slider_crank_case():
    """The spatial slider-crank over 5 s, started at the crank's 6 rad/s: the API's run, the
    command's and the lean script's; the slider's x against the reference."""
    t = np.linspace(0.0, 5.0, 1001)
    path = FOLDER / "slider_crank.toml"
    wall, simulation = timed(lambda: simulate_mechanism(path, 5.0, rtol=RTOL, atol=ATOL))
    chain = simulation.chain
    model = chain.model
    slider = model.joints[model.getJointId("slider")].idx_q
    solution = example_reference("slider_crank").Reference()
    reference = solution.slider(solution.angle(t))
    error = np.abs(simulation.run.q[:, slider] - reference).max()
    command_wall, _, states, _ = command(
        str(FOLDER / "slider_crank.urdf"), "--closures", str(path), "--duration", "5",
        "--rtol", str(RTOL), "--atol", str(ATOL),
    )  # fmt: skip
    command_error = np.abs(states["q_slider"] - reference).max()
    v0 = simulation.run.v[0]  # the file's rates closed by the run's start (initial_rates)
    lean_wall, q = timed(lambda: lean(chain, simulation.assembled, v0, t))
    lean_error = math.nan if q is None else np.abs(q[:, slider] - reference).max()
    name = "spatial slider-crank, 5 s"
    return (name, wall, error, lean_wall, lean_error), (name, command_wall, command_error)


def n40_full_case() -> dict[str, float]:
    """The N = 40 four-bar's README command over the benchmark's 20 s (module docstring): its
    wall and CPU time [s], the integrator's counts from its summary, B0's error [m] against the
    reference and the flat poses passed (the reference's count beside)."""
    wall, cpu, states, summary = command(
        str(FOLDER / "n_four_bar_40.urdf"), "--closures", str(FOLDER / "n_four_bar_40.toml"),
        "--duration", "20", "--samples", "2001", "--rtol", str(RTOL), "--atol", str(ATOL),
    )  # fmt: skip
    counts = re.search(r"(\d+) steps, (\d+) right-hand sides, (\d+) projections", summary)
    passed = re.search(r"singular positions passed: (\d+)", summary)
    reference = four_bar_reference(40, states["t"])
    crank = np.c_[np.cos(states["q_r0"]), np.sin(states["q_r0"])]
    return {
        "wall_s": wall,
        "cpu_s": cpu,
        "steps": int(counts[1]),
        "evaluations": int(counts[2]),
        "projections": int(counts[3]),
        "b0_error": float(np.abs(crank - reference).max()),
        "passes": int(passed[1]) if passed else 0,
    }


def n40_full(json_path: Path | None) -> None:
    """``--n40-full``: the N = 40 command over 20 s alone, beside Python's start-up."""
    python = start_up()
    figures = n40_full_case()
    print(
        f"A02 N = 40, 20 s, `feeder simulate --no-figures` (2001 samples): wall "
        f"{figures['wall_s']:.2f} s, CPU {figures['cpu_s']:.2f} s (Python's start-up with "
        f"feeder.cli {python:.2f} s); {figures['steps']} steps, {figures['evaluations']} "
        f"right-hand sides, {figures['projections']} projections; {figures['passes']} flat "
        f"poses passed; B0 within {figures['b0_error']:.1e} m; goal ≤ 10 s of wall "
        f"({'met' if figures['wall_s'] <= 10.0 else 'missed'})"
    )
    if json_path:
        json_path.write_text(json.dumps({**figures, "python_s": python}))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", type=Path, help="write the figures to this file")
    choice = parser.add_mutually_exclusive_group()
    choice.add_argument("--quick", action="store_true", help="N = 40 over 3 s only")
    choice.add_argument(
        "--n40-full", action="store_true", help="only the N = 40 command over 20 s"
    )
    args = parser.parse_args()
    if args.n40_full:
        n40_full(args.json)
        return
    bricard, bricard_command = bricard_case()
    slider_crank, slider_crank_command = slider_crank_case()
    cases = [
        pendulum_case(),
        four_bar_case(2, 20.0),
        four_bar_case(40, 3.0 if args.quick else 20.0),
        bricard,
        slider_crank,
    ]
    print(
        f"{'problem':44} {'feeder [s]':>10} {'error':>9} {'lean [s]':>9} {'error':>9} {'ratio':>6}"
    )
    for name, wall, error, lean_wall, lean_error in cases:
        print(
            f"{name:44} {wall:10.2f} {error:9.1e} {lean_wall:9.2f} {lean_error:9.1e} "
            f"{wall / lean_wall:6.1f}"
        )
    print(f"N = 40 wall: {cases[2][1]:.1f} s (goal ≤ 10 s through 20 s)")
    python = start_up()
    commands = []
    for name, wall, error in [bricard_command, slider_crank_command]:
        lean_wall = next(case[3] for case in cases if case[0] == name)
        goal = python + 1.5 + 2.0 * lean_wall
        commands.append((name, wall, error, python, goal))
        print(
            f"{name}: `feeder simulate --no-figures` {wall:.2f} s (error {error:.1e}), "
            f"Python's start-up {python:.2f} s, lean {lean_wall:.2f} s: "
            f"{wall / lean_wall:.1f} × the lean run; goal ≤ {goal:.2f} s "
            f"({'met' if wall <= goal else 'missed'})"
        )
    if args.json:
        keys = ("problem", "feeder_s", "feeder_error", "lean_s", "lean_error")
        figures = [dict(zip(keys, case, strict=True)) for case in cases]
        keys = ("problem", "command_s", "command_error", "python_s", "goal_s")
        figures += [dict(zip(keys, case, strict=True)) for case in commands]
        args.json.write_text(json.dumps(figures))


if __name__ == "__main__":
    main()
