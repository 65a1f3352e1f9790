"""Time each command as a user runs it, as a whole process, against the start-up of its
libraries measured in the same run (issue 29).

Each case is a fresh interpreter; its CPU time (user + system, its reaped children included:
``cycle``'s figure workers, ``sweep``'s cycle workers) and its wall time are taken from
``os.wait4``. The cases run interleaved, one repeat of every case after the other, so that a
load on the shared machine weighs on all of them alike; the medians over the repeats are
printed as ratios:

* to the start-up reference ``python -c "import pinocchio, numpy, scipy"``: ``cycle`` with its
  13 figures (goal ≤ 6), ``cycle --no-figures`` (≤ 2.5), ``parameters`` (≤ 1.5);
* to a whole lean Pinocchio + SciPy script for Andrews' squeezer (the model from its URDF,
  ``constraintDynamics`` with Baumgarte in ``solve_ivp``, 1 001 states written, nothing of
  feeder imported): ``simulate`` of ``examples/andrews_squeezer`` with its figures and report
  page (≤ 2), and with ``--no-figures`` (≤ 1.3);
* the 75-elevation ``sweep`` (the default elevations) as wall time beyond the start-up
  (≤ 1.6 s on two free cores).

Before timing, feeder's sources are byte-compiled (:mod:`compileall`, as ``pip install`` does):
a shell with ``PYTHONDONTWRITEBYTECODE`` set would otherwise compile every module of feeder
afresh in every run (0.17 s of ``cycle --no-figures``), which no installed copy does.

Run: ``.venv/bin/python benchmarks/bench_commands.py [--repeats N] [--json FILE]``.
"""

from __future__ import annotations

import argparse
import compileall
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SQUEEZER = REPO / "examples" / "andrews_squeezer"
FEEDER = [sys.executable, "-m", "feeder"]
SIMULATE = [*FEEDER, "simulate", str(SQUEEZER / "andrews_squeezer.urdf"), "--closures"]
SIMULATE += [str(SQUEEZER / "squeezer.toml"), "--duration", "0.03"]

LEAN = f"""
import sys, tomllib
import numpy as np, pinocchio as pin, scipy.integrate
model = pin.buildModelFromUrdf({str(SQUEEZER / "andrews_squeezer.urdf")!r})
model.gravity.setZero()
data = model.createData()
spec = tomllib.loads(open({str(SQUEEZER / "squeezer.toml")!r}, "rb").read().decode())
q0 = np.zeros(model.nq)
for name, value in spec["mechanism"]["pose"].items():
    q0[model.joints[model.getJointId(name)].idx_q] = value
models = pin.StdVec_RigidConstraintModel()
for closure in spec["closure"]:
    a, b = (model.frames[model.getFrameId(n)] for n in closure["frames"])
    c = pin.RigidConstraintModel(pin.ContactType.CONTACT_3D, model, a.parentJoint, a.placement,
                                 b.parentJoint, b.placement, pin.LOCAL)
    c.m_baumgarte_parameters.Kp, c.m_baumgarte_parameters.Kd = 20.0**2, 2 * 20.0
    models.append(c)
datas = pin.StdVec_RigidConstraintData([c.createData() for c in models])
pin.initConstraintDynamics(model, data, models, datas)
settings = pin.ProximalSettings(1e-13, 1e-10, 100)
d, c, body = (model.getFrameId(n) for n in ("D_body3", "C_ground", "body1"))
world = pin.LOCAL_WORLD_ALIGNED
moment = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 0.033])
nq = model.nq

def rhs(t, y):
    q, v = y[:nq], y[nq:]
    pin.computeJointJacobians(model, data, q)
    gap = (pin.updateFramePlacement(model, data, c).translation
           - pin.updateFramePlacement(model, data, d).translation)
    length = np.sqrt(gap @ gap)
    tau = (4530.0 * (length - 0.07785) / length) * (gap @ pin.getFrameJacobian(model, data, d,
                                                                              world)[:3])
    tau += moment @ pin.getFrameJacobian(model, data, body, world)
    return np.concatenate([v, pin.constraintDynamics(model, data, q, v, tau, models, datas,
                                                     settings)])

t = np.linspace(0.0, 0.03, 1001)
run = scipy.integrate.solve_ivp(rhs, (0.0, 0.03), np.concatenate([q0, np.zeros(nq)]),
                                method="DOP853", rtol=1e-8, atol=1e-10, t_eval=t)
np.savetxt(sys.argv[1] + ".csv", np.column_stack([t, run.y.T]), delimiter=",")
"""
"""The lean reference: what a user would write by hand for the squeezer's run and its table
(the spring, 4 530 N/m from 0.07785 m, and the 0.033 N·m moment as generalized forces)."""

CASES = {
    "start-up": [sys.executable, "-c", "import pinocchio, numpy, scipy"],
    "lean squeezer script": [sys.executable, "-c", LEAN, "{out}"],
    "cycle": [*FEEDER, "cycle", "--elevation", "30", "--out", "{out}"],
    "cycle --no-figures": [
        *FEEDER,
        "cycle",
        "--elevation",
        "30",
        "--no-figures",
        "--out",
        "{out}",
    ],
    "parameters": [*FEEDER, "parameters"],
    "simulate": [*SIMULATE, "--out", "{out}"],
    "simulate --no-figures": [*SIMULATE, "--no-figures", "--out", "{out}"],
    "sweep (75 elevations)": [*FEEDER, "sweep", "--out", "{out}"],
}
"""Each case's command line; ``{out}`` is a fresh output path of each run."""

GOALS = {
    "cycle": ("start-up", "cpu", 6.0),
    "cycle --no-figures": ("start-up", "cpu", 2.5),
    "parameters": ("start-up", "cpu", 1.5),
    "simulate": ("lean squeezer script", "cpu", 2.0),
    "simulate --no-figures": ("lean squeezer script", "cpu", 1.3),
}
"""Issue 29's goals: case → (reference, measure, highest ratio)."""

SWEEP_GOAL = 1.6  # [s] of wall beyond the start-up, issue 29


def run_once(argv: list[str], out: Path) -> tuple[float, float]:
    """[s] CPU (user + system, reaped children included) and wall of one process."""
    argv = [word.replace("{out}", str(out)) for word in argv]
    environment = dict(os.environ, PYTHONPATH=str(REPO))
    start = time.perf_counter()
    process = subprocess.Popen(
        argv, cwd=REPO, env=environment, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE
    )
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - start
    process.returncode = os.waitstatus_to_exitcode(status)
    if process.returncode:
        raise SystemExit(f"{' '.join(argv)} failed:\n{process.stderr.read().decode()}")
    process.stderr.close()
    return usage.ru_utime + usage.ru_stime, wall


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=3, help="runs of each case (default 3)")
    parser.add_argument("--json", type=Path, help="also write the medians here")
    args = parser.parse_args(argv)
    compileall.compile_dir(REPO / "feeder", quiet=1)  # the bytecode an installed copy has
    times: dict[str, list[tuple[float, float]]] = {name: [] for name in CASES}
    with tempfile.TemporaryDirectory() as scratch:
        for repeat in range(args.repeats):
            for name, command in CASES.items():
                out = Path(scratch) / f"{repeat}-{len(times[name])}-{name.split()[0]}"
                times[name].append(run_once(command, out))
                shutil.rmtree(out, ignore_errors=True)
    medians = {
        name: {
            "cpu": statistics.median(c for c, _ in runs),
            "wall": statistics.median(w for _, w in runs),
        }
        for name, runs in times.items()
    }
    print(f"{'case':24s} {'CPU [s]':>8s} {'wall [s]':>8s}   ratio (CPU) to      goal")
    for name, median in medians.items():
        line = f"{name:24s} {median['cpu']:8.2f} {median['wall']:8.2f}"
        if name in GOALS:
            reference, measure, goal = GOALS[name]
            ratio = median[measure] / medians[reference][measure]
            median["ratio"], median["goal"] = ratio, goal
            line += f"   {ratio:5.2f} × {reference:20s} ≤ {goal:g}"
        elif name.startswith("sweep"):
            beyond = median["wall"] - medians["start-up"]["wall"]
            median["wall_beyond_start_up"], median["goal"] = beyond, SWEEP_GOAL
            line += f"   {beyond:5.2f} s wall beyond the start-up ≤ {SWEEP_GOAL:g} s"
        print(line)
    print(f"({args.repeats} repeats, medians; {os.cpu_count()} cores, shared)")
    if args.json:
        args.json.write_text(json.dumps(medians, indent=2) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
