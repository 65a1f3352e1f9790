"""Forward runs on a moving base (feeder.chain.dynamics.forward_base) and the Controller hook.

Independent checks: a point pendulum on a heaving or rocking base against its hand-written
equation integrated by SciPy (the relative angle, the absolute energy and the base's work), the
parametric resonance of Mathieu's equation, MuJoCo's equations of the device on a hull with six
joints at every sample of a run, the inverse dynamics of the run's samples (the drives read
back), and a controller with a first-order lag against its hand-written ODE.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin
import pytest
from scipy.integrate import solve_ivp

from feeder.chain import BaseMotion, ChainDynamics, ClosedChain, simulate
from feeder.chain.dynamics import Controller
from feeder.chain.model.channels import Channels
from feeder.exceptions import InputError

G, LENGTH, MASS = 9.81, 0.5, 2.0
"""The pendulum: gravity [m/s²], length [m] and point mass [kg]."""

OMEGA0 = math.sqrt(G / LENGTH)
"""Its small-oscillation frequency [rad/s]."""

TIGHT = dict(rtol=1e-12, atol=1e-14)
"""Both integrations at tolerances near round-off: their difference is then the error of the
looser one, a few 1e-11 rad over the periods run (measured 1e-11 to 4e-11)."""

CLOSED_FORM = 1e-8
"""The brief's bound on the difference from the hand-written equation [rad, rad/s, J]."""


@dataclass(frozen=True)
class Harmonic:
    """A hull channel moving as A cos(Ωt): ``channel`` 0–5 (x, y, z in the vehicle axes, roll,
    pitch, yaw), amplitude A [m or rad], frequency Ω [rad/s]. A programmer's profile
    (``channels`` and ``describe``)."""

    channel: int
    amplitude: float
    frequency: float

    def channels(self, t: np.ndarray) -> Channels:
        out = [np.zeros((t.size, 6)) for _ in range(3)]
        w, a = self.frequency, self.amplitude
        out[0][:, self.channel] = a * np.cos(w * t)
        out[1][:, self.channel] = -a * w * np.sin(w * t)
        out[2][:, self.channel] = -a * w**2 * np.cos(w * t)
        return Channels(*out)

    def describe(self) -> str:
        return f"channel {self.channel}: {self.amplitude:g} cos({self.frequency:g} t)"


def pendulum() -> ClosedChain:
    """A point mass on a massless rod, hinged at the model's origin about the forward axis x;
    up is z; θ = 0 hangs down, θ > 0 swings it towards +y."""
    model = pin.Model()
    model.gravity = pin.Motion(np.array([0.0, 0.0, -G, 0.0, 0.0, 0.0]))
    joint = model.addJoint(0, pin.JointModelRX(), pin.SE3.Identity(), "swing")
    model.appendBodyToJoint(
        joint,
        pin.Inertia(MASS, np.array([0.0, 0.0, -LENGTH]), np.zeros((3, 3))),
        pin.SE3.Identity(),
    )
    return ClosedChain(model, [])


def heave(amplitude: float, frequency: float) -> BaseMotion:
    """The base heaving: its height −A cos Ωt, its upward acceleration a(t) = A Ω² cos Ωt."""
    return BaseMotion((Harmonic(2, -amplitude, frequency),))


def heaving_reference(t, y0, amplitude, frequency):
    """The hand ODE of the heaving pendulum, θ̈ = −(g + a(t))/L sin θ, with the base's power
    P_B = ż · m (z̈_G + g) (the support's vertical force on the pendulum times the pivot's
    velocity; z_G = z − L cos θ the mass's height), integrated with the state."""
    w, amp = frequency, amplitude

    def rhs(s, y):
        theta, rate, _ = y
        lift = amp * w**2 * math.cos(w * s)  # a(t)
        speed = amp * w * math.sin(w * s)  # ż, z = −A cos Ωt
        accel = -(G + lift) / LENGTH * math.sin(theta)
        height_accel = lift + LENGTH * (accel * math.sin(theta) + rate**2 * math.cos(theta))
        return [rate, accel, speed * MASS * (height_accel + G)]

    return solve_ivp(rhs, (t[0], t[-1]), [*y0, 0.0], t_eval=t, method="DOP853", **TIGHT).y


def heaving_energy(t, theta, rate, amplitude, frequency):
    """The absolute motion's kinetic and gravitational energy [J] of the heaving pendulum."""
    speed = amplitude * frequency * np.sin(frequency * t)
    height = -amplitude * np.cos(frequency * t) - LENGTH * np.cos(theta)
    vy, vz = LENGTH * rate * np.cos(theta), speed + LENGTH * rate * np.sin(theta)
    return 0.5 * MASS * (vy**2 + vz**2), MASS * G * height


def test_a_pendulum_on_a_heaving_base_follows_its_hand_written_equation():
    """The relative angle, the absolute energy, the base's work and the mount's vertical force
    of the heaving pendulum against :func:`heaving_reference` and the hand formulas."""
    amplitude, frequency = 0.03, 7.0  # a(t) peaks at 1.47 m/s², 0.15 g
    chain = pendulum()
    dyn = ChainDynamics(chain, [], base=heave(amplitude, frequency))
    t = np.linspace(0.0, 5.0, 501)  # 3.5 periods of the pendulum, 5.6 of the base
    run = simulate(dyn, t, np.array([0.4]), np.array([0.3]), **TIGHT)
    theta, rate, base_work = heaving_reference(t, [0.4, 0.3], amplitude, frequency)
    assert np.abs(run.q[:, 0] - theta).max() < CLOSED_FORM
    assert np.abs(run.v[:, 0] - rate).max() < CLOSED_FORM
    # the absolute energy and the base's work, by hand
    kinetic, potential = heaving_energy(t, theta, rate, amplitude, frequency)
    assert np.abs(run.kinetic - kinetic).max() < CLOSED_FORM
    assert np.abs(run.energy - (kinetic + potential)).max() < CLOSED_FORM
    assert np.abs(run.base_work - base_work).max() < CLOSED_FORM
    assert np.abs(run.base_work).max() > 0.1  # the base does work: the check is not empty
    assert np.abs(run.work).max() == 0.0  # nothing else does
    assert run.energy_error() < CLOSED_FORM
    # the mount's vertical force (base axes): m (z̈_G + g), z̈_G = a + L (θ̈ sin θ + θ̇² cos θ)
    # with the hand equation's θ̈; θ and θ̇ within 1e-8 move it by ~1e-6 N
    lift = amplitude * frequency**2 * np.cos(frequency * t)
    accel = -(G + lift) / LENGTH * np.sin(theta)
    vertical = MASS * (lift + LENGTH * (accel * np.sin(theta) + rate**2 * np.cos(theta)) + G)
    assert np.abs(run.loads.mount.force[:, 2] - vertical).max() < 1e-6 * MASS * G


def test_a_pendulum_on_a_rocking_base_follows_its_hand_written_equation():
    """The base rolls about the pendulum's own axis, φ = Φ cos Ωt: the absolute angle θ + φ
    obeys the standing pendulum's equation, θ̈ = −φ̈ − g/L sin(θ + φ)."""
    roll, frequency = 0.1, 5.0
    dyn = ChainDynamics(pendulum(), [], base=BaseMotion((Harmonic(3, roll, frequency),)))
    t = np.linspace(0.0, 5.0, 401)
    run = simulate(dyn, t, np.array([0.2]), np.array([0.0]), **TIGHT)

    def rhs(s, y):
        phi = roll * math.cos(frequency * s)
        phi_accel = -roll * frequency**2 * math.cos(frequency * s)
        return [y[1], -phi_accel - G / LENGTH * math.sin(y[0] + phi)]

    theta, rate = solve_ivp(rhs, (0.0, 5.0), [0.2, 0.0], t_eval=t, method="DOP853", **TIGHT).y
    assert np.abs(run.q[:, 0] - theta).max() < CLOSED_FORM
    assert np.abs(run.v[:, 0] - rate).max() < CLOSED_FORM
    # the absolute motion is the standing pendulum's at θ + φ: its energy by hand
    phi = roll * np.cos(frequency * t)
    phi_rate = -roll * frequency * np.sin(frequency * t)
    energy = 0.5 * MASS * (LENGTH * (rate + phi_rate)) ** 2 - MASS * G * LENGTH * np.cos(
        theta + phi
    )
    assert np.abs(run.energy - energy).max() < CLOSED_FORM
    assert run.energy_error() < CLOSED_FORM
    # the rocking base's work is the moment it applies times its rate (the mount's moment
    # about the pivot along x): W_B(t) = E(t) − E(0), nothing else acting
    np.testing.assert_allclose(run.base_work, energy - energy[0], rtol=0.0, atol=CLOSED_FORM)


def _growth(frequency: float) -> float:
    """Largest |θ| over 15 s of a pendulum started at 0.01 rad on a base heaving with a(t)
    peaking at 0.2 g, at the base frequency ``frequency`` [rad/s]."""
    amplitude = 0.2 * G / frequency**2
    dyn = ChainDynamics(pendulum(), [], base=heave(amplitude, frequency))
    run = simulate(dyn, np.linspace(0.0, 15.0, 751), np.array([0.01]), np.array([0.0]))
    return float(np.abs(run.q[:, 0]).max()) / 0.01


def test_heaving_at_twice_the_pendulum_frequency_is_parametric_resonance():
    """Mathieu's equation θ̈ + ω₀² (1 + h cos Ωt) θ = 0, h = 0.2: at Ω = 2ω₀ (inside the first
    zone of instability, |Ω − 2ω₀| < h ω₀ / 2) a small angle grows like e^(h ω₀ t / 4)
    (e^3.3 ≈ 27 over 15 s, less as the swing grows and its frequency falls); at Ω = 3ω₀,
    between the zones, it stays of its initial size."""
    assert _growth(2.0 * OMEGA0) > 10.0
    assert _growth(3.0 * OMEGA0) < 2.0


def test_a_base_at_rest_runs_as_before():
    """dyn.base None: the run has no base's work, and a Controller without states gives the
    plain actuation's run bit for bit (the hook does not change the arithmetic)."""
    dyn = ChainDynamics(pendulum(), ["swing"])
    t = np.linspace(0.0, 1.0, 51)

    class Constant:
        n_states = 0

        def start(self, t0, q0, v0):
            return np.zeros(0)

        def __call__(self, t, q, v, x):
            return np.array([0.4]), np.zeros(0)

    plain = simulate(dyn, t, np.array([0.2]), np.array([0.0]), lambda t, q, v: np.array([0.4]))
    hooked = simulate(dyn, t, np.array([0.2]), np.array([0.0]), Constant())
    assert plain.base_work is None
    for name in ("q", "v", "a", "energy", "kinetic", "work", "residual", "actuation"):
        assert np.array_equal(getattr(plain, name), getattr(hooked, name)), name
    assert plain.controller.shape == (51, 0)
    assert np.all(plain.actuation == 0.4)


@dataclass
class Lag:
    """A PD law through a first-order lag (a servo's bandwidth): the drive u = s follows the
    command −k θ − c θ̇ with time constant T, ṡ = (−k θ − c θ̇ − s) / T."""

    gain: float = 8.0  # [N·m/rad]
    damping: float = 0.5  # [N·m·s/rad]
    lag: float = 0.05  # [s]
    n_states: int = 1

    def start(self, t0, q0, v0):
        return np.array([0.0])

    def __call__(self, t, q, v, x):
        command = -self.gain * q[0] - self.damping * v[0]
        return x.copy(), np.array([(command - x[0]) / self.lag])


@pytest.mark.parametrize("lift", [0.0, 0.03])
def test_a_controller_with_a_lag_follows_its_hand_written_equation(lift):
    """m L² θ̈ = s − m (g + a(t)) L sin θ and the lag's ṡ, by SciPy, standing (lift 0: no base)
    and on a heaving base (A = 3 cm at 7 rad/s); the controller's states and the applied
    actuation are reported, and the inverse dynamics of the samples read the drive back."""
    frequency, law = 7.0, Lag()
    base = heave(lift, frequency) if lift else None
    dyn = ChainDynamics(pendulum(), ["swing"], base=base)
    t = np.linspace(0.0, 3.0, 301)
    run = simulate(dyn, t, np.array([0.3]), np.array([0.0]), law, **TIGHT)

    def rhs(s, y):
        theta, rate, drive = y
        accel = lift * frequency**2 * math.cos(frequency * s)
        command = -law.gain * theta - law.damping * rate
        angular = (drive - MASS * (G + accel) * LENGTH * math.sin(theta)) / (MASS * LENGTH**2)
        return [rate, angular, (command - drive) / law.lag]

    theta, rate, drive = solve_ivp(
        rhs, (0.0, 3.0), [0.3, 0.0, 0.0], t_eval=t, method="DOP853", **TIGHT
    ).y
    assert np.abs(run.q[:, 0] - theta).max() < CLOSED_FORM
    assert np.abs(run.v[:, 0] - rate).max() < CLOSED_FORM
    assert np.abs(run.controller[:, 0] - drive).max() < CLOSED_FORM
    assert np.array_equal(run.actuation, run.controller)  # u = s
    assert np.abs(drive).max() > 1.0  # the drive acts: the checks are not empty
    # the inverse dynamics of the samples read the applied drive back (round-off of M q̈ + b)
    read = run.loads.actuators["swing"]
    assert np.abs(read - run.actuation[:, 0]).max() < 1e-12 * np.abs(drive).max() * 1e2
    # the work W includes the drive's power: the balance closes (with the base's work)
    assert run.energy_error() < CLOSED_FORM


class Bad:
    n_states = 1

    def __init__(self, states=1, start=(0.0,), out=None):
        self.n_states, self.first, self.out = states, np.array(start), out

    def start(self, t0, q0, v0):
        return self.first

    def __call__(self, t, q, v, x):
        return self.out if self.out is not None else (np.zeros(1), np.zeros(1))


@pytest.mark.parametrize(
    ("controller", "message"),
    [
        (Bad(states=-1), "n_states must be a whole number ≥ 0"),
        (Bad(start=(0.0, 1.0)), "initial states must be 1 finite numbers"),
        (Bad(start=(math.nan,)), "initial states"),
        (Bad(out=np.zeros(1)), "must return \\(u, xdot\\)"),
        (Bad(out=(np.zeros(1), np.zeros(2))), "controller state rates at t = 0 s must be 1"),
        (Bad(out=(np.zeros(2), np.zeros(1))), "actuation at t = 0 s must be 1 finite"),
    ],
)
def test_bad_controllers_are_refused_in_one_line(controller, message):
    assert isinstance(controller, Controller)
    dyn = ChainDynamics(pendulum(), ["swing"])
    with pytest.raises(InputError, match=message):
        simulate(dyn, np.linspace(0.0, 0.1, 3), np.array([0.3]), np.array([0.0]), controller)


MUJOCO = 1e-8
"""Largest gap between feeder's accelerations and MuJoCo's (relative to the largest q̈ of the
sample), and between the absolute energies (relative to the largest). MuJoCo's M and bias are
exact Newton–Euler on the absolute motion; the gap is the forward equations' own: the proximal
solver's accuracy (1e-13) and Baumgarte's corrector on the sample's residual (ω² × 1e-13 m,
ω = 20/s: 4e-11 m/s²) — measured ≤ 1e-14 (accelerations) and 2e-16 (energies)."""


def test_the_device_on_a_rocking_hull_moves_as_in_mujoco(feeder):
    """The device (its base link given a bracket's inertia, as in test_base_mujoco) on the hull
    weaving in all six channels over terrain, held by constant drives (the standing loads of its
    start): at every sample of the run MuJoCo's equations on a hull with six joints driven by
    the same motion give the same accelerations, and MuJoCo's energies (``mj_energyPos``,
    ``mj_energyVel`` of hull and device) are the run's absolute ones.

    MuJoCo's constrained accelerations at a sample: the closure's acceleration rows are
    kinematics (the run meets them: its loads' inverse dynamics check them to 1e-9); along the
    directions they leave free (N: a basis of the null space of the loop's Jacobian J_d, the
    device's columns) MuJoCo's equations Nᵀ (M_dd q̈_d + M_dh q̈_h + b_d − τ_d) = 0 fix q̈; the
    part of feeder's q̈ that violates them is N (Nᵀ M_dd N)⁻¹ Nᵀ r, r the residual."""
    mujoco = pytest.importorskip("mujoco")
    from feeder.chain.dynamics.inverse import inverse_dynamics
    from feeder.dynamics.models import ACTUATED_JOINTS
    from feeder.motion.cycle import feeding_cycle

    from .test_base_mujoco import ANGLES, BASE_JOINTS, BRACKET, FORWARD, Weave, mjcf

    model = pin.Model(feeder.chain.model)
    model.inertias[0] = BRACKET
    chain = ClosedChain(model, feeder.chain.closures)
    from feeder.chain.model.profiles import Terrain

    base = BaseMotion((Terrain(), Weave()), forward=FORWARD)
    cycle = feeding_cycle(feeder, math.radians(30.0))
    start = int(np.flatnonzero(cycle.gripped == 1)[0]) + 10
    q0, v0 = (
        feeder.to_pinocchio(getattr(cycle, name)[start : start + 1])[0] for name in ("q", "v")
    )
    t = cycle.t[start] + np.linspace(0.0, 0.4, 21)
    standing = inverse_dynamics(
        ChainDynamics(chain, ACTUATED_JOINTS), q0[None], v0[None], 0 * v0[None]
    )
    hold = np.array([standing.actuators[name][0] for name in ACTUATED_JOINTS])
    dyn = ChainDynamics(chain, ACTUATED_JOINTS, base=base)
    run = simulate(dyn, t, q0, v0, lambda s, q, v: hold)
    assert run.displacement(model) > 1e-3  # the hull shakes it: the comparison is not at rest

    m = mujoco.MjModel.from_xml_string(mjcf(model))
    m.opt.enableflags |= mujoco.mjtEnableBit.mjENBL_ENERGY
    d = mujoco.MjData(m)
    channels = sum((p.channels(t) for p in base.profiles[1:]), base.profiles[0].channels(t))
    axes = base.vehicle_axes(model.gravity.linear)
    hull = [
        np.hstack([x[:, :3] @ axes.T, x[:, ANGLES]])
        for x in (channels.value, channels.rate, channels.acceleration)
    ]
    hull_dofs = [m.joint(name).dofadr[0] for name, _, _ in BASE_JOINTS]
    hull_q = [m.joint(name).qposadr[0] for name, _, _ in BASE_JOINTS]
    dofs = np.array([m.joint(model.names[j]).dofadr[0] for j in range(1, model.njoints)])
    qpos = [m.joint(model.names[j]).qposadr[0] for j in range(1, model.njoints)]
    frames = [model.frames[i] for i in chain.frame_ids[0]]
    bodies = [m.body(model.names[frame.parentJoint]).id for frame in frames]
    columns = [model.joints[j].idx_v for j in range(1, model.njoints)]
    drive = np.zeros(model.nv)
    drive[dyn.columns] = hold
    full = np.zeros((m.nv, m.nv))
    for k in range(t.size):
        d.qpos[hull_q], d.qvel[hull_dofs] = hull[0][k], hull[1][k]
        d.qpos[qpos], d.qvel[dofs] = run.q[k, columns], run.v[k, columns]
        mujoco.mj_forward(m, d)
        column = np.zeros(m.nv)
        for i, unit in enumerate(np.eye(m.nv)):  # M column by column (mj_fullM's signature
            mujoco.mj_mulM(m, d, column, unit)  # changed in MuJoCo 3.x)
            full[:, i] = column
        jac = []
        for frame, body in zip(frames, bodies, strict=True):
            point = d.xpos[body] + d.xmat[body].reshape(3, 3) @ frame.placement.translation
            one = np.zeros((3, m.nv))
            mujoco.mj_jac(m, d, one, None, point, body)
            jac.append(one[:, dofs])
        _, values, rows = np.linalg.svd(jac[0] - jac[1])
        free = rows[np.sum(values > 1e-9 * values[0]) :].T  # N, (n_device, n_free)
        a = run.a[k, columns]
        residual = (
            full[np.ix_(dofs, dofs)] @ a
            + full[np.ix_(dofs, hull_dofs)] @ hull[2][k]
            + d.qfrc_bias[dofs]
            - drive[columns]
        )
        reduced = free.T @ full[np.ix_(dofs, dofs)] @ free
        gap = free @ np.linalg.solve(reduced, free.T @ residual)
        assert np.abs(gap).max() <= MUJOCO * np.abs(a).max(), (k, np.abs(gap).max())
        assert abs(run.kinetic[k] - d.energy[1]) <= MUJOCO * np.abs(run.energy).max()
        assert abs(run.energy[k] - d.energy.sum()) <= MUJOCO * np.abs(run.energy).max()
    # the drives read back, and the balance with the base's work closes to the integrator's
    # tolerance (rtol 1e-8 on energies of some 1e3 J: ~1e-5 J over the run)
    for i, name in enumerate(ACTUATED_JOINTS):
        assert (
            np.abs(run.loads.actuators[name] - run.actuation[:, i]).max() <= 1e-9 * abs(hold).max()
        )
    assert np.abs(run.base_work).max() > 1.0
    assert run.energy_error() <= 1e-7 * max(run.energy_scales().values())


def test_a_base_that_does_not_move_runs_as_a_base_at_rest():
    """A base whose channels are all zero takes the moving-base path (the moving root, its
    bias, the base's work) and gives the standing run: the bias b − b_B is zero to round-off,
    but the state's extra component (W_B) changes the integrator's error norm and so its
    steps, and the two runs differ by their integration errors: both at :data:`TIGHT`, each
    within a few 1e-11 of the exact motion (the closed-form tests), 1e-10 bounds their gap.
    The base's work is exactly zero (its velocity is)."""
    drive = lambda t, q, v: np.array([0.3 * math.sin(3.0 * t)])  # noqa: E731
    t = np.linspace(0.0, 2.0, 41)
    still = BaseMotion((Harmonic(2, 0.0, 7.0),))
    dyns = [ChainDynamics(pendulum(), ["swing"], base=base) for base in (None, still)]
    runs = [simulate(dyn, t, np.array([0.3]), np.zeros(1), drive, **TIGHT) for dyn in dyns]
    assert runs[0].base_work is None and np.all(runs[1].base_work == 0.0)
    for name in ("q", "v", "a", "energy", "work"):
        np.testing.assert_allclose(
            getattr(runs[1], name), getattr(runs[0], name), rtol=0, atol=1e-10
        )
    for what in ("force", "moment"):
        np.testing.assert_allclose(
            getattr(runs[1].loads.mount, what),
            getattr(runs[0].loads.mount, what),
            rtol=0,
            atol=1e-9,
        )


def test_a_hull_table_that_does_not_cover_the_run_is_refused_before_it():
    from feeder.chain import HullTable, Table

    times = np.array([0.0, 0.5, 1.0])
    table = HullTable(Table(times, np.zeros((3, 18)), source="hull.csv"))
    dyn = ChainDynamics(pendulum(), [], base=BaseMotion((table,)))
    with pytest.raises(InputError, match="hull.csv: the hull motion covers t = 0 … 1 s"):
        simulate(dyn, np.linspace(0.0, 2.0, 3), np.array([0.3]), np.zeros(1))


def test_a_run_on_a_moving_base_passes_a_singular_position(delta):
    """The planar delta robot released on a terrain ride passes the dead centre of its third
    rod (t ≈ 0.05 s standing) as it does standing (test_singular.py): the rank drop listed,
    the samples next to it flagged, and the balance with the base's work closed as closely as
    the standing run's (measured 3e-8 of the energy moved; the pass's expansion and
    projections allow 1e-6)."""
    from feeder.chain.model.profiles import Terrain

    standing, q0 = delta
    dyn = ChainDynamics(standing.chain, standing.actuated, base=BaseMotion((Terrain(),)))
    run = simulate(dyn, np.linspace(0.0, 0.08, 17), q0, np.zeros(standing.chain.model.nv))
    assert len(run.singular) == 1 and 0.045 < run.singular[0].time < 0.055
    assert run.indeterminate.any() and not run.indeterminate.all()
    assert np.abs(run.base_work).max() > 1e-3
    assert run.energy_error() <= 1e-6 * max(run.energy_scales().values())


@pytest.mark.parametrize("method", ["DOP853", "RK45"])
def test_the_base_is_computed_once_a_step_at_the_times_the_step_evaluates(monkeypatch, method):
    """The explicit methods' stage times are predicted (``stage_times``) and the base's motion
    computed for them in one pass: the single-time path is left to rejected steps, and the run
    is the one it would be without the prediction, to round-off (the vectorised sines and the
    single ones may differ in the last bit)."""
    from feeder.chain.dynamics import forward, forward_base

    dyn = ChainDynamics(pendulum(), [], base=heave(0.03, 7.0))
    t = np.linspace(0.0, 2.0, 201)
    singles = []
    states = forward_base.MovingBase.states

    def counted(self, times):
        if np.size(times) == 1:
            singles.append(float(np.ravel(times)[0]))
        return states(self, times)

    monkeypatch.setattr(forward_base.MovingBase, "states", counted)
    run = simulate(dyn, t, np.array([0.4]), np.array([0.3]), method=method, **TIGHT)
    # an evaluation outside the predicted times is a rejected step's (SciPy retries it within
    # the same call, shorter): 15 % of this run's at rtol 1e-12 (1.4 % in the device's cycle)
    assert len(singles) < 0.2 * run.evaluations, (len(singles), run.evaluations)
    monkeypatch.setattr(forward, "stage_times", lambda solver: np.zeros(0))
    alone = simulate(dyn, t, np.array([0.4]), np.array([0.3]), method=method, **TIGHT)
    assert len(singles) >= alone.evaluations  # without the prediction every time is alone
    # the same steps on the same equations: round-off of angles ~1 (1e-13 with 1 000 steps)
    np.testing.assert_allclose(run.q, alone.q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(run.base_work, alone.base_work, rtol=0, atol=1e-12)
