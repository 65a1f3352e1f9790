"""Hybrid runs on a moving base (feeder.chain.hybrid_run with ``dyn.base``): the rod between two
balls on a driven carriage (tests/data/hybrid/ball_rod.urdf, the fixture of test_hybrid.py), its
spin a pendulum on a slider, on a hull pitched on a slope that heaves and surges. Checked against
the pendulum's hand-written equation in the base's moving axes integrated independently by
SciPy, the slider's force against its hand formula, the start at rest against the tilted
gravity's closed form, and a base at rest against the standing run bit for bit.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest
from scipy.integrate import solve_ivp

from feeder.chain import (
    BaseMotion,
    ChainDynamics,
    Partition,
    hybrid_run,
    load_mechanism,
    read_spec,
)
from feeder.chain.dynamics.forward_base import MovingBase
from feeder.chain.model.profiles import Slope

from ...conftest import constrained_data
from .test_forward_base import Harmonic
from .test_hybrid import CARRIAGE, DATA, IZZ, MASS, OFFSET, TILT, G, carriage

PITCH = 0.1
"""The slope's pitch [rad] (nose down): gravity in the model's moving axes (x forward, y up) is
g (sin β, −cos β, 0)."""

HEAVE, HEAVE_RATE = 0.02, 10.0
"""The hull's heave A cos Ωt [m, rad/s] (level vertical): its acceleration −A Ω² cos Ωt peaks at
2 m/s²."""

SURGE, SURGE_RATE = 0.01, 7.0
"""The hull's surge A cos Ωt [m, rad/s] (level forward): acceleration peaks at 0.49 m/s²."""

TIGHT = dict(rtol=1e-12, atol=1e-14)
"""Both integrations near round-off: their difference is the error of the hybrid run's (steps
projected onto the loop and the table, Baumgarte's terms); measured 1e-10 rad and 1.2e-9 rad/s
over 351 steps, under the bound 1e-8 of the closed-form checks (the issue's)."""


def hull() -> BaseMotion:
    return BaseMotion(
        (Slope(pitch=PITCH), Harmonic(2, HEAVE, HEAVE_RATE), Harmonic(0, SURGE, SURGE_RATE))
    )


def field(t):
    """The specific force f = g − a_base [m/s²] in the model's moving axes (x, y), (2, N): the
    level gravity (0, −g) minus the hull's level acceleration (a_x, a_y), turned into the pitched
    axes (model x in the level axes (cos β, −sin β), model y (sin β, cos β))."""
    t = np.asarray(t, dtype=float)
    ax = -SURGE * SURGE_RATE**2 * np.cos(SURGE_RATE * t)
    ay = -HEAVE * HEAVE_RATE**2 * np.cos(HEAVE_RATE * t)
    fx, fy = -ax, -G - ay
    c, s = math.cos(PITCH), math.sin(PITCH)
    return np.array([fx * c - fy * s, fx * s + fy * c])


def pendulum(t: float, y: np.ndarray) -> list[float]:
    """(I + m e²) ψ̈ = m e (f_y sin ψ + (f_x − ẍ) cos ψ): the rod's spin ψ (its centre of
    gravity's angle from the model's −y towards +x) about the line through its balls (along z),
    in the specific force f of the hull (:func:`field`) and the carriage's ẍ along x."""
    psi, rate = y
    fx, fy = field(t)
    ddx = carriage(np.array(t))[2]
    inertia = IZZ + MASS * OFFSET**2
    return [rate, MASS * OFFSET * (fy * np.sin(psi) + (fx - ddx) * np.cos(psi)) / inertia]


def ball_rod(base: BaseMotion | None):
    spec = read_spec(DATA / "ball_rod.toml")
    chain = load_mechanism(spec)
    assembled = Partition(chain, spec.independent).mount(np.zeros(chain.model.nq))
    return chain, ChainDynamics(chain, spec.actuated, base=base), assembled


def run_on(base: BaseMotion | None, t: np.ndarray, **settings):
    chain, dyn, assembled = ball_rod(base)
    x, dx, ddx = carriage(t)
    return chain, hybrid_run(dyn, t, x[:, None], dx[:, None], ddx[:, None], assembled, **settings)


@pytest.fixture(scope="module")
def moving():
    return run_on(hull(), np.linspace(0.0, 2.0, 201), **TIGHT)


def test_the_rod_starts_at_rest_under_the_gravity_of_the_pitched_hull(moving):
    """At rest in g (sin β, −cos β): g sin(β − ψ) = 0, ψ = β; ball_rz = β − TILT (SciPy's root
    stops at a relative step of 1.5e-8: ~1e-9 rad). The hull's acceleration at t0 (2 m/s² of
    heave) does not enter the start."""
    chain, run = moving
    spin = chain.joint_slice("ball_rz").start
    assert abs(run.start[spin] - (PITCH - TILT)) <= 1e-8
    assert abs(run.v[0, spin]) <= 1e-12


def test_the_spin_and_the_slider_force_follow_the_hand_written_equations(moving):
    chain, run = moving
    spin = chain.joint_slice("ball_rz").start
    psi0 = run.q[0, spin] + TILT
    reference = solve_ivp(
        pendulum, (0.0, 2.0), [psi0, 0.0], method="DOP853", t_eval=run.t, **TIGHT
    )
    psi, rate = reference.y
    assert np.abs(run.q[:, spin] + TILT - psi).max() < 1e-8
    assert np.abs(run.v[:, spin] - rate).max() < 1e-8
    assert np.abs(run.travel[:, 0] - (psi - psi0)).max() < 1e-8
    assert np.abs(psi - psi0).max() > 0.5  # the hull and the carriage swing it far
    # F = (M + m)(ẍ − f_x) + m e (ψ̈ cos ψ − ψ̇² sin ψ): the x momentum rate of carriage and rod
    # in the moving axes, less the specific force's pull on their mass (the prismatic joint's
    # reaction has no x component). Its error: the state's (1e-8) times its sensitivity,
    # m e (|ψ̈| + ψ̇² + ...) × (1 + m e |f| / I) ~ 1e2 N per rad (test_hybrid.py): 1e-6 N
    # (measured 3e-10 N of 12.7 N).
    accel = np.array([pendulum(s, y)[1] for s, y in zip(run.t, reference.y.T, strict=True)])
    ddx = carriage(run.t)[2]
    fx = field(run.t)[0]
    force = (CARRIAGE + MASS) * (ddx - fx) + MASS * OFFSET * (
        accel * np.cos(psi) - rate**2 * np.sin(psi)
    )
    assert np.abs(run.loads.actuators["slider"] - force).max() < 1e-6
    assert np.abs((CARRIAGE + MASS) * fx).max() > 2.0  # the hull's share is not negligible


def test_the_slider_force_found_drives_constraint_dynamics_on_the_hull_to_the_run(moving):
    """Pinocchio's constraintDynamics with the moving root's bias (MovingBase.bias, as the forward
    runs take it), the loop closed and the slider driven by the force found, the rod free: the
    run's accelerations (both solve M q̈ + b_B = τ + Jᵀλ; the proximal solver's accuracy 1e-13
    on the constraint accelerations, the KKT system's condition ~1e4: 1e-9 of the largest;
    measured 4e-14 m/s² of 68, 13 m/s² off without the moving root's bias)."""
    chain, run = moving
    model = chain.model
    data, datas = constrained_data(chain)
    settings = pin.ProximalSettings(1e-14, 1e-10, 1000)
    root = MovingBase(model, hull())
    slider = chain.joint_slice("slider").start
    for k in range(0, run.t.size, 20):
        tau = np.zeros(model.nv)
        tau[slider] = run.loads.actuators["slider"][k]
        tau += root.bias(data, run.t[k], run.q[k], run.v[k])[0]
        ddq = pin.constraintDynamics(
            model, data, run.q[k], run.v[k], tau, chain.constraint_models, datas, settings
        )
        np.testing.assert_allclose(ddq, run.a[k], rtol=0, atol=1e-9 * np.abs(run.a).max())


def test_a_base_at_rest_runs_as_before():
    """A BaseMotion without profiles is a base at rest (dyn.base None): the standing arithmetic,
    bit for bit. A level slope takes the moving root's path (b − (b − b_B)): the same run to
    round-off of the bias, carried by the integration (measured 1.4e-15 rad, 5e-15 N of 9 N)."""
    t = np.linspace(0.0, 0.5, 51)
    _, standing = run_on(None, t)
    _, empty = run_on(BaseMotion(()), t)
    for name in ("q", "v", "a", "travel", "residual", "start"):
        assert np.array_equal(getattr(empty, name), getattr(standing, name)), name
    assert np.array_equal(empty.loads.actuators["slider"], standing.loads.actuators["slider"])
    _, level = run_on(BaseMotion((Slope(),)), t)
    assert level.steps == standing.steps
    np.testing.assert_allclose(level.q, standing.q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(
        level.loads.actuators["slider"], standing.loads.actuators["slider"], rtol=0, atol=1e-11
    )
    assert standing.gravity is None and empty.gravity is None
    np.testing.assert_array_equal(level.gravity, [0.0, -G, 0.0])


def test_the_summary_says_the_gravity_of_the_start(moving):
    chain, run = moving
    text = "\n".join(run.text(chain.model))
    g = [G * math.sin(PITCH), -G * math.cos(PITCH), 0.0]
    np.testing.assert_allclose(run.gravity, g, rtol=0, atol=1e-14)  # one rotation's round-off
    weighed = ", ".join(f"{value:.4g}" for value in g)
    assert f"under the gravity the moving base sees there, [{weighed}] m/s² in its axes" in text


def test_the_base_is_computed_once_a_step(monkeypatch):
    """As a forward run's (test_forward_base.py): the base's motion at a step's stage times in
    one pass, a time alone only in a rejected step or a restart after a projection (a fifth of
    this run's evaluations at the default rtol 1e-8: 6 of its 36 steps are first rejected, and
    every step restarts; a third at rtol 1e-12; all of them without the prediction)."""
    from feeder.chain.dynamics import forward_base

    singles = []
    states = forward_base.MovingBase.states

    def counted(self, times):
        singles.extend(np.atleast_1d(times)[: np.size(times) == 1])
        return states(self, times)

    monkeypatch.setattr(forward_base.MovingBase, "states", counted)
    _, run = run_on(hull(), np.linspace(0.0, 0.5, 51))
    assert len(singles) < 0.3 * run.evaluations, (len(singles), run.evaluations)
