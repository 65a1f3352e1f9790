"""Inverse dynamics on a moving base against MuJoCo, an independent dynamics engine, on the device.

The device's open tree is written as MJCF (a small converter below: one body per joint, nested
as in the Pinocchio model, each with its joint placement, hinge or slide axis and spatial
inertia) and put on a hull: a body carrying six joints at the world, three slides along the level
model axes x, y, z, then three hinges at the model's origin, yaw about the model's up (+y),
pitch about the new left (+z), roll about the new forward (−x): MuJoCo composes a body's joints
in order, so the hull's attitude is R_y(ψ) R_z(θ) R_−x(φ) = V R_z(ψ) R_y(θ) R_x(φ) Vᵀ: the
attitude of :mod:`feeder.chain.model.base` in the model's axes (V the vehicle's axes in them).
The base joints' coordinates are the channels themselves (translations in level model axes, the
Euler angles), so their rates and accelerations are the channels' rates and accelerations.

For each sample MuJoCo gives M q̈ + b (``mj_mulM`` and ``qfrc_bias``: its recursive Newton–Euler
and composite-rigid-body algorithms on the absolute motion, nothing of feeder's
:func:`~feeder.chain.kinematics.tree.on_base`) and the loop's point Jacobian J (``mj_jac`` of the
pin point on the piston's body less on the arm's). The hard constraint equations

    M q̈ + b = Sᵀ τ + Jᵀ λ,   S: the six base joints and the two actuated ones,

are 10 equations in 8 + 3 unknowns; the planar loop leaves its out-of-plane force λ_z
indeterminate (one null direction, in λ only: checked), so lstsq's minimum-norm solution
determines τ and the in-plane λ. τ of the actuated joints are the actuator loads; τ of the base
joints are the generalized forces the mount applies across them: the slides' are the
components of the mount's force along the level axes, the hinges' the components of its moment
about the model's origin (the hinges' common point) along each hinge's axis at that instant.

MuJoCo refuses a massless moving body and the device's base link has no inertia, so both sides
get the same base-link inertia (:data:`BRACKET`, a mount bracket): it enters the mount's wrench
(feeder's base-link term) and, the base's motion being prescribed, not the actuators (checked
against the built-in device). The payload is gripped: the samples are the cycle's gripped ones
(:attr:`~feeder.motion.cycle.CycleKinematics.gripped`), every 50th, with the device's model
(which includes the payload).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin
import pytest

from feeder.chain.dynamics.inverse import ChainDynamics, inverse_dynamics
from feeder.chain.model.base import BaseMotion
from feeder.chain.model.channels import Channels
from feeder.chain.model.closure import ClosedChain
from feeder.chain.model.forces import Table
from feeder.chain.model.hull_table import HullTable
from feeder.chain.model.profiles import Recoil, Slope, Terrain
from feeder.dynamics.models import ACTUATED_JOINTS
from feeder.motion.cycle import feeding_cycle

mujoco = pytest.importorskip("mujoco")

RELATIVE = 1e-9
"""Largest difference relative to the largest load of a comparison. Both sides solve the same
equations of the same rigid bodies in double precision: MuJoCo's M and bias forces are exact
Newton–Euler (no integration, no soft constraints: the closure enters through its Jacobian only),
so only round-off separates them (measured ≤ 5e-14)."""

FORWARD = (-1.0, 0.0, 0.0)
"""The device's vehicle forward axis in its model's axes (the muzzle side); up is +y."""

EVERY = 50
"""Sub-sampling of the gripped part of the cycle (61 samples)."""

BRACKET = pin.Inertia(
    40.0,
    np.array([-0.2, 0.1, 0.05]),
    np.array([[1.2, 0.1, -0.05], [0.1, 1.5, 0.08], [-0.05, 0.08, 0.9]]),
)
"""The base link's inertia given to both sides [kg, m, kg·m² about the CG] (module docstring)."""

BASE_JOINTS = (
    ("hull_x", "slide", (1.0, 0.0, 0.0)),
    ("hull_y", "slide", (0.0, 1.0, 0.0)),
    ("hull_z", "slide", (0.0, 0.0, 1.0)),
    ("hull_yaw", "hinge", (0.0, 1.0, 0.0)),  # up
    ("hull_pitch", "hinge", (0.0, 0.0, 1.0)),  # left = up × forward
    ("hull_roll", "hinge", (-1.0, 0.0, 0.0)),  # forward
)
"""The hull's joints (module docstring), model axes."""

ANGLES = (5, 4, 3)
"""The channels of the hull's hinges, in order: yaw, pitch, roll."""

AXES = {"X": (1.0, 0.0, 0.0), "Y": (0.0, 1.0, 0.0), "Z": (0.0, 0.0, 1.0)}


@dataclass(frozen=True)
class Weave:
    """A hull turning (steady yaw rate, a forward speed) and weaving in all six channels:
    harmonics at different frequencies, so every Coriolis and centripetal term is non-zero."""

    frequency: tuple = (0.7, 0.9, 1.3, 1.1, 0.8, 0.5)  # [Hz] x, y, z, roll, pitch, yaw
    amplitude: tuple = (0.3, 0.2, 0.05, 0.06, 0.05, 0.4)  # [m], [rad]
    phase: tuple = (0.1, 0.7, 1.3, 0.4, 2.0, 0.9)  # [rad]
    drift: tuple = (4.0, 0.0, 0.0, 0.0, 0.0, 0.35)  # [m/s], [rad/s]: driving on, turning left

    def channels(self, t: np.ndarray) -> Channels:
        w, amp = 2.0 * math.pi * np.array(self.frequency), np.array(self.amplitude)
        s, c = np.sin(w * t[:, None] + self.phase), np.cos(w * t[:, None] + self.phase)
        drift = np.array(self.drift)
        return Channels(amp * s + drift * t[:, None], amp * w * c + drift, -amp * w**2 * s)

    def describe(self) -> str:
        return "weaving turn"


def _columns(channels: Channels) -> list[np.ndarray]:
    return [channels.value, channels.rate, channels.acceleration]


def _base(case: str, t: np.ndarray) -> BaseMotion:
    """The base motions compared: a slope, a ride, recoil rocking within the cycle, a weaving turn
    over terrain, and the same turn as a hull table (sampled at the motion's times, where its
    interpolation is exact) on a slope."""
    profiles = {
        "slope": (Slope(pitch=math.radians(10.0), roll=math.radians(-15.0)),),
        "terrain": (Terrain(),),
        "recoil": (Recoil(start=2.0),),  # the gripped samples are t = 1 … 4 s
        "turn": (Terrain(), Weave()),
        "table": (
            Slope(pitch=math.radians(-5.0), roll=math.radians(8.0)),
            HullTable(Table(t, np.hstack(_columns(Weave().channels(t))))),
        ),
    }[case]
    return BaseMotion(profiles, forward=FORWARD)


def _numbers(values) -> str:
    return " ".join(repr(float(x)) for x in np.ravel(values))


def _inertial(inertia: pin.Inertia) -> str:
    if inertia.mass == 0.0:
        return ""
    i = inertia.inertia
    moments = [i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]]
    return (
        f'<inertial mass="{float(inertia.mass)!r}" pos="{_numbers(inertia.lever)}" '
        f'fullinertia="{_numbers(moments)}"/>'
    )


def _joint(model: pin.Model, j: int) -> tuple[str, np.ndarray]:
    """A one-coordinate joint's MJCF type and axis (in its frame)."""
    short = model.joints[j].shortname()
    if short in ("JointModelRevoluteUnaligned", "JointModelPrismaticUnaligned"):
        kind, axis = short[10], model.joints[j].extract().axis
    elif short[:11] in ("JointModelR", "JointModelP") and short[11:] in AXES:
        kind, axis = short[10], AXES[short[11:]]
    else:
        raise NotImplementedError(f"joint {model.names[j]}: {short}")
    return {"R": "hinge", "P": "slide"}[kind], np.asarray(axis, dtype=float)


def _body(model: pin.Model, j: int, children: dict[int, list[int]]) -> str:
    placement = model.jointPlacements[j]
    x, y, z, w = pin.Quaternion(placement.rotation).coeffs()
    kind, axis = _joint(model, j)
    name = model.names[j]
    return (
        f'<body name="{name}" pos="{_numbers(placement.translation)}" '
        f'quat="{_numbers([w, x, y, z])}">'
        f'<joint name="{name}" type="{kind}" axis="{_numbers(axis)}"/>'
        + _inertial(model.inertias[j])
        + "".join(_body(model, c, children) for c in children[j])
        + "</body>"
    )


def mjcf(model: pin.Model) -> str:
    """The tree on the hull (module docstring) as MJCF: no geoms, no contacts, no damping or
    armature, the model's gravity."""
    children = {j: [] for j in range(model.njoints)}
    for j in range(1, model.njoints):
        children[model.parents[j]].append(j)
    hull = "".join(
        f'<joint name="{name}" type="{kind}" axis="{_numbers(axis)}"/>'
        for name, kind, axis in BASE_JOINTS
    )
    tree = "".join(_body(model, c, children) for c in children[0])
    return (
        f'<mujoco><option gravity="{_numbers(model.gravity.linear)}">'
        '<flag contact="disable"/></option><worldbody><body name="hull">'
        f"{hull}{_inertial(model.inertias[0])}{tree}</body></worldbody></mujoco>"
    )


@dataclass(frozen=True)
class Reference:
    """MuJoCo's answer at N samples: hull placement (level model axes), the hinges' world axes
    (N, 3, 3), the base joints' generalized forces (N, 6), the actuated joints' (N, 2), λ in
    world axes (N, 3)."""

    rotation: np.ndarray
    position: np.ndarray
    hinge_axes: np.ndarray
    base: np.ndarray
    actuators: np.ndarray
    closure: np.ndarray


def mujoco_loads(chain: ClosedChain, base: BaseMotion, t, q, v, a) -> Reference:
    """The loads from MuJoCo's M q̈ + b and closure Jacobian (module docstring) of a chain with
    one point closure, λ on the body of its first frame."""
    model = chain.model
    m = mujoco.MjModel.from_xml_string(mjcf(model))
    d = mujoco.MjData(m)
    channels = Channels(*(np.zeros((t.size, 6)) for _ in range(3)))
    for profile in base.profiles:
        channels = channels + profile.channels(t)
    axes = base.vehicle_axes(model.gravity.linear)  # vehicle axes → model axes
    hull = {
        kind: np.hstack(
            [getattr(channels, kind)[:, :3] @ axes.T, getattr(channels, kind)[:, ANGLES]]
        )
        for kind in ("value", "rate", "acceleration")
    }
    dofs = [m.joint(name).dofadr[0] for name, _, _ in BASE_JOINTS]
    qpos = [m.joint(name).qposadr[0] for name, _, _ in BASE_JOINTS]
    device = [
        (m.joint(model.names[j]).qposadr[0], m.joint(model.names[j]).dofadr[0], j)
        for j in range(1, model.njoints)
    ]
    selected = dofs + [m.joint(name).dofadr[0] for name in ACTUATED_JOINTS]
    select = np.zeros((len(selected), m.nv))
    select[np.arange(len(selected)), selected] = 1.0
    frames = [model.frames[i] for i in chain.frame_ids[0]]  # piston_pin, arm_pin
    bodies = [m.body(model.names[frame.parentJoint]).id for frame in frames]
    hinges = [m.joint(name).id for name, kind, _ in BASE_JOINTS if kind == "hinge"]
    out = {key: [] for key in ("rotation", "position", "hinge_axes", "base", "act", "lam")}
    for n in range(t.size):
        acceleration = np.zeros(m.nv)
        d.qpos[qpos], d.qvel[dofs], acceleration[dofs] = (
            hull["value"][n],
            hull["rate"][n],
            hull["acceleration"][n],
        )
        for address, dof, j in device:
            d.qpos[address] = q[n, model.joints[j].idx_q]
            d.qvel[dof] = v[n, model.joints[j].idx_v]
            acceleration[dof] = a[n, model.joints[j].idx_v]
        mujoco.mj_forward(m, d)
        rhs = np.zeros(m.nv)
        mujoco.mj_mulM(m, d, rhs, acceleration)  # M q̈ (mj_fullM's signature changed in 3.x)
        rhs += d.qfrc_bias
        jacobians, points = [], []
        for frame, body in zip(frames, bodies, strict=True):
            point = d.xpos[body] + d.xmat[body].reshape(3, 3) @ frame.placement.translation
            jac = np.zeros((3, m.nv))
            mujoco.mj_jac(m, d, jac, None, point, body)
            jacobians.append(jac)
            points.append(point)
        # The converter's check: the cycle closes the loop in MuJoCo's tree too.
        assert np.linalg.norm(points[0] - points[1]) < 1e-9
        system = np.hstack([select.T, (jacobians[0] - jacobians[1]).T])
        x, _, rank, _ = np.linalg.lstsq(system, rhs, rcond=None)
        assert rank == m.nv  # one null direction: λ along the loop's normal, no τ in it
        null = np.linalg.svd(system)[2][-1]
        assert np.abs(null[: len(selected)]).max() < 1e-12
        assert np.abs(system @ x - rhs).max() <= 1e-12 * np.abs(rhs).max()  # consistent
        out["rotation"].append(d.xmat[m.body("hull").id].reshape(3, 3).copy())
        out["position"].append(d.xpos[m.body("hull").id].copy())
        out["hinge_axes"].append(d.xaxis[hinges].copy())
        out["base"].append(x[:6])
        out["act"].append(x[6 : len(selected)])
        out["lam"].append(x[len(selected) :])
    return Reference(*(np.array(values) for values in out.values()))


@pytest.fixture(scope="module")
def samples(feeder):
    """Times, q, q̇, q̈ (Pinocchio order) of the gripped part of the 30° cycle, every 50th."""
    cycle = feeding_cycle(feeder, math.radians(30.0))
    keep = np.flatnonzero(cycle.gripped == 1)[::EVERY]
    return (
        cycle.t[keep],
        *(feeder.to_pinocchio(getattr(cycle, name)[keep]) for name in ("q", "v", "a")),
    )


@pytest.fixture(scope="module")
def bracketed(feeder) -> ClosedChain:
    """The device with :data:`BRACKET` as its base link's inertia (module docstring)."""
    model = pin.Model(feeder.chain.model)
    model.inertias[0] = BRACKET
    return ClosedChain(model, feeder.chain.closures)


def _check(what: str, actual: np.ndarray, expected: np.ndarray) -> None:
    scale = np.abs(expected).max()
    error = np.abs(actual - expected).max() / scale
    assert error <= RELATIVE, f"{what}: {error:.2e} of {scale:.4g}"


@pytest.mark.parametrize("case", ["slope", "terrain", "recoil", "turn", "table"])
def test_moving_base_loads_match_mujoco(case, feeder, samples, bracketed):
    t, q, v, a = samples
    base = _base(case, t)
    loads = inverse_dynamics(ChainDynamics(bracketed, ACTUATED_JOINTS, base=base), q, v, a, t=t)
    ref = mujoco_loads(bracketed, base, t, q, v, a)
    # MuJoCo's hull is where feeder puts the base: the attitude's Euler convention and axes.
    np.testing.assert_allclose(loads.base.rotation, ref.rotation, rtol=0, atol=1e-12)
    np.testing.assert_allclose(loads.base.position, ref.position, rtol=0, atol=1e-12)

    for i, name in enumerate(ACTUATED_JOINTS):
        _check(name, loads.actuators[name], ref.actuators[:, i])
    slides = loads.mount.level_force  # the slides' axes are the level axes
    hinges = np.einsum("nki,ni->nk", ref.hinge_axes, loads.mount.level_moment)
    _check("mount force (slides)", slides, ref.base[:, :3])
    _check("mount moment (hinges)", hinges, ref.base[:, 3:])
    # The closure forces in the base's axes, the determined (in-plane) rows.
    labels = bracketed.row_labels()
    rows = [i for i, label in enumerate(labels) if label not in loads.indeterminacy.rows]
    assert len(rows) == 2
    moving = np.einsum("nji,nj->ni", ref.rotation, ref.closure)
    _check("closure forces", loads.closure_forces[:, rows], moving[:, rows])

    # The bracket rides on the prescribed base: the built-in device's actuators are the same.
    device = inverse_dynamics(
        ChainDynamics(feeder.chain, ACTUATED_JOINTS, base=base), q, v, a, t=t
    )
    for name in ACTUATED_JOINTS:
        _check(f"{name}, built-in device", device.actuators[name], loads.actuators[name])
