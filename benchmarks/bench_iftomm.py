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

Run: ``.venv/bin/python benchmarks/bench_iftomm.py [--json FILE] [--quick]`` (``--quick``: N = 40
over 3 s only).
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import numpy as np
import pinocchio as pin
import scipy.integrate
import scipy.special

from feeder.chain import ChainDynamics, Partition, simulate
from feeder.study.analyze import mount_mechanism
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
    models = pin.StdVec_RigidConstraintModel()
    for constraint in chain.constraint_models:
        copy = pin.RigidConstraintModel(constraint)
        copy.m_baumgarte_parameters.Kp = RATE**2
        copy.m_baumgarte_parameters.Kd = 2.0 * RATE
        models.append(copy)
    datas = pin.StdVec_RigidConstraintData()
    for constraint in models:
        datas.append(constraint.createData())
    if len(models):
        pin.initConstraintDynamics(model, data, models, datas)
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", type=Path, help="write the figures to this file")
    parser.add_argument("--quick", action="store_true", help="N = 40 over 3 s only")
    args = parser.parse_args()
    cases = [
        pendulum_case(),
        four_bar_case(2, 20.0),
        four_bar_case(40, 3.0 if args.quick else 20.0),
    ]
    print(
        f"{'problem':44} {'feeder [s]':>10} {'error':>9} {'lean [s]':>9} {'error':>9} {'ratio':>6}"
    )
    for name, wall, error, lean_wall, lean_error in cases:
        print(
            f"{name:44} {wall:10.2f} {error:9.1e} {lean_wall:9.2f} {lean_error:9.1e} "
            f"{wall / lean_wall:6.1f}"
        )
    print(f"N = 40 wall: {cases[-1][1]:.1f} s (goal ≤ 10 s through 20 s)")
    if args.json:
        keys = ("problem", "feeder_s", "feeder_error", "lean_s", "lean_error")
        args.json.write_text(json.dumps([dict(zip(keys, case, strict=True)) for case in cases]))


if __name__ == "__main__":
    main()
