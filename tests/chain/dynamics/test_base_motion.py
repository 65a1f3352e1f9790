"""Inverse dynamics on a moving base, against independent computations:

* a base with a constant acceleration a is the same mechanism standing with gravity g − a;
* a pendulum on a base turning at a constant rate, against the rotating-frame terms written by
  hand (centrifugal, Coriolis, gyroscopic);
* a slope of zero changes nothing, bit for bit;
* the mount's wrench is the whole mechanism's rate of momentum less gravity and the external
  loads, from Pinocchio's centroidal momentum of the same model on a free-flyer root whose motion
  is the base's (a different algorithm: no Newton–Euler recursion of feeder's).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from feeder.chain import ClosedChain, Closure, load_closed_chain
from feeder.chain.dynamics.inverse import ChainDynamics, inverse_dynamics
from feeder.chain.model.base import BaseMotion
from feeder.chain.model.channels import Channels
from feeder.chain.model.forces import Load, Spring
from feeder.chain.model.profiles import Recoil, Slope, Terrain
from feeder.chain.readers.urdf import build_model
from feeder.exceptions import InputError

from ..model.test_base import Tumble
from .test_inverse import FOUR_BAR, _gravity, _motion

ROUND_OFF = 1e-12
"""Relative to the loads' scale: the same equations summed in another order (~1e-15 each)."""


class _Profile:
    """A hull motion given by its channels' functions of time (value, rate, acceleration)."""

    def __init__(self, channels):
        self._channels = channels

    def channels(self, t):
        return Channels(*self._channels(np.asarray(t, dtype=float)))

    def describe(self):
        return "test profile"


def _constant_acceleration(acceleration):
    a = np.asarray(acceleration, dtype=float)
    return _Profile(
        lambda t: (
            0.5 * a * t[:, None] ** 2 * [1, 1, 1, 0, 0, 0],
            a * t[:, None] * [1, 1, 1, 0, 0, 0],
            np.tile(np.r_[a[:3], 0, 0, 0], (t.size, 1)),
        )
    )


def _four_bar():
    return _gravity(
        load_closed_chain(FOUR_BAR, [Closure("coupler_tip", "rocker_tip", "revolute")])
    )


def _all_loads(loads):
    """Every computed load as one flat array."""
    parts = [*loads.actuators.values(), loads.closure_forces]
    for wrench in loads.joints.values():
        parts += [wrench.force, wrench.moment]
    parts += [loads.mount.force, loads.mount.moment]
    return np.concatenate([np.ravel(p) for p in parts])


def test_constant_acceleration_is_gravity_less_the_acceleration():
    chain = _four_bar()
    q, v, a = _motion(chain)
    t = np.linspace(0.0, 1.0, q.shape[0])
    acceleration = np.array([3.0, -1.5, 4.0])  # forward, left, up [m/s²]
    base = BaseMotion((_constant_acceleration(np.r_[acceleration, 0, 0, 0]),))
    moving = inverse_dynamics(ChainDynamics(chain, ["crank_joint"], base=base), q, v, a, t=t)
    axes = base.vehicle_axes(chain.model.gravity.linear)  # forward x, up y, left −z
    still = _four_bar()
    still.model.gravity = pin.Motion(chain.model.gravity.linear - axes @ acceleration, np.zeros(3))
    standing = inverse_dynamics(ChainDynamics(still, ["crank_joint"]), q, v, a)
    expected = _all_loads(standing)
    assert np.abs(_all_loads(moving) - expected).max() <= ROUND_OFF * np.abs(expected).max()


PENDULUM = """<robot name="pendulum">
  <link name="base"/>
  <link name="rod">
    <inertial><origin xyz="0 -{length} 0"/><mass value="{m}"/>
      <inertia ixx="{jp}" iyy="{ja}" izz="{jp}" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="hinge" type="revolute"><parent link="base"/><child link="rod"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
</robot>"""


def test_pendulum_on_a_turntable_by_hand():
    """A rod hinged at the base's origin about the horizontal z, the base turning about the
    vertical y at Ω. With e = (sin θ, −cos θ, 0) the rod's axis, n = (cos θ, sin θ, 0),
    K = J_p + m l² and J_a the rod's axial inertia, in the turning axes:

    * hinge moment τ = K θ̈ − Ω² (K − J_a) sin θ cos θ + m g l sin θ;
    * mount force m (a_G − g), a_G = l θ̈ n − l θ̇² e − Ω² l sin θ x̂ − 2 Ω l θ̇ cos θ ẑ
      (relative, centrifugal and Coriolis accelerations);
    * mount moment about the origin (a fixed point) I_O ω̇ + ω × I_O ω − l e × m g, with
      ω = Ω ŷ + θ̇ ẑ and ω̇ = θ̈ ẑ + Ω θ̇ x̂ (ẑ turns with the base).
    """
    m, length, jp, ja, g, spin = 2.0, 0.4, 0.03, 0.004, 9.81, 1.7
    model = build_model(PENDULUM.format(m=m, length=length, jp=jp, ja=ja), "pendulum")
    model.gravity = pin.Motion(np.array([0.0, -g, 0.0]), np.zeros(3))
    chain = ClosedChain(model, [])
    t = np.linspace(0.0, 2.0, 41)
    theta, dtheta, ddtheta = 0.3 + 0.5 * np.sin(2 * t), np.cos(2 * t), -2 * np.sin(2 * t)
    yaw = _Profile(
        lambda t: tuple(
            np.outer(column, [0, 0, 0, 0, 0, 1]) for column in (spin * t, spin + 0 * t, 0 * t)
        )
    )
    base = BaseMotion((yaw,), forward=(1.0, 0.0, 0.0))
    loads = inverse_dynamics(
        ChainDynamics(chain, ["hinge"], base=base),
        theta[:, None],
        dtheta[:, None],
        ddtheta[:, None],
        t=t,
    )
    s, c = np.sin(theta), np.cos(theta)
    k = jp + m * length**2
    torque = k * ddtheta - spin**2 * (k - ja) * s * c + m * g * length * s
    scale = np.abs(torque).max()
    assert np.abs(loads.actuators["hinge"] - torque).max() <= ROUND_OFF * scale
    e = np.column_stack([s, -c, 0 * s])
    n = np.column_stack([c, s, 0 * s])
    x, z = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])
    a_g = (
        length * ddtheta[:, None] * n
        - length * dtheta[:, None] ** 2 * e
        - spin**2 * length * s[:, None] * x
        - 2 * spin * length * (dtheta * c)[:, None] * z
    )
    gravity = np.array([0.0, -g, 0.0])
    force = m * (a_g - gravity)
    assert np.abs(loads.mount.force - force).max() <= ROUND_OFF * np.abs(force).max()
    moment = np.empty_like(force)
    for i in range(t.size):
        rotation = pin.rpy.rpyToMatrix(0.0, 0.0, theta[i])
        lever = np.array([0.0, -length, 0.0])
        inertia = np.diag([jp, ja, jp]) + m * (lever @ lever * np.eye(3) - np.outer(lever, lever))
        inertia = rotation @ inertia @ rotation.T
        omega = np.array([0.0, spin, dtheta[i]])
        alpha = ddtheta[i] * z + spin * dtheta[i] * x
        moment[i] = (
            inertia @ alpha
            + np.cross(omega, inertia @ omega)
            - np.cross(length * e[i], m * gravity)
        )
    assert np.abs(loads.mount.moment - moment).max() <= ROUND_OFF * np.abs(moment).max()
    # the turning axes in the level ones: a yaw of Ω t about y
    np.testing.assert_allclose(loads.base.rotation[:, 0, 2], np.sin(spin * t), rtol=0, atol=1e-15)


def test_zero_slope_changes_nothing():
    """Every term a slope of zero adds is an exact zero: the loads are equal bit for bit."""
    chain = _four_bar()
    q, v, a = _motion(chain)
    standing = inverse_dynamics(ChainDynamics(chain, ["crank_joint"]), q, v, a)
    level = BaseMotion((Slope(0.0, 0.0),))
    sloped = inverse_dynamics(ChainDynamics(chain, ["crank_joint"], base=level), q, v, a)
    assert np.array_equal(_all_loads(sloped), _all_loads(standing))
    assert np.array_equal(sloped.mount.level_force, standing.mount.level_force)


TUMBLE = Tumble(
    w=(1.1, 2.3, 1.9, 1.3, 0.8, 1.6), amplitude=(0.02, 0.03, 0.05, 0.08, -0.1, 0.4), offset=0.0
)


@pytest.mark.parametrize(
    "profiles",
    [(Slope(0.1, 0.25),), (Terrain(),), (Recoil(start=0.2), Slope(-0.05, 0.1)), (TUMBLE,)],
    ids=["slope", "terrain", "recoil-on-slope", "tumble"],
)
def test_mount_is_the_rate_of_momentum_less_gravity_and_loads(profiles):
    """Newton–Euler of the whole four-bar (a spring to the ground and a load on the coupler
    included), level axes: F = ḣ_lin − m g − F_load, M_O = ḣ_G + (c − o) × (ḣ_lin − m g) − M_load
    about the base's origin o, with Pinocchio's centroidal momentum rate of the same URDF on a
    free-flyer root moved as the base."""
    spring = Spring(("ground", "coupler_tip"), stiffness=300.0, rest_length=0.05, damping=2.0)
    load = Load("coupler_tip", force=(1.0, -2.0, 0.5), moment=(0.1, 0.2, -0.3))
    chain = _four_bar()
    q, v, a = _motion(chain)
    t = np.linspace(0.0, 1.0, q.shape[0])
    base = BaseMotion(profiles, forward=(1.0, 0.0, 0.0))
    dyn = ChainDynamics(chain, ["crank_joint"], elements=(spring, load), base=base)
    loads = inverse_dynamics(dyn, q, v, a, t=t)
    state = loads.base

    model = pin.buildModelFromUrdf(str(FOUR_BAR), pin.JointModelFreeFlyer())
    g = chain.model.gravity.linear
    model.gravity = pin.Motion(g, np.zeros(3))
    data = model.createData()
    fixed, fixed_data = chain.model, chain.model.createData()
    frame = fixed.getFrameId("coupler_tip")
    mass = sum(inertia.mass for inertia in model.inertias)
    for k in range(t.size):
        rotation, origin = state.rotation[k], state.position[k]
        quaternion = pin.Quaternion(rotation).coeffs()
        q_ff = np.r_[origin, quaternion, q[k]]
        v_ff = np.r_[state.velocity[k], state.omega[k], v[k]]
        linear = state.acceleration[k] - np.cross(state.omega[k], state.velocity[k])
        a_ff = np.r_[linear, state.alpha[k], loads.accelerations[k]]
        pin.computeCentroidalMomentumTimeVariation(model, data, q_ff, v_ff, a_ff)
        momentum_rate = data.dhg
        centre = data.com[0]
        pin.framesForwardKinematics(fixed, fixed_data, q[k])
        where = fixed_data.oMf[frame].translation  # the load's point, base axes
        load_force = rotation @ np.array(load.force)
        load_moment = rotation @ (np.array(load.moment) + np.cross(where, load.force))
        net = momentum_rate.linear - mass * g
        force = net - load_force
        moment = momentum_rate.angular + np.cross(centre - origin, net) - load_moment
        scale = max(np.abs(force).max(), 1.0)
        assert np.abs(loads.mount.level_force[k] - force).max() <= ROUND_OFF * scale
        assert np.abs(loads.mount.level_moment[k] - moment).max() <= ROUND_OFF * scale


def test_refusals():
    chain = _four_bar()
    q, v, a = _motion(chain, 3)
    with pytest.raises(InputError, match="times"):
        inverse_dynamics(
            ChainDynamics(chain, ["crank_joint"], base=BaseMotion((Terrain(),))), q, v, a
        )
    with pytest.raises(InputError, match="horizontal"):
        ChainDynamics(chain, ["crank_joint"], base=BaseMotion((Slope(0.1),), forward=(0, 1, 0)))
    with pytest.raises(InputError, match="BaseMotion"):
        ChainDynamics(chain, ["crank_joint"], base=Slope(0.1))
