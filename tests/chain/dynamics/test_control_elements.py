"""The computed-torque controller driving a joint by a force element's push (a ``[[control]]``
table's ``element``): a pendulum lifted by a hydraulic cylinder from a ground pivot and a slider
pushed by an oblique spring, against hand-derived statics and dynamics (the push the motion
needs, the chamber pressure, the hinge's reaction), the closed loop's closed form from a
disturbed start, the lag and limits on the push (SciPy, independently), and the refusals."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import scipy.integrate

from feeder.chain import ClosedChain
from feeder.chain.dynamics.control import ComputedTorque
from feeder.chain.dynamics.forward import simulate
from feeder.chain.dynamics.inverse import ChainDynamics
from feeder.chain.model.control import ControlSpec
from feeder.chain.model.forces import Cylinder, JointSpring, Spring
from feeder.exceptions import InputError

from .test_control import _vandermonde_error

MASS, ARM, GRAVITY = 2.0, 0.3, 9.81
"""The pendulum's mass [kg], its centre of gravity's distance from the hinge [m], g [m/s²]."""
MOMENT = 4e-3 + MASS * ARM**2
"""Its moment of inertia about the hinge I_O [kg·m²] (parallel axes from 4e-3 at the centre)."""
EYE = 0.2
"""The cylinder's rod eye on the pendulum, EYE along its x axis [m]."""
BORE, ROD = 0.04, 0.02
"""The cylinder's bore D and rod d [m]."""

TIGHT = {"rtol": 1e-11, "atol": 1e-12}
"""Integrator tolerances of the comparisons with closed forms: their global error on motions of
~0.1 rad or m over ~1 s is ~1e-10 (measured), so the comparisons hold to 1e-8 or better."""


def _spec(joint: str, t: np.ndarray, q, v, a, **settings) -> ControlSpec:
    arrays = [np.broadcast_to(np.asarray(x, dtype=float), t.shape).copy() for x in (q, v, a)]
    gains = {"kp": 100.0, "kd": 20.0} | settings
    return ControlSpec(joint, Path("reference.csv"), t, *arrays, **gains)


def _frame(model: pin.Model, name: str, joint: int, where) -> None:
    placement = pin.SE3(np.eye(3), np.asarray(where, dtype=float))
    model.addFrame(pin.Frame(name, joint, 0, placement, pin.FrameType.OP_FRAME))


def _pendulum(anchor, *elements, actuated=()) -> ChainDynamics:
    """A rod on a hinge about z, its centre of gravity ARM along its x, gravity −y
    (I_O θ̈ = τ − m g ARM cos θ), a frame "anchor" on the ground at ``anchor`` [m] and "eye" on
    the rod at EYE along its x; ``elements``: the force elements, default the cylinder "lift"
    from the anchor (cap end) to the eye."""
    model = pin.Model()
    joint = model.addJoint(0, pin.JointModelRZ(), pin.SE3.Identity(), "hinge")
    inertia = pin.Inertia(MASS, np.array([ARM, 0.0, 0.0]), np.diag([1e-4, 4e-3, 4e-3]))
    model.appendBodyToJoint(joint, inertia, pin.SE3.Identity())
    model.gravity = pin.Motion(np.array([0.0, -GRAVITY, 0.0]), np.zeros(3))
    _frame(model, "anchor", 0, anchor)
    _frame(model, "eye", joint, [EYE, 0.0, 0.0])
    _frame(model, "ground", 0, [0.5, 0.5, 0.0])
    elements = elements or (Cylinder(("anchor", "eye"), BORE, ROD, name="lift"),)
    return ChainDynamics(ClosedChain(model, []), list(actuated), elements=elements)


def _lever(theta: np.ndarray, anchor) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """By hand: the eye p = EYE (cos θ, sin θ), the cylinder's length ℓ = |p − a|, its unit
    direction n = (p − a)/ℓ (N, 2) and its lever g = dℓ/dθ = n · dp/dθ
    = EYE (a_x sin θ − a_y cos θ)/ℓ [m]: the hinge torque of a unit push."""
    ax, ay = anchor[0], anchor[1]
    gap = np.column_stack([EYE * np.cos(theta) - ax, EYE * np.sin(theta) - ay])
    length = np.hypot(gap[:, 0], gap[:, 1])
    return length, gap / length[:, None], EYE * (ax * np.sin(theta) - ay * np.cos(theta)) / length


def _swing(t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The reference θ = 0.3 + 0.2 sin 2πt [rad] and its two derivatives."""
    w = 2.0 * math.pi
    return 0.3 + 0.2 * np.sin(w * t), 0.2 * w * np.cos(w * t), -0.2 * w**2 * np.sin(w * t)


@pytest.mark.parametrize(
    ("anchor", "chamber"),
    [((0.1, -0.4, 0.0), "cap"), ((0.1, 0.4, 0.0), "rod")],
    ids=["pushed from below", "pulled from above"],
)
def test_a_cylinder_lifts_a_pendulum_along_its_reference(anchor, chamber):
    """Started on the reference, the pendulum follows it to the integrator's tolerance; the push
    is the one the swing needs, P = (I_O θ̈ + m g ARM cos θ)/g(θ) by hand at the reference; the
    pressure is P/A_cap in the cap chamber (from below: a push) or −P/A_ann in the rod chamber
    (from above: a pull), the other at zero gauge; the energy balance closes with the push's
    work; and the loads of the applied pushes give the cylinder's tension −P and the hinge's
    reaction m a_G − m g − P n (Newton's law for the rod, by hand)."""
    dyn = _pendulum(anchor)
    t_table = np.linspace(0.0, 1.0, 201)
    spec = _spec("hinge", t_table, *_swing(t_table), element="lift", kp=225.0, kd=30.0)
    controller = ComputedTorque(dyn, [spec])
    assert controller.pushes == ("lift",) and controller.n_actuated == 0
    t = t_table[::2]  # the table's samples: there the quintic reference is the sine's
    theta, rate, acceleration = _swing(t)
    run = simulate(dyn, t, theta[:1], rate[:1], controller, **TIGHT)
    record = controller.record(t, run.q, run.v, run.controller)
    assert record.peak_error()[0] <= 1e-9  # the integrator's tolerance (TIGHT)
    length, direction, lever = _lever(theta, anchor)
    push = (MOMENT * acceleration + MASS * GRAVITY * ARM * np.cos(theta)) / lever
    assert np.all(push > 0.0) if chamber == "cap" else np.all(push < 0.0)
    # the state's offset (≤ 1e-11 rad measured) moves the push of ~40 N by its share, and the
    # feedback K_p e I_O / g adds ~1e-8 N at most: 1e-7 N (measured 5e-9 N)
    np.testing.assert_allclose(record.force[:, 0], push, rtol=0.0, atol=1e-7)
    cap, rod = record.chambers["hinge"]
    cap_area, annulus = math.pi * BORE**2 / 4.0, math.pi * (BORE**2 - ROD**2) / 4.0
    expected = (push / cap_area, 0.0) if chamber == "cap" else (0.0, -push / annulus)
    np.testing.assert_allclose(cap, expected[0], rtol=0.0, atol=1e-7 / annulus)  # the push's
    np.testing.assert_allclose(rod, expected[1], rtol=0.0, atol=1e-7 / annulus)
    assert "control of 'hinge' by the push of 'lift'" in record.lines()[0]
    assert "peak cap pressure" in record.lines()[0]
    # the work of the push P ℓ̇ is in W: the balance to the integrator's tolerance on the
    # swing's 2.2 J (rtol 1e-11; measured 6e-13 J), where a missing push power would be ~J
    assert np.abs(run.balance()).max() <= 1e-10
    loads = run.loads  # the inverse dynamics of the run's samples with the pushes applied
    np.testing.assert_allclose(loads.elements["lift"], -push, rtol=0.0, atol=1e-7)  # as the push
    gravity = np.array([0.0, -GRAVITY])
    q, w, dw = run.q[:, 0], run.v[:, 0], run.a[:, 0]
    centre = ARM * np.column_stack([-np.sin(q) * dw - np.cos(q) * w**2,
                                    np.cos(q) * dw - np.sin(q) * w**2])  # fmt: skip
    reaction = MASS * centre - MASS * gravity - push[:, None] * direction
    # forces of ~40 N from pushes to 1e-7 N and accelerations of the run's round-off: 1e-7 N
    np.testing.assert_allclose(loads.joints["hinge"].force[:, :2], reaction, rtol=0, atol=1e-7)


def test_the_run_s_own_loads_are_those_of_the_applied_pushes():
    """The forward run's loads (ForwardRun.loads) carry the pushes the controller applied: the
    cylinder's tension is −push at every sample."""
    anchor = (0.1, -0.4, 0.0)
    dyn = _pendulum(anchor)
    t_table = np.linspace(0.0, 1.0, 201)
    controller = ComputedTorque(dyn, [_spec("hinge", t_table, *_swing(t_table), element="lift")])
    t = t_table[::4]
    theta, rate, _ = _swing(t)
    run = simulate(dyn, t, theta[:1], rate[:1], controller, **TIGHT)
    record = controller.record(t, run.q, run.v, run.controller)
    # the same pushes at the same states, a Table at its own knots: to round-off of ~50 N
    np.testing.assert_allclose(run.loads.elements["lift"], -record.force[:, 0], atol=1e-12)


def _slider(anchor, *elements, mass: float = 3.0) -> ChainDynamics:
    """A mass on a prismatic joint "slide" along x, no gravity, its frame "block" at its origin,
    "anchor" on the ground at ``anchor`` [m] and "ground" at (1, 1, 0) m."""
    model = pin.Model()
    joint = model.addJoint(0, pin.JointModelPX(), pin.SE3.Identity(), "slide")
    model.appendBodyToJoint(
        joint, pin.Inertia(mass, np.zeros(3), np.eye(3) * 1e-3), pin.SE3.Identity()
    )
    model.gravity = pin.Motion.Zero()
    _frame(model, "anchor", 0, anchor)
    _frame(model, "block", joint, [0.0, 0.0, 0.0])
    _frame(model, "ground", 0, [1.0, 1.0, 0.0])
    return ChainDynamics(ClosedChain(model, []), [], elements=elements)


def test_an_oblique_spring_s_push_brings_the_slider_back_as_the_closed_loop_says():
    """A slider x pushed by a spring–damper–actuator from a ground point at height H (ℓ² =
    x² + H², lever g = x/ℓ, its spring k (ℓ − ℓ₀) and damper c ℓ̇ acting), started at rest 0.1 m
    short of a constant reference: under critically damped gains the error is
    e0 (1 + ωt) e^(−ωt) whatever the nonlinear geometry, and the push is the one
    m ẍ = g (P − k (ℓ − ℓ₀) − c ℓ̇) needs at the run's states (by hand)."""
    mass, height, k, rest, c, omega = 3.0, 0.2, 50.0, 0.3, 2.0, 10.0
    spring = Spring(("anchor", "block"), k, rest, c, name="oblique")
    dyn = _slider((0.0, height, 0.0), spring, mass=mass)
    t_table = np.linspace(0.0, 1.5, 3)
    spec = _spec("slide", t_table, 0.5, 0.0, 0.0, element="oblique", kp=omega**2, kd=2 * omega)
    controller = ComputedTorque(dyn, [spec])
    t = np.linspace(0.0, 1.5, 151)
    run = simulate(dyn, t, np.array([0.4]), np.zeros(1), controller, **TIGHT)
    record = controller.record(t, run.q, run.v, run.controller)
    exact = 0.1 * (1.0 + omega * t) * np.exp(-omega * t)
    np.testing.assert_allclose(record.error[:, 0], exact, rtol=0.0, atol=1e-9)
    x, dx, ddx = run.q[:, 0], run.v[:, 0], run.a[:, 0]
    length = np.hypot(x, height)
    lever = x / length
    push = mass * ddx / lever + k * (length - rest) + c * lever * dx
    # the run's accelerations at its samples are its equations' at the same states: the push
    # of up to 41 N to round-off (measured 1.4e-14 N), 1e-10 N with room
    np.testing.assert_allclose(record.force[:, 0], push, rtol=0.0, atol=1e-10)
    # the damper's and the push's work (0.9 J) in W: the balance to the integrator's tolerance
    assert np.abs(run.balance()).max() <= 1e-9  # (measured 1.6e-12 J)


def test_a_lagged_limited_push_follows_the_linear_model():
    """A spring along the slide (lever 1, no stiffness): the push through a lag T with a force
    and a rate limit is the joint's drive was, m ẍ = F, Ḟ = clip((clip(m (K_p e − K_d ẋ), ±L)
    − F)/T, ±r): against SciPy; without the limits, the third-order loop's modes."""
    mass, lag, kp, kd, target = 3.0, 0.02, 400.0, 30.0, 0.1
    dyn = _slider((-1.0, 0.0, 0.0), Spring(("anchor", "block"), name="axial"), mass=mass)
    t_table = np.linspace(0.0, 1.0, 3)
    t = np.linspace(0.0, 1.0, 201)
    free = ComputedTorque(
        dyn, [_spec("slide", t_table, target, 0.0, 0.0, element="axial", kp=kp, kd=kd, lag=lag)]
    )
    run = simulate(dyn, t, np.zeros(1), np.zeros(1), free, **TIGHT)
    roots = np.roots([lag, 1.0, kd, kp])
    exact = _vandermonde_error(roots, np.array([target, 0.0, -kp * target]), t)
    np.testing.assert_allclose(free.record(t, run.q, run.v, run.controller).error[:, 0], exact,
                               rtol=0.0, atol=1e-8)  # fmt: skip
    limit, rate = 80.0, 1500.0  # the unlimited loop's force falls at up to 2200 N/s
    spec = _spec("slide", t_table, target, 0.0, 0.0, element="axial", kp=kp, kd=kd, lag=lag,
                 force_limit=(-limit, limit), rate_limit=rate)  # fmt: skip
    controller = ComputedTorque(dyn, [spec])
    run = simulate(dyn, t, np.zeros(1), np.zeros(1), controller, **TIGHT)
    record = controller.record(t, run.q, run.v, run.controller)

    def linear(_, y):
        x, v, force = y
        command = np.clip(mass * (kp * (target - x) - kd * v), -limit, limit)
        return [v, force / mass, np.clip((command - force) / lag, -rate, rate)]

    solution = scipy.integrate.solve_ivp(
        linear, (0.0, 1.0), [0.0, 0.0, limit], t_eval=t, rtol=1e-12, atol=1e-14
    )
    # the clips kink the right-hand side: both integrators step over them, 1e-7 m
    np.testing.assert_allclose(run.q[:, 0], solution.y[0], rtol=0.0, atol=1e-7)
    assert record.saturated[0, 0] and record.rate_limited[:, 0].any()
    assert np.all(np.abs(record.force[:, 0]) <= limit * (1.0 + 1e-12))


LIFT = Cylinder(("anchor", "eye"), BORE, ROD, name="lift")
T3 = np.linspace(0.0, 1.0, 3)


@pytest.mark.parametrize(
    ("elements", "actuated", "settings", "message"),
    [
        ((LIFT,), (), {"element": "lfit"}, "no force element 'lfit'; did you mean 'lift'"),
        ((JointSpring("hinge", 1.0, name="coil"),), (), {"element": "coil"}, "is a JointSpring"),
        (
            (Spring(("anchor", "eye"), force=5.0, name="s"),),
            (),
            {"element": "s"},
            "push law of its own",
        ),
        (
            (Cylinder(("anchor", "eye"), BORE, ROD, 1e5, name="c"),),
            (),
            {"element": "c"},
            "push law of its own",
        ),
        ((LIFT,), ("hinge",), {"element": "lift"}, "'hinge' is actuated"),
        ((LIFT,), (), {"element": "lift", "area": 1e-3}, "area is for a joint's own drive"),
        ((LIFT,), ("hinge",), {}, None),  # the joint's own drive: accepted
    ],
)
def test_bad_element_drives_are_refused_in_one_line(elements, actuated, settings, message):
    dyn = _pendulum((0.1, -0.4, 0.0), *elements, actuated=actuated)
    specs = [_spec("hinge", T3, 0.0, 0.0, 0.0, **settings)]
    if message is None:
        assert ComputedTorque(dyn, specs).pushes == ()
        return
    with pytest.raises(InputError, match=message) as error:
        ComputedTorque(dyn, specs)
    assert "\n" not in str(error.value)


def test_an_element_pushed_for_two_joints_or_an_unknown_joint_is_refused():
    spring = Spring(("anchor", "block"), name="push")
    dyn = _slider((-1.0, 0.0, 0.0), spring)
    spec = _spec("slide", T3, 0.0, 0.0, 0.0, element="push")
    with pytest.raises(InputError, match="'push' is pushed for two joints"):
        ComputedTorque(dyn, [spec, spec])
    with pytest.raises(InputError, match="no joint 'slid'.*did you mean 'slide'"):
        ComputedTorque(dyn, [_spec("slid", T3, 0.0, 0.0, 0.0, element="push")])


@pytest.mark.parametrize(
    ("frames", "anchor"),
    [(("anchor", "block"), (0.0, 0.2, 0.0)), (("anchor", "ground"), (0.0, 0.2, 0.0))],
    ids=["across the slide", "both ends on the ground"],
)
def test_an_element_that_cannot_move_its_joint_is_refused_at_the_start(frames, anchor):
    """A spring square to the slide at the start (its lever x/ℓ is 0 at x = 0), or between two
    ground points: its push cannot accelerate the slider."""
    dyn = _slider(anchor, Spring(frames, name="square"))
    controller = ComputedTorque(dyn, [_spec("slide", T3, 0.1, 0.0, 0.0, element="square")])
    with pytest.raises(
        InputError, match="cannot be accelerated independently by the push of 'square'"
    ):
        simulate(dyn, np.linspace(0.0, 1.0, 3), np.zeros(1), np.zeros(1), controller)


def _two_springs(angle: float, mass: float = 2.0) -> ChainDynamics:
    """A point mass on two prismatic joints "x" and "y" (M = m I: the carriage between them is
    massless), no gravity, pushed by two springs without stiffness from ground anchors 1 m away
    along −n₁ and −n₂, n_k = (cos θ_k, sin θ_k): θ₁ = 0.7 rad, θ₂ = θ₁ + ``angle``."""
    model = pin.Model()
    x = model.addJoint(0, pin.JointModelPX(), pin.SE3.Identity(), "x")
    model.appendBodyToJoint(x, pin.Inertia.Zero(), pin.SE3.Identity())
    y = model.addJoint(x, pin.JointModelPY(), pin.SE3.Identity(), "y")
    model.appendBodyToJoint(
        y, pin.Inertia(mass, np.zeros(3), np.eye(3) * 1e-3), pin.SE3.Identity()
    )
    model.gravity = pin.Motion.Zero()
    _frame(model, "mass", y, [0.0, 0.0, 0.0])
    for name, theta in (("one", 0.7), ("two", 0.7 + angle)):
        _frame(model, f"anchor_{name}", 0, [-math.cos(theta), -math.sin(theta), 0.0])
    springs = [Spring((f"anchor_{name}", "mass"), name=name) for name in ("one", "two")]
    return ChainDynamics(ClosedChain(model, []), [], elements=springs)


def test_nearly_parallel_pushes_are_solved_or_refused_by_the_rank_tolerance():
    """Two pushes whose lines meet at an angle δ control x and y: their shares' smallest
    singular value is √(1 − cos δ) ≈ δ/√2 (unit columns n₁/m, n₂/m scaled by their reach).
    At δ = 1e-6 (7e-7, above RANK_TOLERANCE 1e-8) the pushes are m [n₁ n₂]⁻¹ q̈* by hand, to the
    conditioning's share of round-off (cond 1.4e6: 1e-9 relative); at δ = 1e-9 (7e-10, below)
    the start is refused. The tolerance therefore sits between lines one microradian apart
    (solved) and lines parallel to the round-off of their anchors (1e-16 rad)."""
    mass, target = 2.0, np.array([1.0, 0.5])  # q̈* = q̈_ref on the reference (no error)
    t = np.linspace(0.0, 1.0, 3)
    specs = [
        _spec(joint, t, 0.0, 0.0, a, element=name)
        for joint, name, a in (("x", "one", target[0]), ("y", "two", target[1]))
    ]
    near = ComputedTorque(_two_springs(1e-6, mass), specs)
    lines = np.array(
        [[math.cos(0.7), math.cos(0.7 + 1e-6)], [math.sin(0.7), math.sin(0.7 + 1e-6)]]
    )
    expected = mass * np.linalg.solve(lines, target)
    assert np.abs(expected).max() > 1e5  # huge pushes: the lines nearly cancel
    np.testing.assert_allclose(near.demand(0.0, np.zeros(2), np.zeros(2)), expected, rtol=1e-8)
    parallel = ComputedTorque(_two_springs(1e-9, mass), specs)
    with pytest.raises(InputError, match="cannot be accelerated independently"):
        simulate(parallel.dyn, t, np.zeros(2), np.zeros(2), parallel)


def test_a_joint_s_drive_and_an_element_s_push_in_one_controller():
    """Two bodies on the ground: the pendulum lifted by its cylinder (not actuated) and a slider
    of 3 kg driven by its own actuator, the element's table listed first: u is the actuated
    slider's drive, then the push; each follows its reference to the integrator's tolerance,
    the drive is m ẍ_ref and the push the pendulum's hand-derived one."""
    dyn = _pendulum((0.1, -0.4, 0.0))
    model = dyn.chain.model
    joint = model.addJoint(0, pin.JointModelPX(), pin.SE3.Identity(), "slide")
    model.appendBodyToJoint(joint, pin.Inertia(3.0, np.zeros(3), np.eye(3) * 1e-3),
                            pin.SE3.Identity())  # fmt: skip
    elements = dyn.elements.elements
    dyn = ChainDynamics(ClosedChain(model, []), ["slide"], elements=elements)
    t_table = np.linspace(0.0, 1.0, 201)
    w = 3.0
    slide = (0.1 * np.sin(w * t_table), 0.1 * w * np.cos(w * t_table),
             -0.1 * w**2 * np.sin(w * t_table))  # fmt: skip
    specs = [
        _spec("hinge", t_table, *_swing(t_table), element="lift"),
        _spec("slide", t_table, *slide),
    ]
    controller = ComputedTorque(dyn, specs)
    t = t_table[::2]
    theta, rate, acceleration = _swing(t)
    q0, v0 = np.array([theta[0], 0.0]), np.array([rate[0], 0.1 * w])
    run = simulate(dyn, t, q0, v0, controller, **TIGHT)
    record = controller.record(t, run.q, run.v, run.controller)
    assert np.all(record.peak_error() <= 1e-9)  # the integrator's tolerance (TIGHT)
    _, _, lever = _lever(theta, (0.1, -0.4, 0.0))
    push = (MOMENT * acceleration + MASS * GRAVITY * ARM * np.cos(theta)) / lever
    np.testing.assert_allclose(record.force[:, 0], push, rtol=0.0, atol=1e-7)  # as above
    # the drive m ẍ_ref of ≤ 2.7 N, the state off by ~1e-11 m: 1e-8 N
    drive = -3.0 * 0.1 * w**2 * np.sin(w * t)
    np.testing.assert_allclose(record.force[:, 1], drive, rtol=0.0, atol=1e-8)
    np.testing.assert_allclose(run.actuation[:, 0], record.force[:, 1], rtol=0.0, atol=0.0)


def test_on_a_rocking_base_a_cylinder_holds_the_pendulum_with_the_base_s_terms():
    """The point-mass pendulum hinged on the forward axis x of a base rolling as φ = Φ cos Ωt
    (test_forward_base), held at θ_ref = 0.3 rad by a cylinder from a point of the base,
    a = (0, −0.3, −0.2) m, to the rod at r = 0.5 m below the hinge: the hinge needs
    u = m L² φ̈ + m g L sin(θ_ref + φ) (as the joint's own drive would, test_control), so the push
    is u over the lever g = dℓ/dθ = r (−a_y cos θ − a_z sin θ)/ℓ (by hand, in the base's axes),
    the error stays at the integrator's tolerance and the energy balance of the absolute motion
    closes with the push's work and the base's."""
    from feeder.chain import BaseMotion

    from .test_control import FREQUENCY, HELD, ROLL, held_on_rocking_base
    from .test_forward_base import Harmonic, pendulum

    r, (ay, az) = 0.5, (-0.3, -0.2)
    model = pendulum().model
    _frame(model, "anchor", 0, [0.0, ay, az])
    _frame(model, "eye", 1, [0.0, 0.0, -r])
    dyn = ChainDynamics(
        ClosedChain(model, []), [], elements=[Cylinder(("anchor", "eye"), BORE, ROD, name="lift")],
        base=BaseMotion((Harmonic(3, ROLL, FREQUENCY),)),
    )  # fmt: skip
    spec = _spec("swing", np.linspace(0.0, 2.0, 3), HELD, 0.0, 0.0, element="lift")
    run, record, drive = held_on_rocking_base(dyn, ComputedTorque(dyn, [spec]))
    length = math.hypot(r * math.sin(HELD) - ay, -r * math.cos(HELD) - az)
    lever = r * (-ay * math.cos(HELD) - az * math.sin(HELD)) / length
    # pushes of ≤ 10 N from a state held on the reference to round-off (the base's terms are
    # the run's own): 1e-9 N (measured 2e-13 N)
    np.testing.assert_allclose(record.force[:, 0], drive / lever, rtol=0.0, atol=1e-9)
    # the base's work of 0.6 J in the balance, at rtol 1e-11 (measured 6e-12 J)
    assert np.abs(run.balance()).max() <= 1e-9
