"""Time the forward runs of feeder.chain (``simulate``) against a lean reference measured in the
same run: Pinocchio's ``constraintDynamics`` with Baumgarte inside SciPy's ``solve_ivp`` (DOP853),
the squeezer's spring and moment hand-coded as generalized forces from frame Jacobians.

Figures (issue 16):
* Andrews' squeezer (``examples/andrews_squeezer``, from its shipped files): the wall time to
  reach 1e-8 relative in q(0.03) against the published solution — for each, the loosest rtol of
  a scan that reaches it (goal ≤ 50 ms);
* the cost of one right-hand side in bare ``constraintDynamics`` calls on the same model and
  state, on the four-bar, the Cassie-like leg and the squeezer (goal ≤ 2), and the lean
  reference's on the squeezer;
* the cost of one right-hand side on a moving base (the four-bar on a terrain ride:
  :mod:`feeder.chain.dynamics.forward_base`, the base's state evaluated at each call) against
  the same mechanism's standing one (no goal: a measurement, issue 31).

Run: ``.venv/bin/python benchmarks/bench_forward.py [--json FILE]``.
"""

from __future__ import annotations

import argparse
import json
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pinocchio as pin
import scipy.integrate
from bench_chain import best_time  # the script's folder is on the path

from feeder.chain import (
    BaseMotion,
    ChainDynamics,
    Closure,
    Partition,
    Terrain,
    load_closed_chain,
    load_mechanism,
    read_spec,
    simulate,
)
from feeder.chain.dynamics.forward_equations import ForwardEquations

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
SQUEEZER = EXAMPLES / "andrews_squeezer"
RTOLS = (1e-6, 3e-7, 1e-7, 3e-8, 1e-8, 3e-9, 1e-9, 3e-10, 1e-10)
TARGET = 1e-8
RATE = 20.0  # Baumgarte [1/s], as simulate's default


def squeezer():
    spec = read_spec(SQUEEZER / "squeezer.toml")
    chain = load_mechanism(spec)
    reference = tomllib.loads((SQUEEZER / "reference.toml").read_text(encoding="utf-8"))
    order = [chain.model.getJointId(n) - 1 for n in reference["coordinates"]["paper"]]
    q0, q_end = np.empty(7), np.empty(7)
    q0[order] = [float(x) for x in reference["initial"]["q"]]
    q_end[order] = reference["final"]["q"]
    return spec, chain, q0, q_end


def lean_run(chain, q0, rtol):
    """The reference: constraintDynamics in solve_ivp, the spring (D_body3–C_ground, 4530 N/m,
    0.07785 m) and the moment (0.033 N·m on body1) as generalized forces."""
    model, data = chain.model, chain.model.createData()
    models = pin.StdVec_RigidConstraintModel()
    for constraint in chain.constraint_models:
        copy = pin.RigidConstraintModel(constraint)
        copy.m_baumgarte_parameters.Kp, copy.m_baumgarte_parameters.Kd = RATE**2, 2 * RATE
        models.append(copy)
    datas = pin.StdVec_RigidConstraintData()
    for constraint in models:
        datas.append(constraint.createData())
    pin.initConstraintDynamics(model, data, models, datas)
    settings = pin.ProximalSettings(1e-13, 1e-10, 100)
    d, c, body = (model.getFrameId(n) for n in ("D_body3", "C_ground", "body1"))
    world = pin.LOCAL_WORLD_ALIGNED
    moment = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 0.033])

    def rhs(t, y):
        q, v = y[:7], y[7:]
        pin.computeJointJacobians(model, data, q)
        gap = (
            pin.updateFramePlacement(model, data, c).translation
            - pin.updateFramePlacement(model, data, d).translation
        )
        length = np.sqrt(gap @ gap)
        jd = pin.getFrameJacobian(model, data, d, world)[:3]
        tau = (4530.0 * (length - 0.07785) / length) * (gap @ jd)
        tau += moment @ pin.getFrameJacobian(model, data, body, world)
        a = pin.constraintDynamics(model, data, q, v, tau, models, datas, settings)
        return np.concatenate([v, a])

    solution = scipy.integrate.solve_ivp(
        rhs, (0.0, 0.03), np.concatenate([q0, np.zeros(7)]), method="DOP853", rtol=rtol,
        atol=rtol * 1e-2,
    )  # fmt: skip
    return solution.y[:7, -1], solution.nfev, rhs


def scan(name, run, q_end):
    """The loosest rtol reaching TARGET, its wall time and evaluations."""
    for rtol in RTOLS:
        q, count = run(rtol)
        error = np.abs(q - q_end).max() / np.abs(q_end).max()
        if error <= TARGET:
            wall = best_time(lambda rtol=rtol: run(rtol))
            print(
                f"  {name:34s} rtol {rtol:g}: error {error:.1e}, {count} right-hand sides, "
                f"{wall * 1e3:6.1f} ms"
            )
            return {"rtol": rtol, "error": error, "evaluations": count, "ms": wall * 1e3}
    print(f"  {name}: no rtol of the scan reaches {TARGET:g}")
    return {}


def bare_call_time(chain, q, v) -> float:
    model, data = chain.model, chain.model.createData()
    pin.initConstraintDynamics(model, data, chain.constraint_models, chain.constraint_datas)
    settings, tau = pin.ProximalSettings(1e-13, 1e-10, 100), np.zeros(model.nv)
    n = 2000

    def calls():
        for _ in range(n):
            pin.constraintDynamics(
                model, data, q, v, tau, chain.constraint_models, chain.constraint_datas, settings
            )

    return best_time(calls) / n


def rhs_time(function, y) -> float:
    n = 2000

    def calls():
        for _ in range(n):
            function(0.0, y)

    return best_time(calls) / n


def rhs_ratio(name, dyn, q, v) -> float:
    equations = ForwardEquations(dyn, None, RATE)
    y = np.concatenate([q, v, [0.0]])
    ratio = rhs_time(equations, y) / bare_call_time(dyn.chain, q, v)
    print(f"  {name:34s} {ratio:5.2f} calls (goal ≤ 2): {'PASS' if ratio <= 2 else 'MISS'}")
    return ratio


def base_ratio(name, dyn, moving, q, v) -> float:
    """One right-hand side on the moving base ``moving`` over the standing ``dyn``'s."""
    standing = rhs_time(ForwardEquations(dyn, None, RATE), np.concatenate([q, v, [0.0]]))
    rolling = rhs_time(ForwardEquations(moving, None, RATE), np.concatenate([q, v, [0.0, 0.0]]))
    print(f"  {name:34s} {rolling / standing:5.2f} standing right-hand sides")
    return rolling / standing


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--json", help="also write the figures to this JSON file")
    args = parser.parse_args(argv)
    spec, chain, q0, q_end = squeezer()
    dyn = ChainDynamics(chain, spec.actuated, elements=spec.forces)
    t = np.array([0.0, 0.03])

    def ours(rtol):
        run = simulate(dyn, t, q0, np.zeros(7), rtol=rtol, atol=rtol * 1e-2)
        return run.q[-1], run.evaluations

    print(f"Andrews' squeezer to {TARGET:g} relative in q(0.03) (goal ≤ 50 ms):")
    figures = {
        "squeezer_simulate": scan("feeder.chain.simulate (DOP853)", ours, q_end),
        "squeezer_lean": scan(
            "lean constraintDynamics + solve_ivp", lambda r: lean_run(chain, q0, r)[:2], q_end
        ),
    }
    wall = figures["squeezer_simulate"].get("ms", float("inf"))
    print(f"  simulate: {wall:.1f} ms (goal ≤ 50 ms): {'PASS' if wall <= 50.0 else 'MISS'}")
    print("one right-hand side, in bare constraintDynamics calls at the same state:")
    v = Partition(chain, spec.independent).velocity(q0, np.array([10.0]))
    ratios = {"squeezer": rhs_ratio("Andrews' squeezer (spring, moment)", dyn, q0, v)}
    _, _, lean = lean_run(chain, q0, 1e-3)
    lean_cost = rhs_time(lean, np.concatenate([q0, v]))
    ratios["squeezer_lean"] = lean_cost / bare_call_time(chain, q0, v)
    print(f"  {'lean reference on the squeezer':34s} {ratios['squeezer_lean']:5.2f} calls")
    four_bar = load_closed_chain(
        EXAMPLES / "four_bar" / "four_bar.urdf", [Closure("coupler_tip", "rocker_tip", "revolute")]
    )
    partition = partition_four_bar = Partition(four_bar, ["crank_joint"])
    q = partition.mount(np.zeros(3))
    ratios["four_bar"] = rhs_ratio(
        "four-bar", ChainDynamics(four_bar, ["crank_joint"]), q,
        partition.velocity(q, np.array([3.0])),
    )  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cassie_spec = read_spec(EXAMPLES / "cad" / "cassie_like" / "robot.yaml")
        cassie = load_mechanism(cassie_spec)
    partition = Partition(cassie, cassie_spec.independent)
    q = partition.mount(pin.neutral(cassie.model))
    speeds = np.full(len(cassie_spec.independent), 0.5)
    ratios["cassie_like"] = rhs_ratio(
        "Cassie-like leg", ChainDynamics(cassie, cassie_spec.actuated), q,
        partition.velocity(q, speeds),
    )  # fmt: skip
    figures["rhs_calls"] = ratios
    print("one right-hand side on a moving base, in standing ones:")
    terrain = BaseMotion((Terrain(),))
    q = partition_four_bar.mount(np.zeros(3))
    v = partition_four_bar.velocity(q, np.array([3.0]))
    figures["moving_base_rhs"] = base_ratio(
        "four-bar on a terrain ride", ChainDynamics(four_bar, ["crank_joint"]),
        ChainDynamics(four_bar, ["crank_joint"], base=terrain), q, v,
    )  # fmt: skip
    if args.json:
        Path(args.json).write_text(json.dumps(figures, indent=2) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
