"""Hybrid runs (feeder.chain.hybrid_run): the actuated joints follow a motion, the freedoms they
leave free and that move mass are integrated. Checked on a rod between two ball joints on a
driven carriage (tests/data/hybrid/ball_rod.urdf), whose spin about the line through its balls
is a pendulum on a slider with a closed form, against that form integrated independently; against
Pinocchio's constraintDynamics driven by the loads found; and on the mechanisms whose idle
motions move no mass (they stay on the minimum-norm path: no hybrid run).
"""

from __future__ import annotations

import warnings

import numpy as np
import pinocchio as pin
import pytest
from scipy.integrate import solve_ivp

from feeder.chain import (
    ChainDynamics,
    Partition,
    hybrid_run,
    load_closed_chain,
    load_mechanism,
    read_spec,
)
from feeder.chain.assembly.newton import newton
from feeder.chain.assembly.rank import locked_motions, rank_tolerance
from feeder.chain.dynamics.forward import ATOL, RTOL
from feeder.chain.dynamics.free_freedoms import free_freedoms
from feeder.exceptions import FeederWarning, InputError

from ...conftest import REPO, constrained_data

DATA = REPO / "tests" / "data" / "hybrid"

MASS, CARRIAGE, OFFSET, IZZ, TILT, G = 0.5, 2.0, 0.05, 0.002, 0.3, 9.81
"""The rod's mass [kg], the carriage's [kg], the rod's centre of gravity's distance from the
line through its balls [m], the rod's inertia about its centre of gravity along that line
[kg·m²], the angle [rad] of its centre of gravity from the rod frame's −y axis, gravity [m/s²]
(ball_rod.urdf)."""

AMPLITUDE, OMEGA = 0.1, 2.0 * np.pi
"""The carriage's motion x = A sin(ω t) [m, rad/s]."""


def carriage(t: np.ndarray):
    x = AMPLITUDE * np.sin(OMEGA * t)
    return x, AMPLITUDE * OMEGA * np.cos(OMEGA * t), -(OMEGA**2) * x


def pendulum(t: float, y: np.ndarray) -> list[float]:
    """ψ̈ = −m e (g sin ψ + ẍ cos ψ) / (I_zz + m e²): the rod's spin ψ (its centre of gravity's
    angle from the downward vertical) about the line through its balls, which the carriage
    carries along x (gravity −y, the line along z)."""
    psi, rate = y
    inertia = IZZ + MASS * OFFSET**2
    ddx = carriage(np.array(t))[2]
    return [rate, -MASS * OFFSET * (G * np.sin(psi) + ddx * np.cos(psi)) / inertia]


@pytest.fixture(scope="module")
def ball_rod():
    spec = read_spec(DATA / "ball_rod.toml")
    chain = load_mechanism(spec)
    dyn = ChainDynamics(chain, spec.actuated)
    assembled = Partition(chain, spec.independent).mount(np.zeros(chain.model.nq))
    t = np.linspace(0.0, 2.0, 201)
    x, dx, ddx = carriage(t)
    run = hybrid_run(dyn, t, x[:, None], dx[:, None], ddx[:, None], assembled)
    return chain, dyn, run


def test_the_spinning_rod_is_the_free_freedom_and_starts_at_rest(ball_rod):
    chain, _, run = ball_rod
    assert run.free.joints == (("ball_rz",),)
    spin = chain.joint_slice("ball_rz").start
    # At rest its centre of gravity hangs below the line: ball_rz = −TILT. SciPy's root stops at
    # a relative step of 1.5e-8 of |s| ≈ 0.3: 4.5e-9 rad.
    assert abs(run.start[spin] + TILT) <= 1e-8
    assert abs(run.v[0, spin]) <= 1e-12  # rates 0: the projection keeps them


def test_the_spin_and_the_drive_force_follow_the_closed_form(ball_rod):
    chain, _, run = ball_rod
    spin = chain.joint_slice("ball_rz").start
    psi0 = run.q[0, spin] + TILT
    reference = solve_ivp(
        pendulum, (0.0, 2.0), [psi0, 0.0], method="DOP853", rtol=1e-12, atol=1e-14,
        t_eval=run.t,
    )  # fmt: skip
    psi, rate = reference.y
    accel = np.array([pendulum(s, y)[1] for s, y in zip(run.t, reference.y.T, strict=True)])
    # The run's global error: at most its steps' local errors summed, each ≤ rtol |y| + atol
    # (|ψ| ≤ 2 rad); the reference's, at rtol 1e-12, is 1e4 times smaller. Measured 8e-10.
    bound = run.steps * (RTOL * 2.0 + ATOL)
    np.testing.assert_allclose(run.q[:, spin] + TILT, psi, rtol=0, atol=bound)
    np.testing.assert_allclose(run.travel[:, 0], psi - psi0, rtol=0, atol=bound)
    np.testing.assert_allclose(run.v[:, spin], rate, rtol=0, atol=bound * 10.0)
    assert run.excursion()[0] == pytest.approx(np.abs(psi - psi0).max(), abs=bound)
    # F = (M + m) ẍ + m e (ψ̈ cos ψ − ψ̇² sin ψ): its sensitivity to ψ, ψ̇, ψ̈ is below
    # m e (|ψ̈| + ψ̇² + 2 |ψ̇| + 1) × (1 + m e (g + |ẍ|max) / I) per unit error of ψ (the error of
    # ψ̈ follows the pendulum's equation); ψ̇'s error is ten times ψ's at most (above).
    ddx = carriage(run.t)[2]
    force = (CARRIAGE + MASS) * ddx + MASS * OFFSET * (accel * np.cos(psi) - rate**2 * np.sin(psi))
    inertia = IZZ + MASS * OFFSET**2
    sensitivity = MASS * OFFSET * (np.abs(accel).max() + rate.max() ** 2 + 20 * np.abs(rate).max())
    sensitivity *= 1.0 + MASS * OFFSET * (G + np.abs(ddx).max()) / inertia
    np.testing.assert_allclose(
        run.loads.actuators["slider"], force, rtol=0, atol=10.0 * sensitivity * bound
    )
    assert np.abs(force).max() > 5.0  # the swing matters: not a vanishing force


def test_the_drive_force_found_drives_constraint_dynamics_to_the_run(ball_rod):
    """Pinocchio's constraintDynamics, the loop closed and the slider driven by the force found,
    the rod free: the same accelerations (both solve the same equations; the proximal solver's
    accuracy is 1e-13 on the constraint accelerations and the KKT system's condition ~1e4 here:
    1e-9 of the largest acceleration leaves room)."""
    chain, dyn, run = ball_rod
    model = chain.model
    data, datas = constrained_data(chain)
    settings = pin.ProximalSettings(1e-14, 1e-10, 1000)
    slider = chain.joint_slice("slider").start
    for k in range(0, run.t.size, 20):
        tau = np.zeros(model.nv)
        tau[slider] = run.loads.actuators["slider"][k]
        ddq = pin.constraintDynamics(
            model, data, run.q[k], run.v[k], tau, chain.constraint_models, datas, settings
        )
        np.testing.assert_allclose(ddq, run.a[k], rtol=0, atol=1e-9 * np.abs(run.a).max())


def test_the_run_keeps_the_table_and_the_loop(ball_rod):
    chain, _, run = ball_rod
    slider = chain.joint_slice("slider").start
    x, dx, ddx = carriage(run.t)
    # every sample projected onto the table and the loop (Newton stops at 1e-13 m)
    np.testing.assert_allclose(run.q[:, slider], x, rtol=0, atol=1e-12)
    np.testing.assert_allclose(run.v[:, slider], dx, rtol=0, atol=1e-12)
    # the accelerations: the table's (Baumgarte's terms vanish on a projected sample)
    np.testing.assert_allclose(run.a[:, slider], ddx, rtol=0, atol=1e-8)
    assert max(np.abs(chain.residual(q)).max() for q in run.q) <= 1e-12
    assert run.residual.max() <= 1e-8  # the drift before projection: tolerance 1e-10 + a step


@pytest.mark.parametrize("name", ["5bar_linkage", "robot_delta", "cassie_like", "battobot_6d"])
def test_idle_motions_that_move_no_point_are_not_free_freedoms(name):
    """The CAD exports' idle motions (rods spinning about their own axis, coaxial hinges) move no
    point: no free freedom, so ``feeder analyze`` keeps them on the minimum-norm path and a
    hybrid run is refused."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FeederWarning)  # the 5-bar's 654-tonne sphere
        spec = read_spec(REPO / "examples" / "cad" / name / "robot.yaml")
        chain = load_mechanism(spec)
    dyn = ChainDynamics(chain, spec.actuated)
    assembled = Partition(chain, spec.independent).mount(pin.neutral(chain.model))
    assert len(free_freedoms(dyn, assembled)) == 0
    if name == "5bar_linkage":
        x = np.tile(Partition(chain, spec.actuated).independent_values(assembled), (2, 1))
        with pytest.raises(InputError, match="no freedom that carries mass"):
            hybrid_run(dyn, np.array([0.0, 0.1]), x, 0 * x, 0 * x, assembled)


def test_bad_arguments_are_refused(ball_rod):
    chain, dyn, _ = ball_rod
    q = np.zeros(chain.model.nq)
    x = np.zeros((3, 1))
    with pytest.raises(InputError, match="increasing"):
        hybrid_run(dyn, np.array([0.0, 0.0, 1.0]), x, x, x, q)
    with pytest.raises(InputError, match="one row per time"):
        hybrid_run(dyn, np.array([0.0, 1.0]), x, x, x, q)
    with pytest.raises(InputError, match="method"):
        hybrid_run(dyn, np.array([0.0, 0.5, 1.0]), x, x, x, q, method="Euler")


def test_a_dead_centre_has_no_free_freedom():
    """The example four-bar driven from its rocker, at its folded dead centre (crank and coupler
    aligned): with the rocker locked the crank may still turn there (to first order), moving
    mass, but the rocker cannot move freely: a singular pose, not a free freedom (the kinematics
    refuse it as before)."""
    spec = read_spec(REPO / "examples" / "four_bar" / "closures.toml")
    chain = load_mechanism(spec)
    dyn = ChainDynamics(chain, ["rocker_joint"])
    names = ("crank_joint", "coupler_joint", "rocker_joint")
    crank, coupler, rocker = (chain.joint_slice(name).start for name in names)
    folded = np.zeros(3)
    folded[[crank, coupler, rocker]] = 4.0, np.pi, 2.2  # coupler folded back onto the crank
    q, gap = newton(chain, folded, np.array([crank, rocker]))
    assert gap <= 1e-13
    # the rocker at the dead centre, cos φ = (0.08² − 0.1² − 0.08²)/(2 · 0.1 · 0.08)
    assert q[rocker] == pytest.approx(np.arccos(-0.625), abs=1e-12)
    jac = chain.jacobian(q)
    _, locked = locked_motions(jac, dyn.partition.dependent, rank_tolerance(jac))
    assert locked.shape[0] == 1 and locked[0, crank] != 0.0  # the crank turns, a mass moves
    assert len(free_freedoms(dyn, q)) == 0


def test_a_continuous_drive_turning_twice_is_followed_as_a_revolute_one(tmp_path):
    """The carriage turned about the vertical instead of slid, two turns in 2 s: written as a URDF
    ``continuous`` joint (cos, sin: its gap to the table wraps at ±π) it gives the rod the same
    swing and needs the same torque as a revolute joint of wide limits."""
    text = (DATA / "ball_rod.urdf").read_text(encoding="utf-8")
    slider = text[text.index('<joint name="slider"') : text.index("</joint>") + len("</joint>")]
    runs = {}
    for kind in ("revolute", "continuous"):
        turning = (
            slider.replace('type="prismatic"', f'type="{kind}"')
            .replace('<axis xyz="1 0 0"/>', '<axis xyz="0 1 0"/>')
            .replace('lower="-1" upper="1"', 'lower="-20" upper="20"')
        )
        (tmp_path / "ball_rod.urdf").write_text(text.replace(slider, turning), encoding="utf-8")
        (tmp_path / "ball_rod.toml").write_text((DATA / "ball_rod.toml").read_text())
        spec = read_spec(tmp_path / "ball_rod.toml")
        chain = load_mechanism(spec)
        start = Partition(chain, spec.independent).mount(pin.neutral(chain.model))
        t = np.linspace(0.0, 2.0, 101)
        angle = 2.0 * np.pi * t - 0.5 * np.sin(np.pi * t)  # [rad]: past ±π three times
        rate = 2.0 * np.pi - 0.5 * np.pi * np.cos(np.pi * t)
        accel = 0.5 * np.pi**2 * np.sin(np.pi * t)
        run = hybrid_run(
            ChainDynamics(chain, spec.actuated), t, angle[:, None], rate[:, None],
            accel[:, None], start,
        )  # fmt: skip
        runs[kind] = (chain, run)
    (chain_r, revolute), (chain_c, continuous) = runs["revolute"], runs["continuous"]
    assert chain_c.model.nq == chain_r.model.nq + 1
    spin_r, spin_c = (
        c.model.joints[c.model.getJointId("ball_rz")].idx_q for c in (chain_r, chain_c)
    )
    # two runs of one motion in other coordinates: each within its global error bound of the
    # exact one (steps × (rtol |y| + atol), |y| ≤ 13 rad: the turning angle)
    bound = (revolute.steps + continuous.steps) * (RTOL * 13.0 + ATOL)
    np.testing.assert_allclose(continuous.q[:, spin_c], revolute.q[:, spin_r], atol=bound)
    np.testing.assert_allclose(continuous.travel, revolute.travel, atol=bound)
    # the torque: a smooth function of the state, its relative error the state's (measured: 9e-11
    # rad and 3e-11 N·m of 0.7 apart)
    torque = revolute.loads.actuators["slider"]
    np.testing.assert_allclose(
        continuous.loads.actuators["slider"], torque, atol=bound * np.abs(torque).max()
    )
    assert revolute.excursion()[0] > 0.01  # the turning swings the rod


def test_a_rod_hung_from_one_ball_on_the_carriage_swings_in_three_freedoms():
    """The rod without its second ball (no closure): three free freedoms (the ball's three
    revolutes), coming to rest hanging straight down (gravity −z, the model's), where every
    generalized force vanishes (the loads' consistency check is relative to the joints'
    wrenches there, not to their sum, round-off). The slider's force is the whole mechanism's
    horizontal momentum rate: (carriage + rod mass) × its centre of gravity's acceleration,
    from Pinocchio's centerOfMass (round-off: 1e-12 of the force's scale)."""
    chain = load_closed_chain(DATA / "ball_rod.urdf", [])
    model = chain.model
    t = np.linspace(0.0, 0.5, 51)
    x, dx, ddx = carriage(t)
    run = hybrid_run(
        ChainDynamics(chain, ["slider"]), t, x[:, None], dx[:, None], ddx[:, None],
        np.zeros(model.nq),
    )  # fmt: skip
    assert sorted(name for joints in run.free.joints for name in joints) == [
        "ball_rx", "ball_ry", "ball_rz",
    ]  # fmt: skip
    data = model.createData()
    pin.forwardKinematics(model, data, run.start)
    rod = model.getJointId("ball_rz")
    centre = data.oMi[rod].act(model.inertias[rod].lever) - data.oMi[rod].translation
    np.testing.assert_allclose(centre / np.linalg.norm(centre), [0, 0, -1], atol=1e-8)
    assert np.all(np.abs(run.start[1:]) <= np.pi)  # angles wrapped
    total = sum(inertia.mass for inertia in model.inertias)
    rate = []
    for state in zip(run.q, run.v, run.a, strict=True):
        pin.centerOfMass(model, data, *state)
        rate.append(total * data.acom[0][0])
    force = run.loads.actuators["slider"]
    scale = total * np.abs(ddx).max()  # [N]: round-off ~1e-16 of it (measured 2e-15 N of 9 N)
    np.testing.assert_allclose(force, rate, rtol=0, atol=1e-12 * scale)
    assert np.abs(force).max() > 1.0  # the carriage's 3.9 m/s² on 2.5 kg
