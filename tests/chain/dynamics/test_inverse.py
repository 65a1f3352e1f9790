"""Inverse dynamics of any closed chain: against Pinocchio's constrained forward dynamics, across
cut kinds, and its refusals.

The independent checks: (1) the loads it computes, fed to Pinocchio's ``constraintDynamics`` with
the chain's own ``RigidConstraintModel`` s, give back the prescribed accelerations; (2) the same
four-bar cut at a pin (revolute or point cut) or in the middle of its rocker (a weld) needs the
same drive torque; (3) every passive joint carries no load along its axis.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from feeder.chain import ClosedChain, Closure, load_closed_chain
from feeder.chain.assembly.partition import Partition
from feeder.chain.assembly.tracking import track
from feeder.chain.dynamics.inverse import ChainDynamics, inverse_dynamics
from feeder.chain.dynamics.loads_solve import (
    MAX_FORCE_GAIN,
    _shortcut,
    _solve,
    load_gain,
    load_rank,
)
from feeder.chain.readers.urdf import build_model
from feeder.device import load_feeder
from feeder.exceptions import InputError, SingularPoseError, UnreachablePoseError
from feeder.motion import CycleSpec, feeding_cycle

from ...conftest import REPO

FOUR_BAR = REPO / "examples" / "four_bar" / "four_bar.urdf"
C = 0.080  # rocker length [m]
BAR = 7850.0 * 0.020 * 0.010  # [kg/m]

ACCELERATION = 1e-10
"""[rad/s²] The issue's bound for Pinocchio's forward dynamics fed with our loads: both solve the
same equations to round-off (~1e-13 here, with a 1e-10 proximal regularisation)."""

RELATIVE = 1e-9
"""Loads of one mechanism computed through different cuts: round-off (~1e-14) and Newton's
1e-13 residual, relative to the largest load."""

PASSIVE = 1e-12
"""[N·m, N] Load along a passive joint's axis, and the minimum-norm out-of-plane cut force and
tilting moments: zero to round-off of ~0.1 N·m moments and ~3 N forces."""

BALANCE = 1e-11
"""[N] Newton's law for one body from two computations of ~3 N forces: round-off ~1e-14."""

SHARE = 1e-12
"""Relative: the stiffness split is one linear solve; round-off ~1e-15 of the force."""

HELD = 1e-12
"""[m] Relative to the largest force, times 1 m for the moments (the forearm's lever arms are
under a metre): one body's Newton–Euler terms evaluated two ways, round-off ~1e-15."""


def _gravity(chain: ClosedChain) -> ClosedChain:
    chain.model.gravity = pin.Motion(np.array([0.0, -9.81, 0.0]), np.zeros(3))
    return chain


def _motion(chain: ClosedChain, samples: int = 21):
    """One crank turn with a rising speed, tracked on the open branch."""
    partition = Partition(chain, ["crank_joint"])
    t = np.linspace(0.0, 1.0, samples)
    x = (math.radians(40.0) + 2.0 * math.pi * t + 1.5 * t**2)[:, None]
    dx = (2.0 * math.pi + 3.0 * t)[:, None]
    ddx = np.full_like(x, 3.0)
    guess = np.array([x[0, 0], -0.35, 1.0])
    motion = track(partition, partition.assemble(guess), x, dx, ddx)
    return motion.q, motion.v, motion.a


@pytest.fixture(scope="module", params=["revolute", "point"])
def four_bar(request):
    return _gravity(
        load_closed_chain(FOUR_BAR, [Closure("coupler_tip", "rocker_tip", request.param)])
    )


def test_loads_give_back_the_accelerations_in_pinocchio(four_bar):
    q, v, a = _motion(four_bar)
    loads = inverse_dynamics(ChainDynamics(four_bar, ["crank_joint"]), q, v, a)
    model, data = four_bar.model, four_bar.model.createData()
    models, datas = four_bar.constraint_models, four_bar.constraint_datas
    pin.initConstraintDynamics(model, data, models, datas)
    settings = pin.ProximalSettings(1e-14, 1e-10, 200)
    for k in range(q.shape[0]):
        tau = np.zeros(model.nv)
        tau[0] = loads.actuators["crank_joint"][k]
        forward = pin.constraintDynamics(model, data, q[k], v[k], tau, models, datas, settings)
        assert np.abs(forward - a[k]).max() <= ACCELERATION


def test_passive_joints_carry_nothing_along_their_axes(four_bar):
    q, v, a = _motion(four_bar)
    loads = inverse_dynamics(ChainDynamics(four_bar, ["crank_joint"]), q, v, a)
    for name in ("coupler_joint", "rocker_joint"):
        assert np.abs(loads.joints[name].drive).max() <= PASSIVE
    np.testing.assert_allclose(
        loads.joints["crank_joint"].drive, loads.actuators["crank_joint"], rtol=0, atol=PASSIVE
    )


def test_closure_force_balances_the_rocker(four_bar):
    """Newton's law for the rocker (the body of the cut's second frame), with Pinocchio's
    kinematics: ground-on-rocker reaction − closure force on the first frame's body + m g =
    m a_G. The closure force's out-of-plane and tilting parts are zero (minimum norm)."""
    q, v, a = _motion(four_bar)
    loads = inverse_dynamics(ChainDynamics(four_bar, ["crank_joint"]), q, v, a)
    (wrench,) = loads.closures.values()
    model, data = four_bar.model, four_bar.model.createData()
    joint = model.getJointId("rocker_joint")
    inertia = model.inertias[joint]
    for k in range(q.shape[0]):
        pin.forwardKinematics(model, data, q[k], v[k], a[k])
        rotation = data.oMi[joint].rotation
        velocity, acceleration = data.v[joint], data.a[joint]
        omega, alpha = rotation @ velocity.angular, rotation @ acceleration.angular
        origin = rotation @ (acceleration.linear + np.cross(velocity.angular, velocity.linear))
        lever = rotation @ inertia.lever
        a_g = origin + np.cross(alpha, lever) + np.cross(omega, np.cross(omega, lever))
        balance = loads.joints["rocker_joint"].force[k] - wrench.force[k]
        expected = inertia.mass * (a_g - model.gravity.linear)
        np.testing.assert_allclose(balance, expected, rtol=0, atol=BALANCE)
    assert np.abs(wrench.force[:, 2]).max() <= PASSIVE
    assert np.abs(wrench.moment[:, :2]).max() <= PASSIVE


def _bar(name: str, length: float, start: float, mass: float) -> str:
    """A 20 × 10 mm bar link of ``mass`` [kg] from x = start to start + length (the examples'
    section, so that two halves have the inertia of the whole bar)."""
    width, thickness = 0.020, 0.010
    centre = start + length / 2.0
    ixx = mass * (width**2 + thickness**2) / 12.0
    iyy = mass * (length**2 + thickness**2) / 12.0
    izz = mass * (length**2 + width**2) / 12.0
    return (
        f'<link name="{name}"><inertial><origin xyz="{centre!r} 0 0" rpy="0 0 0"/>'
        f'<mass value="{mass!r}"/><inertia ixx="{ixx!r}" ixy="0" ixz="0" iyy="{iyy!r}" iyz="0" '
        f'izz="{izz!r}"/></inertial></link>'
    )


def weld_four_bar() -> ClosedChain:
    """The example four-bar with its rocker cut in the middle: the half at the ground pivot and
    the half at the coupler, welded back together (same masses and inertias as one bar)."""
    source = FOUR_BAR.read_text()
    rocker_start = source.index('  <link name="rocker">')
    rocker_end = source.index("</robot>")
    half = BAR * C / 2.0
    halves = (
        _bar("rocker_a", C / 2.0, 0.0, half)
        + '<joint name="rocker_joint" type="revolute"><origin xyz="0.1 0 0" rpy="0 0 0"/>'
        '<parent link="ground"/><child link="rocker_a"/><axis xyz="0 0 1"/>'
        '<limit lower="-12.6" upper="12.6" effort="1000" velocity="100"/></joint>'
        '<link name="rocker_mid_a"/><joint name="rocker_mid_a_joint" type="fixed">'
        f'<origin xyz="{C / 2!r} 0 0" rpy="0 0 0"/><parent link="rocker_a"/>'
        '<child link="rocker_mid_a"/></joint>'
        + _bar("rocker_b", C / 2.0, 0.0, half)
        + '<joint name="rocker_b_joint" type="revolute"><origin xyz="0.12 0 0" rpy="0 0 0"/>'
        '<parent link="coupler"/><child link="rocker_b"/><axis xyz="0 0 1"/>'
        '<limit lower="-12.6" upper="12.6" effort="1000" velocity="100"/></joint>'
        '<link name="rocker_mid_b"/><joint name="rocker_mid_b_joint" type="fixed">'
        f'<origin xyz="{C / 2!r} 0 0" rpy="0 0 {math.pi!r}"/><parent link="rocker_b"/>'
        '<child link="rocker_mid_b"/></joint>'
    )
    xml = source[:rocker_start] + halves + source[rocker_end:]
    model = build_model(xml, "<weld four-bar>")
    return _gravity(ClosedChain(model, [Closure("rocker_mid_a", "rocker_mid_b", "weld")]))


def test_a_weld_cut_needs_the_same_torque_as_a_pin_cut(four_bar):
    q, v, a = _motion(four_bar)
    pinned = inverse_dynamics(ChainDynamics(four_bar, ["crank_joint"]), q, v, a)
    welded = weld_four_bar()
    partition = Partition(welded, ["crank_joint"])
    # Same motion: crank and coupler as in the pinned chain, the halves from the rocker angle.
    index = {
        welded.model.names[j]: welded.model.joints[j].idx_q for j in range(1, welded.model.njoints)
    }
    guess = np.zeros(welded.model.nq)
    guess[index["crank_joint"]], guess[index["coupler_joint"]] = q[0, 0], q[0, 1]
    guess[index["rocker_joint"]] = q[0, 2]
    guess[index["rocker_b_joint"]] = q[0, 2] - q[0, 0] - q[0, 1] + math.pi
    x = q[:, :1]
    welded_motion = track(partition, partition.assemble(guess), x, v[:, :1], a[:, :1])
    qw, vw, aw = welded_motion.q, welded_motion.v, welded_motion.a
    loads = inverse_dynamics(ChainDynamics(welded, ["crank_joint"]), qw, vw, aw)
    torque = pinned.actuators["crank_joint"]
    scale = np.abs(torque).max()
    np.testing.assert_allclose(
        loads.actuators["crank_joint"], torque, rtol=0, atol=RELATIVE * scale
    )
    assert {label.split(":")[1] for label in loads.indeterminacy.rows} == {"fz", "mx", "my"}


def test_stiffness_splits_an_indeterminate_force(tmp_path):
    """Two bearings of one pin, as two point cuts at the same place (a second pair of frames on
    the pin's axis: the same frames twice are refused as one loop given twice), share its force
    by their stiffness (3 : 1 here), a redundancy the rigid model cannot resolve alone."""
    text = FOUR_BAR.read_text(encoding="utf-8")
    second = "".join(
        f'<link name="{body}_bearing"/><joint name="{body}_bearing_joint" type="fixed">'
        f'<origin xyz="{x} 0 0" rpy="0 0 0"/><parent link="{body}"/>'
        f'<child link="{body}_bearing"/></joint>'
        for body, x in (("coupler", 0.12), ("rocker", 0.08))  # the tips' offsets in the URDF
    )
    urdf = tmp_path / "four_bar.urdf"
    urdf.write_text(text.replace("</robot>", second + "</robot>"), encoding="utf-8")
    closures = [
        Closure("coupler_tip", "rocker_tip", name="stiff"),
        Closure("coupler_bearing", "rocker_bearing", name="soft"),
    ]
    chain = _gravity(load_closed_chain(urdf, closures))
    q, v, a = _motion(chain)
    stiffness = {"stiff": [3.0, 3.0, 3.0], "soft": [1.0, 1.0, 1.0]}
    loads = inverse_dynamics(ChainDynamics(chain, ["crank_joint"], stiffness), q, v, a)
    stiff, soft = loads.closures["stiff"].force, loads.closures["soft"].force
    np.testing.assert_allclose(stiff, 3.0 * soft, rtol=0, atol=SHARE * np.abs(stiff).max())
    assert {label.split(":")[0] for label in loads.indeterminacy.rows} == {"stiff", "soft"}


def test_a_held_part_that_is_its_whole_body_carries_the_joint_reaction():
    """The wrench that holds a part (:meth:`ChainLoads.held_wrench`) of the device's forearm, a
    leaf body with no cut and no external load on it: taken as the forearm's whole inertia, it
    is the forearm joint's reaction, its moment moved from the centre of gravity to the joint."""
    feeder = load_feeder("projectile")
    cycle = feeding_cycle(feeder, math.radians(30.0), CycleSpec(rate=100.0))
    q, v, a = (feeder.to_pinocchio(x) for x in (cycle.q, cycle.v, cycle.a))
    dyn = ChainDynamics(feeder.chain, ["piston_joint", "forearm_joint"])
    loads = inverse_dynamics(dyn, q, v, a)
    model = feeder.model
    joint = model.getJointId("forearm_joint")
    inertia = model.inertias[joint]
    force, moment = loads.held_wrench(joint, inertia)
    reaction = loads.joints["forearm_joint"]
    lever = np.einsum("nij,j->ni", loads.motion.rotation[joint], inertia.lever)
    scale = np.abs(reaction.force).max()
    np.testing.assert_allclose(force, reaction.force, rtol=0, atol=HELD * scale)
    np.testing.assert_allclose(
        moment + np.cross(lever, force), reaction.moment, rtol=0, atol=HELD * scale
    )
    np.testing.assert_array_equal(loads.gravity, model.gravity.linear)


def test_refusals(four_bar):
    q, v, a = _motion(four_bar)
    dyn = ChainDynamics(four_bar, ["crank_joint"])
    with pytest.raises(UnreachablePoseError, match="does not close"):
        inverse_dynamics(dyn, q + [0.0, 0.01, 0.0], v, a)
    with pytest.raises(InputError, match="velocities of sample 0 open the loops"):
        inverse_dynamics(dyn, q, v + [0.0, 1.0, 0.0], a)
    with pytest.raises(InputError, match="shape"):
        inverse_dynamics(dyn, q[:, :2], v, a)
    with pytest.raises(InputError, match="finite"):
        inverse_dynamics(dyn, q, v * np.nan, a)
    with pytest.raises(InputError, match="no joint 'motor'"):
        ChainDynamics(four_bar, ["motor"])
    with pytest.raises(InputError, match="cannot produce the motion"):
        inverse_dynamics(ChainDynamics(four_bar, []), q, v, a)
    with pytest.raises(SingularPoseError, match="not determined"):
        inverse_dynamics(ChainDynamics(four_bar, ["crank_joint", "rocker_joint"]), q, v, a)
    with pytest.raises(InputError, match="unknown closure"):
        ChainDynamics(four_bar, ["crank_joint"], {"other": [1.0, 1.0, 1.0]})


def test_near_a_dead_centre_the_loads_are_refused(four_bar):
    """Driven by its rocker, the crank-rocker has a dead centre where crank and coupler line up
    (the rocker's end of travel): the drive loads grow without bound there, and are refused
    near it rather than returned huge."""
    chain = _gravity(
        load_closed_chain(FOUR_BAR, [Closure("coupler_tip", "rocker_tip", "revolute")])
    )
    a, b, c, d = 0.040, 0.120, 0.080, 0.100
    theta2 = math.acos(((a + b) ** 2 + d**2 - c**2) / (2 * (a + b) * d))
    theta4 = math.atan2((a + b) * math.sin(theta2), (a + b) * math.cos(theta2) - d)
    rocker = Partition(chain, ["rocker_joint"], max_gain=1e12)  # let assembly reach it
    dyn = ChainDynamics(chain, ["rocker_joint"])
    still = np.zeros((1, 3))
    far = rocker.assemble(np.array([theta2 - 0.01, 0.01, theta4 + 0.1]))
    assert np.isfinite(
        inverse_dynamics(dyn, far[None], still, still).actuators["rocker_joint"]
    ).all()
    for inside in (1e-7, 1e-9):
        q = rocker.assemble(np.array([theta2 - 0.01, 0.01, theta4 + inside]))
        with pytest.raises(SingularPoseError, match="singular pose"):
            inverse_dynamics(dyn, q[None], still, still)
    # in a motion, the error names the first sample refused, for the caller to give its time
    near = rocker.assemble(np.array([theta2 - 0.01, 0.01, theta4 + 1e-7]))
    motion = np.array([far, far, near, near])
    with pytest.raises(SingularPoseError, match=r"^sample 2 is at or near") as caught:
        inverse_dynamics(dyn, motion, np.zeros((4, 3)), np.zeros((4, 3)))
    assert caught.value.sample == 2


def test_the_gain_of_one_pose_is_the_one_the_loads_check():
    """load_gain (a forward run's check after every step) is the condition number the load
    solve refuses above MAX_FORCE_GAIN: below it at a pose the loads are given, above it near
    the rocker-driven dead centre they are refused."""
    chain = _gravity(
        load_closed_chain(FOUR_BAR, [Closure("coupler_tip", "rocker_tip", "revolute")])
    )
    a, b, c, d = 0.040, 0.120, 0.080, 0.100
    theta2 = math.acos(((a + b) ** 2 + d**2 - c**2) / (2 * (a + b) * d))
    theta4 = math.atan2((a + b) * math.sin(theta2), (a + b) * math.cos(theta2) - d)
    rocker = Partition(chain, ["rocker_joint"], max_gain=1e12)
    dyn = ChainDynamics(chain, ["rocker_joint"])
    far = rocker.assemble(np.array([theta2 - 0.01, 0.01, theta4 + 0.1]))
    rank = load_rank(dyn, far)
    assert rank == 3  # one drive and two independent rows of the planar revolute cut
    still = np.zeros((1, 3))
    for inside, refused in ((0.1, False), (1e-3, False), (1e-7, True)):
        q = rocker.assemble(np.array([theta2 - 0.01, 0.01, theta4 + inside]))
        gain = load_gain(dyn, q, rank)
        assert (gain > MAX_FORCE_GAIN) == refused, (inside, gain)
        if refused:
            with pytest.raises(SingularPoseError):
                inverse_dynamics(dyn, q[None], still, still)
        else:
            inverse_dynamics(dyn, q[None], still, still)


@pytest.mark.parametrize(("rows", "columns"), [(6, 6), (6, 9), (9, 6)])
def test_the_shortcut_takes_only_well_conditioned_samples(rows, columns):
    """The decomposition-free shortcut of the load solve, square (A⁻¹), wide (Aᵀ (A Aᵀ)⁻¹) and
    tall ((Aᵀ A)⁻¹ Aᵀ, a leg's equations): a well-conditioned sample gets the minimum-norm
    least-squares solution (SVD's, to round-off); a sample with two equal rows — columns for a
    tall one — (where LU may raise) or two equal to round-off (where inv returns garbage rather
    than raising) never passes, and does not keep the good sample from passing."""
    rng = np.random.default_rng(3)
    good = rng.normal(size=(rows, columns)) + 3.0 * np.eye(rows, columns)
    equal, near = good.copy(), good.copy()
    last = min(rows, columns) - 1
    for matrix, noise in ((equal, 0.0), (near, 1e-15)):
        vectors = matrix.T if rows > columns else matrix  # the short side's: rank lost there
        vectors[last] = vectors[last - 1] + noise * rng.normal(size=vectors.shape[1])
    fast, inverse = _shortcut(np.stack([good, equal, near]))
    assert fast.tolist() == [True, False, False]
    rhs = rng.normal(size=rows)
    # cond(good) ~ 10: the shortcut's error is ~cond² ε at most (normal equations).
    assert np.allclose(inverse[0] @ rhs, np.linalg.pinv(good) @ rhs, rtol=0.0, atol=1e-12)


def test_a_tall_system_solved_by_the_shortcut_is_checked_for_consistency():
    """More equations than unknowns (9 × 6): the left inverse's least-squares answer is the
    solution where the equations have one (x recovered to round-off, cond ~ 10), and the
    actuated joints are refused where they have none (a right-hand side off A's range) — at a
    sample that only the shortcut solves (64 samples: the structural checks take every other)."""
    rng = np.random.default_rng(4)
    system = np.repeat((rng.normal(size=(9, 6)) + 3.0 * np.eye(9, 6))[None], 64, axis=0)
    x = rng.normal(size=(64, 6))
    rhs = np.einsum("nij,nj->ni", system, x)
    terms = np.abs(rhs).max(axis=1)
    assert _shortcut(system)[0].all()  # it is the shortcut that answers
    assert np.allclose(_solve(system, rhs, 1, lambda: terms), x, rtol=0.0, atol=1e-12)
    off = rhs.copy()
    off[1] += 1e-3 * np.linalg.svd(system[1])[0][:, -1]  # orthogonal to the range of A
    with pytest.raises(InputError, match="cannot produce the motion"):
        _solve(system, off, 1, lambda: terms)


def test_loads_spread_over_flagged_samples_keep_their_motion_and_indeterminacy(four_bar):
    """A forward run that flags samples spreads the loads of the others over every sample
    (:func:`~feeder.chain.dynamics.singular.spread`, zero at the flagged ones): the motion the
    loads carry is spread with them (a held part's wrench has every sample), and the
    indeterminacy is that of the spread poses, not the kept ones' (the kinematics the inverse
    dynamics computed for it belong to other poses and are not used)."""
    from feeder.chain.dynamics.indeterminacy import indeterminacy
    from feeder.chain.dynamics.singular import spread

    q, v, a = _motion(four_bar, 41)
    keep = np.ones(q.shape[0], dtype=bool)
    keep[[3, 17, 18]] = False
    dyn = ChainDynamics(four_bar, ["crank_joint"])
    kept = inverse_dynamics(dyn, q[keep], v[keep], a[keep])
    loads = spread(kept, keep)
    joint = four_bar.model.getJointId("rocker_joint")
    held = loads.held_wrench(joint, four_bar.model.inertias[joint])
    own = kept.held_wrench(joint, four_bar.model.inertias[joint])
    for spread_out, kept_out in zip(held, own, strict=True):
        assert spread_out.shape == (q.shape[0], 3)
        np.testing.assert_array_equal(spread_out[keep], kept_out)
    assert loads.kinematics is None  # the kept poses' kinematics: not the spread poses'
    assert loads.indeterminacy == indeterminacy(four_bar, loads.q, loads.reach)
    # the tree's joint-first arrays spread along their samples, even where as many samples
    # are kept as the tree has joints (a first axis of that length is not the samples')
    joints = four_bar.model.njoints
    few = np.zeros(q.shape[0], dtype=bool)
    few[5 : 5 + joints] = True
    kept = inverse_dynamics(dyn, q[few], v[few], a[few])
    motion = spread(kept, few).motion
    for name in ("rotation", "origin", "omega", "alpha", "velocity", "acceleration"):
        values, own = getattr(motion, name), getattr(kept.motion, name)
        assert values.shape == (joints, q.shape[0], *own.shape[2:])
        np.testing.assert_array_equal(values[:, few], own)
        assert not values[:, ~few].any()
    assert motion.angular_columns.shape == (q.shape[0], 3, four_bar.model.nv)
    whole = inverse_dynamics(dyn, q, v, a)
    assert whole.indeterminacy == indeterminacy(four_bar, q, whole.reach)  # its own kinematics
