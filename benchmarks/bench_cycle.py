"""Time one loading cycle's dynamics: Pinocchio inverse dynamics and reactions, a forward run,
and the hand-derived Lagrange equations' closed form.

Each Pinocchio figure is also given as a multiple of one bare ``constraintDynamics`` call on the
same model, measured in the same run (so the ratios survive a noisy machine):

* inverse: :func:`feeder.dynamics.actuator_loads` + :func:`feeder.dynamics.joint_reactions`
  over all samples, per sample (target ≤ 3 calls' worth);
* forward: :func:`feeder.dynamics.simulate` driven by the cycle's piston force and forearm
  moment at the sample rate, per step (target ≤ 6 calls' worth; ABM5 PECE makes two calls per
  step, the RK4 starters four);
* Lagrange: :func:`feeder.paper.inverse_dynamics` (closed form, all samples at once) for
  the whole cycle, as a fraction of the Pinocchio loads + pin force path above (target < 1/10)
  and of loads + all reactions, with the largest differences of the loads.

Run: ``python benchmarks/bench_cycle.py [elevation_deg]`` (default −4°).
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np
import pinocchio as pin

from feeder import feeding_cycle, load_feeder
from feeder.dynamics import (
    FeederDynamics,
    ForceRule,
    actuator_loads,
    check_motion,
    joint_reactions,
    simulate,
)
from feeder.paper import inverse_dynamics as lagrange_loads

REPEATS = 7
LAGRANGE_CALLS = 20
"""Calls per timing of the Lagrange cycle (~0.5 ms each: one call alone is near timer noise)."""


def best_time(function, repeats: int = REPEATS, calls: int = 1) -> float:
    """Smallest wall time [s] of one call, over ``repeats`` timings of ``calls`` calls each."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(calls):
            function()
        times.append((time.perf_counter() - start) / calls)
    return min(times)


def main(argv: list[str] | None = None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    elevation = math.radians(float(argv[0])) if argv else math.radians(-4.0)
    feeder = load_feeder("projectile")
    kin = feeding_cycle(feeder, elevation)
    dyn = FeederDynamics(feeder)
    n = kin.t.size
    motion = check_motion(dyn, kin.q, kin.v, kin.a, kin.gripped)

    loads = actuator_loads(dyn, motion)
    case = dyn.cases[1]
    q, v, tau = (dyn.to_pinocchio(x) for x in (kin.q, kin.v, loads.generalized_forces()))

    def bare_calls() -> None:
        for k in range(n):
            pin.constraintDynamics(
                case.model,
                case.data,
                q[k],
                v[k],
                tau[k],
                case.constraint_models,
                case.constraint_datas,
                case.prox,
            )

    def inverse() -> None:
        joint_reactions(dyn, actuator_loads(dyn, motion))

    rule = ForceRule(kin.t, kin.stage, kin.gripped, loads.piston_force, loads.forearm_torque)

    def forward():
        return simulate(dyn, rule, kin.q[0], kin.v[0])

    call = best_time(bare_calls) / n
    t_loads = best_time(lambda: actuator_loads(dyn, motion)) / n
    t_reactions = best_time(lambda: joint_reactions(dyn, loads)) / n
    t_inverse = best_time(inverse) / n
    t_forward = best_time(forward) / (n - 1)
    result = forward()
    tracking = abs(result.q - kin.q).max(axis=0)
    hand = (feeder.params, kin.q, kin.v, kin.a, kin.gripped)
    t_lagrange = best_time(lambda: lagrange_loads(*hand), calls=LAGRANGE_CALLS)
    lagrange = lagrange_loads(*hand)
    differences = {
        "F": (lagrange.piston_force, loads.piston_force, "N"),
        "τ4": (lagrange.forearm_torque, loads.forearm_torque, "N·m"),
        "λ1": (lagrange.lambdas[:, 0], -loads.closure_force[:, 0], "N"),
        "λ2": (lagrange.lambdas[:, 1], -loads.closure_force[:, 1], "N"),
    }

    print(f"cycle at ε = {math.degrees(elevation):g}°: {n} samples at {kin.spec.rate:g} Hz")
    print(f"bare constraintDynamics call      {call * 1e6:8.2f} µs")
    print(
        f"inverse dynamics + all reactions  {t_inverse * 1e6:8.2f} µs/sample "
        f"({1 / t_inverse:9.0f} samples/s) = {t_inverse / call:5.2f} calls (target ≤ 3)"
    )
    print(
        f"  of which actuator loads + pin   {t_loads * 1e6:8.2f} µs/sample "
        f"= {t_loads / call:5.2f} calls"
    )
    print(
        f"  of which joint reactions, grip  {t_reactions * 1e6:8.2f} µs/sample "
        f"= {t_reactions / call:5.2f} calls"
    )
    print(
        f"forward simulation (force rule)   {t_forward * 1e6:8.2f} µs/step   "
        f"({1 / t_forward:9.0f} steps/s)   = {t_forward / call:5.2f} calls (target ≤ 6)"
    )
    print(
        f"forward accuracy: |Δφ3| ≤ {tracking[2]:.2e} rad, |Δφ4| ≤ {tracking[3]:.2e} rad, "
        f"pin gap ≤ {result.closure_residual.max():.2e} m"
    )
    print(
        f"Lagrange closed form, whole cycle {t_lagrange * 1e3:8.3f} ms "
        f"({t_lagrange / n * 1e6:.3f} µs/sample = {t_lagrange / n / call:5.3f} calls)"
    )
    print(
        f"  vs Pinocchio loads + pin        {t_loads * n * 1e3:8.3f} ms: "
        f"ratio {t_lagrange / (t_loads * n):6.4f} (target < 0.1)"
    )
    print(
        f"  vs loads + all reactions        {t_inverse * n * 1e3:8.3f} ms: "
        f"ratio {t_lagrange / (t_inverse * n):6.4f}"
    )
    print(
        "  max |Lagrange − Pinocchio|: "
        + ", ".join(
            f"{name} {np.abs(mine - theirs).max():.1e} {unit} "
            f"of peak {np.abs(theirs).max():.4g} {unit}"
            for name, (mine, theirs, unit) in differences.items()
        )
    )


if __name__ == "__main__":
    main()
