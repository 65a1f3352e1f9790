"""``feeder analyze --motion`` on the three CAD exports of the public collection that were refused
at their first sample before hybrid runs ("… can still move … not an idle motion", issue 28):
the Talos-like leg, the Disney-like leg and the WL16-like Stewart leg (examples/cad). In each a
rod between two balls spins about the line through their centres while the motors are held, its
centre of gravity off that line: the run integrates those free freedoms.

The loads are checked independently of the load solve by the energy balance of the whole
mechanism: the motors' power integrated over the run equals the change of its kinetic plus
potential energy (Pinocchio's computeKineticEnergy, computePotentialEnergy). The closures and
ideal joints do no work, and the free freedoms, which no motor drives, can only take the energy
the motors give: a free freedom integrated off its equation of motion (or loads solved with a
force on it) breaks the balance. Short runs: the first 0.3 s of each shipped table.
"""

from __future__ import annotations

import warnings

import numpy as np
import pinocchio as pin
import pytest
from scipy.integrate import simpson, trapezoid

from feeder.chain.dynamics.forward import ATOL, RTOL
from feeder.exceptions import FeederWarning
from feeder.study.analyze import analyze, check_mechanism

from ..conftest import REPO

CAD = REPO / "examples" / "cad"

SPAN = 0.3
"""The part of each table run here [s]."""

FREE = {"talos_like": 1, "disney_like": 3, "wl16_like": 6}
"""Free freedoms of each at its assembled pose: Talos's rod between its ankle's two balls,
three of the Disney-like leg's rods, the WL16-like leg's six actuators (ball–prismatic–ball)."""

POSE = {"wl16_like": CAD / "wl16_like_pose.csv"}
"""The WL16-like leg's export hangs its lower rods upside down; from its zero pose the mount
reaches a collapsed, singular assembly (the foot in the hips' plane): the pose file picks the
branch with the foot below the hips (examples/cad/README.md)."""


def short_table(name: str, folder) -> object:
    """The first :data:`SPAN` seconds of the shipped motion table, in ``folder``."""
    lines = (CAD / f"{name}_motion.csv").read_text(encoding="utf-8").splitlines()
    t = np.array([float(line.split(",")[0]) for line in lines[1:]])
    path = folder / f"{name}_motion.csv"
    path.write_text("\n".join(lines[: 1 + np.sum(t <= SPAN + 1e-9)]) + "\n", encoding="utf-8")
    return path


@pytest.fixture(scope="module", params=sorted(FREE))
def held_out(request, tmp_path_factory):
    name = request.param
    motion = short_table(name, tmp_path_factory.mktemp(name))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FeederWarning)  # the exports' implausible inertias
        analysis = analyze(CAD / name / "robot.yaml", motion, pose=POSE.get(name))
    return name, analysis


def test_the_run_integrates_the_free_freedoms_and_names_them(held_out):
    name, analysis = held_out
    run = analysis.hybrid
    assert run is not None and len(run.free) == FREE[name]
    summary = analysis.summary()
    for number, joints in enumerate(run.free.joints, start=1):
        assert f"free freedom {number} moves {', '.join(joints)}" in summary
    # each free freedom is a spin between two balls: the joints of both ends move in it
    for joints in run.free.joints:
        assert len({joint.rsplit("_rev", 1)[0] for joint in joints}) >= 2
    assert run.excursion().max() > 1e-3  # gravity swings them: not a motion at rest
    for loads in analysis.loads.actuators.values():
        assert np.all(np.isfinite(loads))


def test_the_motors_power_equals_the_change_of_energy(held_out):
    """∫ Σ τ_i q̇_i dt = Δ(T + V) over the run, the motors' loads from the run's load solve, the
    energies from Pinocchio on the run's samples."""
    _, analysis = held_out
    run, model = analysis.hybrid, analysis.chain.model
    data = model.createData()
    energy, momentum, gravity = [], [], []
    for q, v in zip(run.q, run.v, strict=True):
        energy.append(pin.computeKineticEnergy(model, data, q, v))
        energy[-1] += pin.computePotentialEnergy(model, data, q)
        momentum.append(np.abs(pin.crba(model, data, q) @ v).sum())
        gravity.append(np.abs(pin.computeGeneralizedGravity(model, data, q)).sum())
    power = np.zeros(run.t.size)
    torque = np.zeros(run.t.size)
    for joint, load in analysis.loads.actuators.items():
        column = model.joints[model.getJointId(joint)].idx_v
        power += load * run.v[:, column]
        torque += np.abs(load)
    work = simpson(power, x=run.t)
    # Quadrature: Simpson's error is far below its difference to the trapezoid rule on samples
    # of a smooth power (the trapezoid's own error, O(h²) against O(h⁴)).
    quadrature = abs(work - trapezoid(power, x=run.t))
    # Integration: each state coordinate within the run's global bound δ = steps × (rtol |y| +
    # atol) (|y| ≤ 10: angles and rates), the rates within 10 δ (tests/chain/dynamics/
    # test_hybrid.py measures so); the energies' and the power's first-order changes.
    state = run.steps * (RTOL * 10.0 + ATOL)
    sensitivity = max(gravity) * state + max(momentum) * 10.0 * state
    drift = 2.0 * sensitivity + trapezoid(torque, x=run.t) * 10.0 * state
    change = energy[-1] - energy[0]
    # Measured: 1e-9 to 6e-9 J apart, of 0.02 to 0.4 J; the bound is 4e-4 to 2e-3 J.
    assert work == pytest.approx(change, rel=0, abs=quadrature + drift)
    assert abs(change) > 10.0 * (quadrature + drift)  # the motors do work: not 0 = 0


@pytest.mark.parametrize("name", sorted(FREE))
def test_check_names_the_free_freedoms(name):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FeederWarning)
        check = check_mechanism(CAD / name / "robot.yaml", pose=POSE.get(name))
    assert check.drives and len(check.free) == FREE[name]
    assert f"{FREE[name]} freedom(s) left free move mass" in check.text
