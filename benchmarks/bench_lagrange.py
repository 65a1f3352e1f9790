"""Time a whole cycle's actuator loads: hand-derived Lagrange equations vs a Pinocchio loop.

Lagrange: :func:`feeder.lagrange.lagrange_cycle_loads`, closed-form and vectorised over all
samples. Pinocchio: the straightforward per-sample inverse dynamics of the closed chain,
crba + nonLinearEffects + constraint Jacobian + a least-squares solve of
M a + b = S u + Jᵀ λ_c for the two actuator loads u and the pin force λ_c. Both run on the
same cycle; the script prints the timings, their ratio and the largest load difference.

Run: ``python benchmarks/bench_lagrange.py [elevation_deg]`` (default −4°).
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np
import pinocchio as pin

from feeder import feeding_cycle, load_feeder
from feeder.lagrange import lagrange_cycle_loads

REPEATS = 5


def pinocchio_models(feeder) -> dict[int, pin.Model]:
    """The feeder's model with (1) and without (0) the payload merged into the forearm."""
    empty = pin.Model(feeder.model)
    forearm = empty.getJointId("forearm_joint")
    frame = empty.frames[empty.getFrameId("projectile")]
    payload = feeder.params.payload
    inertia = pin.Inertia(payload.mass, np.zeros(3), np.diag(payload.moments))
    empty.inertias[forearm] = empty.inertias[forearm] - frame.placement.act(inertia)
    return {0: empty, 1: feeder.model}


def pinocchio_cycle_loads(feeder, cycle, models) -> np.ndarray:
    """Piston force [N] and forearm torque [N·m] per sample, (N, 2), by the Pinocchio loop."""
    datas = {k: m.createData() for k, m in models.items()}
    cmodels = feeder.chain.constraint_models
    cdatas = {k: pin.StdVec_RigidConstraintData() for k in models}
    for k in models:
        cdatas[k].append(cmodels[0].createData())
    actuated = [models[1].joints[models[1].getJointId(n)].idx_v
                for n in ("piston_joint", "forearm_joint")]
    q, v, a = (feeder.to_pinocchio(x) for x in (cycle.q, cycle.v, cycle.a))
    loads = np.empty((cycle.t.size, 2))
    for i, held in enumerate(cycle.payload):
        model, data, cdata = models[held], datas[held], cdatas[held]
        mass = pin.crba(model, data, q[i])
        bias = pin.nonLinearEffects(model, data, q[i], v[i])
        pin.computeJointJacobians(model, data, q[i])
        cmodels[0].calc(model, data, cdata[0])
        jac = pin.getConstraintsJacobian(model, data, cmodels, cdata)
        system = np.hstack([np.eye(model.nv)[:, actuated], jac.T])
        loads[i] = np.linalg.lstsq(system, mass @ a[i] + bias, rcond=None)[0][:2]
    return loads


def best_time(function, repeats: int = REPEATS) -> float:
    """Smallest wall time [s] of ``repeats`` calls."""
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def main(argv: list[str] | None = None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    elevation = math.radians(float(argv[0])) if argv else math.radians(-4.0)
    feeder = load_feeder("projectile")
    cycle = feeding_cycle(feeder, elevation)
    models = pinocchio_models(feeder)

    lagrange = lagrange_cycle_loads(feeder, cycle)
    reference = pinocchio_cycle_loads(feeder, cycle, models)
    t_lagrange = best_time(lambda: lagrange_cycle_loads(feeder, cycle))
    t_pinocchio = best_time(lambda: pinocchio_cycle_loads(feeder, cycle, models))

    diff_f = np.max(np.abs(lagrange.piston_force - reference[:, 0]))
    diff_t = np.max(np.abs(lagrange.forearm_torque - reference[:, 1]))
    print(f"cycle at {math.degrees(elevation):g}°: {cycle.t.size} samples, best of {REPEATS}")
    print(f"  Lagrange (vectorised):    {1e3 * t_lagrange:8.2f} ms")
    print(f"  Pinocchio per-sample loop: {1e3 * t_pinocchio:8.2f} ms")
    print(f"  ratio Lagrange/Pinocchio:  {t_lagrange / t_pinocchio:8.4f}")
    print(f"  max |Δ piston force|   = {diff_f:.3e} N "
          f"(peak {np.max(np.abs(reference[:, 0])):.1f} N)")
    print(f"  max |Δ forearm torque| = {diff_t:.3e} N·m "
          f"(peak {np.max(np.abs(reference[:, 1])):.2f} N·m)")


if __name__ == "__main__":
    main()
