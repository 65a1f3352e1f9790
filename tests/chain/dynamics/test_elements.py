"""Each force element kind against the principles its formulas come from, one element at a time:

(1) its generalized force is the virtual power of the wrenches it applies to the bodies,
    Σ_f J_fᵀ w_f, from the batched path (the inverse dynamics' wrenches) and Pinocchio's frame
    Jacobians, and for a joint spring −τ on its own column;
(2) its elastic part is minus the gradient of its potential energy, by central differences;
(3) the power it reports is that of its non-conservative part, Q·q̇ + (∂E/∂q)·q̇.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from feeder.chain import ClosedChain, Closure, load_closed_chain, load_mechanism, read_spec
from feeder.chain.dynamics.elements import (
    BoundElements,
    JointElement,
    LineElement,
    LoadElement,
    bind,
    force_unit,
)
from feeder.chain.kinematics.tree import tree_motion
from feeder.chain.model.forces import Cylinder, JointSpring, Load, Spring, Table
from feeder.chain.model.jacobians import frame_jacobian
from feeder.chain.readers.urdf import build_model
from feeder.exceptions import InputError

from ...conftest import REPO

VIRTUAL_POWER = 1e-12
"""Relative to the largest |Q|: the same forces through Pinocchio's Jacobians and through the
batched tree recursion, equal to round-off (≤ 1.1e-15 measured)."""

STEP = 1e-5
"""[rad or m] Central-difference step on each coordinate."""

GRADIENT = 1e-7
"""Relative to the largest |Q|, for the energy's gradient and, times Σ|q̇|, for the power: at
h = 1e-5 the central difference's truncation h² E'''/6 (lengths ~0.1 m: ~1e-12) is below its
round-off ε E / h (E ~ 0.15 J against forces ~0.02 N·m: ~2e-10 relative, the measured worst);
a wrong sign, factor or missing term is of order one."""

TABLE = Table(np.array([0.0, 0.5, 1.0]), np.array([0.0, 0.4, -0.2]))
"""A one-column table in time, for a push [N] or a pressure (scaled)."""

CASES = {
    "spring": (
        "four_bar",
        Spring(("rocker_tip", "crank"), stiffness=40.0, rest_length=0.09, damping=0.5, force=0.3),
        Spring(("rocker_tip", "crank"), stiffness=40.0, rest_length=0.09),
    ),
    "spring_to_ground": (
        "four_bar",
        Spring(("ground", "coupler_tip"), stiffness=25.0, rest_length=0.05, force=TABLE),
        Spring(("ground", "coupler_tip"), stiffness=25.0, rest_length=0.05),
    ),
    "cylinder": (
        "four_bar",
        Cylinder(
            ("coupler_tip", "crank"),
            bore=0.01,
            rod=0.004,
            pressure=lambda t: 2e5 * t,
            rod_pressure=1e4,
            damping=0.3,
        ),
        None,
    ),
    "joint_spring_revolute": (
        "four_bar",
        JointSpring("rocker_joint", stiffness=0.2, rest=1.0, damping=0.002, preload=0.01),
        JointSpring("rocker_joint", stiffness=0.2, rest=1.0, preload=0.01),
    ),
    "joint_spring_prismatic": (
        "slider_crank",
        JointSpring("slider_joint", stiffness=30.0, rest=0.2, damping=0.5, preload=-0.4),
        JointSpring("slider_joint", stiffness=30.0, rest=0.2, preload=-0.4),
    ),
    "joint_spring_on_a_moving_body": (
        "arm_slider",
        JointSpring("slide_joint", stiffness=30.0, rest=0.1, damping=0.5, preload=0.4),
        JointSpring("slide_joint", stiffness=30.0, rest=0.1, preload=0.4),
    ),
    "load": (
        "slider_crank",
        Load("rod_tip", force=(0.3, -2.0, 0.1), moment=(0.01, 0.0, 0.02)),
        None,
    ),
    "load_table": (
        "four_bar",
        Load("coupler", table=Table(np.array([0.0, 1.0]), np.arange(12.0).reshape(2, 6) / 10)),
        None,
    ),
}
"""Per kind: the chain, the element, and its elastic part (no damper, push or pressure), or None
for a kind without potential energy."""


_INERTIAL = (
    '<inertial><origin xyz="0.05 0 0" rpy="0 0 0"/><mass value="0.3"/>'
    '<inertia ixx="1e-4" ixy="0" ixz="0" iyy="1e-3" iyz="0" izz="1e-3"/></inertial>'
)
ARM_SLIDER = (
    f'<robot name="arm_slider"><link name="ground"/><link name="arm">{_INERTIAL}</link>'
    '<joint name="arm_joint" type="revolute"><origin xyz="0 0 0" rpy="0 0 0"/>'
    '<parent link="ground"/><child link="arm"/><axis xyz="0 0 1"/>'
    '<limit lower="-10" upper="10" effort="1" velocity="1"/></joint>'
    f'<link name="slider">{_INERTIAL}</link>'
    '<joint name="slide_joint" type="prismatic"><origin xyz="0.1 0.05 0" rpy="0.3 0 0.2"/>'
    '<parent link="arm"/><child link="slider"/><axis xyz="1 0 0"/>'
    '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>'
)
"""A prismatic joint on a turning arm, off the arm's origin: its spring's force on the slider
has a moment about the arm's frame, which the virtual power sees."""


@pytest.fixture(scope="module")
def chains():
    four_bar = load_closed_chain(
        REPO / "examples" / "four_bar" / "four_bar.urdf",
        [Closure("coupler_tip", "rocker_tip", "revolute")],
    )
    slider_crank = load_mechanism(read_spec(REPO / "examples" / "slider_crank" / "closures.toml"))
    arm_slider = ClosedChain(build_model(ARM_SLIDER, "<arm with a slider>"), [])
    return {"four_bar": four_bar, "slider_crank": slider_crank, "arm_slider": arm_slider}


def _state(model: pin.Model, seed: int) -> tuple[np.ndarray, np.ndarray, float]:
    """A seeded state (q, v) and time t [s]; the loop need not be closed for one element."""
    rng = np.random.default_rng(seed)
    q = pin.neutral(model) + rng.uniform(-0.6, 0.6, model.nq)
    return q, rng.normal(size=model.nv), 0.3


def _energy_gradient(alone: BoundElements, q: np.ndarray) -> np.ndarray:
    """∂E/∂q (nv,) by central differences of :data:`STEP` along the tangent space."""
    model = alone.model
    gradient = np.empty(model.nv)
    for k in range(model.nv):
        dq = np.zeros(model.nv)
        dq[k] = STEP
        gradient[k] = (
            alone.energy(pin.integrate(model, q, dq)) - alone.energy(pin.integrate(model, q, -dq))
        ) / (2.0 * STEP)
    return gradient


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("case", list(CASES))
def test_an_elements_generalized_force_is_its_wrenches_and_its_energy(chains, case, seed):
    name, element, elastic = CASES[case]
    chain = chains[name]
    model, data = chain.model, chain.model.createData()
    q, v, t = _state(model, seed)
    alone = BoundElements(chain, [element])
    force, power = alone.generalized(q, v, t)
    scale = np.abs(force).max()
    assert scale > 1e-3  # the state loads the element

    # (1) the virtual power of its wrenches
    motion = tree_motion(model, q[None], v[None])
    terms, reported = alone.wrenches(motion, q[None], v[None], np.array([t]))
    pin.computeJointJacobians(model, data, q)
    virtual = sum(
        frame_jacobian(model, data, f, pin.LOCAL_WORLD_ALIGNED).T @ w[0] for f, w in terms
    )
    assert np.abs(force - virtual).max() <= VIRTUAL_POWER * scale
    if case.startswith("joint_spring"):
        column = np.zeros(model.nv)
        iv = model.joints[model.getJointId(element.joint)].idx_v
        column[iv] = -reported[element.name][0]
        assert np.array_equal(force, column)

    # (2) the elastic part is −∂E/∂q, and dampers, pushes and pressures store nothing
    gradient = np.zeros(model.nv)
    if elastic is not None:
        alone_elastic = BoundElements(chain, [elastic])
        gradient = _energy_gradient(alone_elastic, q)
        elastic_force, elastic_power = alone_elastic.generalized(q, np.zeros(model.nv), t)
        assert np.abs(elastic_force + gradient).max() <= GRADIENT * scale
        assert elastic_power == 0.0
        assert alone.energy(q) == alone_elastic.energy(q) != 0.0
    else:
        assert alone.energy(q) == 0.0

    # (3) its reported power: all but the elastic part's
    assert power == pytest.approx(force @ v + gradient @ v, abs=GRADIENT * scale * np.abs(v).sum())


def test_every_kind_is_bound_by_its_own_class_and_reports_in_its_unit(chains):
    four_bar = chains["four_bar"]
    kinds = {LineElement: ("spring", "cylinder"), JointElement: ("joint_spring_revolute",),
             LoadElement: ("load_table",)}  # fmt: skip
    for cls, cases in kinds.items():
        for case in cases:
            assert type(bind(four_bar, CASES[case][1])) is cls
    with pytest.raises(InputError, match="not a force element"):
        bind(four_bar, math.pi)
    units = {"spring": "N", "cylinder": "N", "joint_spring_revolute": "N·m",
             "joint_spring_prismatic": "N"}  # fmt: skip
    for case, unit in units.items():
        name, element, _ = CASES[case]
        assert force_unit(chains[name].model, element) == unit
