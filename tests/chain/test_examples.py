"""The example mechanisms against closed-form kinematics and virtual-work statics.

The four-bar (a = 40, b = 120, c = 80, d = 100 mm) and the in-line slider-crank (r = 50,
l = 200 mm) of ``examples/``: their loop equations solve by hand (circle intersection; the
slider's x = r cos θ + √(l² − r² sin² θ)), their velocity and acceleration follow by
differentiating them, and for a static pose the drive torque follows from virtual work,
τ δθ = δV − F · δx. The generic layer (:mod:`feeder.chain`) must reproduce all of it.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from feeder.chain import Closure, load_closed_chain
from feeder.chain.assembly.partition import Partition
from feeder.chain.dynamics.inverse import ChainDynamics, inverse_dynamics

from ..conftest import REPO

A, B, C, D = 0.040, 0.120, 0.080, 0.100  # four-bar: crank, coupler, rocker, ground [m]
R, L = 0.050, 0.200  # slider-crank: crank, rod [m]
G = 9.81  # [m/s²], −y in the examples' side-files
BAR = 7850.0 * 0.020 * 0.010  # mass per length of the examples' steel bars [kg/m]
SLIDER = 0.5  # slider mass [kg]

RELATIVE = 1e-9
"""The issue's bound, relative to the quantity's scale: both sides are exact to round-off
(~1e-15); Newton stops at a 1e-13 m residual, i.e. ~1e-12 relative on these 0.1 m links."""

ANGLES = np.radians([10.0, 40.0, 95.0, 170.0, 250.0, 330.0])
"""Crank angles [rad] around the turn (the four-bar is a crank-rocker: every angle assembles)."""


def _chain(name: str, kind: str = "revolute"):
    folder = REPO / "examples" / name
    frames = ("coupler_tip", "rocker_tip") if name == "four_bar" else ("rod_tip", "slider_pin")
    chain = load_closed_chain(folder / f"{name}.urdf", [Closure(*frames, kind=kind)])
    chain.model.gravity = pin.Motion(np.array([0.0, -G, 0.0]), np.zeros(3))
    return chain


def four_bar_closed_form(theta2: float, omega2: float, alpha2: float):
    """Open-branch angles θ3 (coupler, absolute), θ4 (rocker) and their rates and
    accelerations, by circle intersection and the differentiated loop equation
    a e^{iθ2} + b e^{iθ3} − c e^{iθ4} − d = 0."""
    ax, ay = A * math.cos(theta2), A * math.sin(theta2)
    dx, dy = D - ax, -ay
    e = math.hypot(dx, dy)
    gamma = math.acos((B**2 + e**2 - C**2) / (2.0 * B * e))
    theta3 = math.atan2(dy, dx) + gamma
    bx, by = ax + B * math.cos(theta3), ay + B * math.sin(theta3)
    theta4 = math.atan2(by, bx - D)
    omega3 = A * omega2 * math.sin(theta4 - theta2) / (B * math.sin(theta3 - theta4))
    omega4 = A * omega2 * math.sin(theta2 - theta3) / (C * math.sin(theta4 - theta3))
    # Second derivative: b α3 i e^{iθ3} − c α4 i e^{iθ4} = rhs, two real equations.
    rhs = (
        -A * alpha2 * 1j * np.exp(1j * theta2)
        + A * omega2**2 * np.exp(1j * theta2)
        + B * omega3**2 * np.exp(1j * theta3)
        - C * omega4**2 * np.exp(1j * theta4)
    )
    col3, col4 = B * 1j * np.exp(1j * theta3), -C * 1j * np.exp(1j * theta4)
    matrix = np.array([[col3.real, col4.real], [col3.imag, col4.imag]])
    alpha3, alpha4 = np.linalg.solve(matrix, [rhs.real, rhs.imag])
    return (theta3, theta4), (omega3, omega4), (alpha3, alpha4)


def slider_closed_form(theta: float, omega: float):
    """Slider position x and rate ẋ, rod angle φ (absolute) of the in-line slider-crank."""
    root = math.sqrt(L**2 - (R * math.sin(theta)) ** 2)
    x = R * math.cos(theta) + root
    xdot = -R * omega * math.sin(theta) - R**2 * omega * math.sin(theta) * math.cos(theta) / root
    phi = math.asin(-R * math.sin(theta) / L)
    return x, xdot, phi


@pytest.mark.parametrize("theta2", ANGLES)
def test_four_bar_kinematics_match_the_closed_form(theta2):
    chain = _chain("four_bar")
    partition = Partition(chain, ["crank_joint"])
    omega2, alpha2 = 2.0 * math.pi, 3.0
    (t3, t4), (w3, w4), (a3, a4) = four_bar_closed_form(theta2, omega2, alpha2)
    guess = np.array([theta2, t3 - theta2, t4])  # the closed form picks the branch
    q = partition.assemble(guess + [0.0, 0.05, 0.05])  # Newton from near the branch
    v = partition.velocity(q, [omega2])
    acc = partition.acceleration(q, v, [alpha2])
    wrap = lambda x: math.remainder(x, 2.0 * math.pi)  # noqa: E731
    assert abs(wrap(q[1] - (t3 - theta2))) <= RELATIVE
    assert abs(wrap(q[2] - t4)) <= RELATIVE
    np.testing.assert_allclose(v[1:], [w3 - omega2, w4], rtol=0, atol=RELATIVE * omega2)
    scale = max(abs(a3), abs(a4), omega2**2)
    np.testing.assert_allclose(acc[1:], [a3 - alpha2, a4], rtol=0, atol=RELATIVE * scale)


@pytest.mark.parametrize("theta", ANGLES)
def test_slider_crank_kinematics_match_the_closed_form(theta):
    chain = _chain("slider_crank")
    partition = Partition(chain, ["crank_joint"])
    omega = 2.0 * math.pi
    x, xdot, phi = slider_closed_form(theta, omega)
    q = partition.assemble(np.array([theta, phi - theta + 0.05, x + 0.01]))
    v = partition.velocity(q, [omega])
    assert abs(q[2] - x) <= RELATIVE * L
    assert abs(math.remainder(q[1] - (phi - theta), 2.0 * math.pi)) <= RELATIVE
    assert abs(v[2] - xdot) <= RELATIVE * R * omega


@pytest.mark.parametrize("kind", ["revolute", "point"])
@pytest.mark.parametrize("theta2", ANGLES)
def test_four_bar_static_torque_is_the_virtual_work_of_gravity(theta2, kind):
    """τ2 = dV/dθ2 with V = g Σ m y_G and the kinematic coefficients h_i = ω_i/ω2; the closure
    kind changes which forces are indeterminate, not the torque."""
    chain = _chain("four_bar", kind)
    partition = Partition(chain, ["crank_joint"])
    (t3, t4), (w3, w4), _ = four_bar_closed_form(theta2, 1.0, 0.0)
    q = partition.assemble(np.array([theta2, t3 - theta2 + 0.05, t4 + 0.05]))
    loads = inverse_dynamics(
        ChainDynamics(chain, ["crank_joint"]), q[None], np.zeros((1, 3)), np.zeros((1, 3))
    )
    m2, m3, m4 = BAR * A, BAR * B, BAR * C
    expected = G * (
        m2 * A / 2 * math.cos(theta2)
        + m3 * (A * math.cos(theta2) + B / 2 * math.cos(t3) * w3)
        + m4 * C / 2 * math.cos(t4) * w4
    )
    scale = G * (m2 + m3 + m4) * (A + B)
    assert abs(loads.actuators["crank_joint"][0] - expected) <= RELATIVE * scale
    expected_indeterminate = {"revolute": {"fz", "m1", "m2"}, "point": {"fz"}}[kind]
    assert {label.split(":")[1] for label in loads.indeterminacy.rows} == expected_indeterminate


@pytest.mark.parametrize("theta", ANGLES)
def test_slider_crank_static_torque_with_an_external_force(theta):
    """A force F along x on the slider and gravity: τ = dV/dθ − F dx/dθ (virtual work)."""
    chain = _chain("slider_crank")
    partition = Partition(chain, ["crank_joint"])
    x, dxdtheta, phi = slider_closed_form(theta, 1.0)
    q = partition.assemble(np.array([theta, phi - theta + 0.05, x + 0.01]))
    force = 25.0  # [N] along +x on the slider (a gas force on a piston)
    wrench = np.array([force, 0.0, 0.0, 0.0, 0.0, 0.0])
    dyn = ChainDynamics(chain, ["crank_joint"])
    loads = inverse_dynamics(
        dyn, q[None], np.zeros((1, 3)), np.zeros((1, 3)), external={"slider_pin": wrench}
    )
    dphi = -R * math.cos(theta) / (L * math.cos(phi))  # from sin φ = −r sin θ / l
    m_crank, m_rod = BAR * R, BAR * L
    potential = G * (
        m_crank * R / 2 * math.cos(theta)
        + m_rod * (R * math.cos(theta) + L / 2 * math.cos(phi) * dphi)
    )
    expected = potential - force * dxdtheta
    scale = force * R + G * (m_crank + m_rod) * L
    assert abs(loads.actuators["crank_joint"][0] - expected) <= RELATIVE * scale
