"""The velocity gain (feeder.chain.assembly.partition): one dimensionless measure, against the
hand-derived rates of a boom raised by a cylinder (a prismatic joint driving revolute ones) and
of the crank-driven four-bar, the same for a machine scaled thirtyfold, and the limit that
refuses a pose on that same measure."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from feeder.chain import Closure, load_closed_chain
from feeder.chain.assembly.partition import Partition
from feeder.chain.assembly.tracking import track
from feeder.chain.mobility import mobility
from feeder.exceptions import SingularPoseError, UnreachablePoseError

from ...conftest import REPO

REACH = 6.0
"""[m] The boom's length: its tip is the frame farthest from the world's origin at the zero
pose (the cylinder's pivots are within 1.2 m), so the mechanism's reach L is 6 m."""

EYE = (1.2, 0.35)
"""[m] The rod's eye on the boom, in the boom's axes (the boom turns about the world's origin)."""

PIVOT = (0.6, -0.9)
"""[m] The cylinder's pivot on the ground."""

RELATIVE = 1e-7
"""The gains from the closure Jacobian against the hand-derived rates: the pose closes to ~1e-13
m, the rates are exact derivatives; 1e-7 leaves room for the pose's conditioning (gain ≤ 40)."""


def _boom_urdf(scale: float) -> str:
    """The boom and its cylinder, every length times ``scale``."""

    def xyz(x: float, y: float) -> str:
        return f'xyz="{x * scale!r} {y * scale!r} 0"'

    def link(name: str) -> str:
        inertia = '<inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/>'
        return f'<link name="{name}"><inertial><mass value="1"/>{inertia}</inertial></link>'

    def fixed(name: str, parent: str, x: float, y: float) -> str:
        return (
            f'<link name="{name}"/><joint name="{name}_joint" type="fixed"><origin {xyz(x, y)}/>'
            f'<parent link="{parent}"/><child link="{name}"/></joint>'
        )

    return f"""<?xml version="1.0"?>
<robot name="boom">
  <link name="ground"/>
  {link("boom")}{link("barrel")}{link("rod")}
  <joint name="boom_pivot" type="revolute"><origin xyz="0 0 0"/><parent link="ground"/>
    <child link="boom"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
  {fixed("boom_eye", "boom", *EYE)}{fixed("boom_tip", "boom", REACH, 0.0)}
  <joint name="cylinder_pivot" type="revolute"><origin {xyz(*PIVOT)}/><parent link="ground"/>
    <child link="barrel"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
  <joint name="stroke" type="prismatic"><origin xyz="0 0 0"/><parent link="barrel"/>
    <child link="rod"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="{10 * scale!r}" effort="1" velocity="1"/>
  </joint>
  {fixed("rod_eye", "rod", 0.0, 0.0)}
</robot>
"""


def _boom(tmp_path, scale: float = 1.0) -> Partition:
    path = tmp_path / f"boom_{scale:g}.urdf"
    path.write_text(_boom_urdf(scale))
    chain = load_closed_chain(path, [Closure("rod_eye", "boom_eye", "revolute")])
    return Partition(chain, ["stroke"])


def _boom_rates(theta: float) -> tuple[float, float, float]:
    """The cylinder's length s [m] at the boom angle θ, and the rates dθ/ds, dφ/ds [rad/m] of
    the boom's and the cylinder's angles per unit stroke: s = |B − A|, B = R(θ) e the eye,
    ds/dθ = (B − A)·B′/s, dφ/dθ = (B − A) × B′/s² (φ the direction of B − A)."""
    ex, ey = EYE
    eye = np.array(
        [ex * math.cos(theta) - ey * math.sin(theta), ex * math.sin(theta) + ey * math.cos(theta)]
    )
    eye_rate = np.array([-eye[1], eye[0]])  # dB/dθ
    arm = eye - np.array(PIVOT)
    s = float(np.linalg.norm(arm))
    ds = float(arm @ eye_rate) / s
    dphi = float(arm[0] * eye_rate[1] - arm[1] * eye_rate[0]) / s**2
    return s, 1.0 / ds, dphi / ds


def _pose(partition: Partition, theta: float, scale: float = 1.0) -> np.ndarray:
    """The closed pose (boom θ, cylinder angle, stroke) at the boom angle θ, by hand."""
    s, _, _ = _boom_rates(theta)
    ex, ey = EYE
    eye = np.array(
        [ex * math.cos(theta) - ey * math.sin(theta), ex * math.sin(theta) + ey * math.cos(theta)]
    )
    phi = math.atan2(*(eye - np.array(PIVOT))[::-1])
    q = np.zeros(3)
    q[[partition.chain.joint_slice(name).start for name in ("boom_pivot", "cylinder_pivot")]] = (
        theta,
        phi,
    )
    q[partition.chain.joint_slice("stroke").start] = s * scale
    np.testing.assert_allclose(partition.chain.residual(q), 0.0, atol=1e-12 * scale)
    return q


@pytest.mark.parametrize("theta", [-0.6, 0.0, 0.5, 1.0])
def test_a_cylinder_driven_boom_has_the_reach_times_its_rates(tmp_path, theta):
    """Gain = L ‖(dθ/ds, dφ/ds)‖ with L = 6 m (the boom's tip at the zero pose), not the
    placements' largest distance at the pose: the same number along a motion, in the report
    and in the refusal."""
    partition = _boom(tmp_path)
    assert partition.length == pytest.approx(REACH, rel=1e-15)
    _, boom_rate, cylinder_rate = _boom_rates(theta)
    expected = REACH * math.hypot(boom_rate, cylinder_rate)
    q = _pose(partition, theta)
    assert partition.gain(q) == pytest.approx(expected, rel=RELATIVE)
    report = mobility(partition.chain, q, ["stroke"])
    assert report.gain == pytest.approx(expected, rel=RELATIVE)
    assert "lengths' speeds in units of the mechanism's reach L = 6 m [–]" in report.text()
    refusing = Partition(partition.chain, ["stroke"], max_gain=expected * (1.0 - 1e-6))
    with pytest.raises(SingularPoseError, match=r"velocity gain [\d.]+ > limit"):
        refusing.velocity(q, np.ones(1))
    Partition(partition.chain, ["stroke"], max_gain=expected * (1.0 + 1e-6)).velocity(q, [1.0])


def test_the_gain_is_the_same_for_a_machine_scaled_thirtyfold(tmp_path):
    """A 30-times larger boom (a 180 m one) at the same angles: rates in rad/m thirty times
    smaller, reach thirty times larger, the same gain — along a tracked motion too (the batched
    path, 101 samples)."""
    small, large = _boom(tmp_path), _boom(tmp_path, 30.0)
    theta = np.linspace(-0.6, 1.0, 101)
    stroke = np.array([_boom_rates(x)[0] for x in theta])[:, None]
    gain_small = track(small, _pose(small, theta[0]), stroke).gain
    gain_large = track(large, _pose(large, theta[0], 30.0), 30.0 * stroke).gain
    np.testing.assert_allclose(gain_large, gain_small, rtol=RELATIVE)
    expected = [REACH * math.hypot(*_boom_rates(x)[1:]) for x in theta]
    np.testing.assert_allclose(gain_small, expected, rtol=RELATIVE)


def test_a_revolute_four_bar_keeps_its_gain_in_rad_per_rad():
    """The crank-driven four-bar (a = 40, b = 120, c = 80, d = 100 mm): the gain is the norm of
    the coupler's and the rocker's joint rates per unit crank rate, by central differences of
    the closed-form rocker angle (Freudenstein); no length enters."""
    chain = load_closed_chain(
        REPO / "examples" / "four_bar" / "four_bar.urdf",
        [Closure("coupler_tip", "rocker_tip", "revolute")],
    )
    a, b, c, d = 0.040, 0.120, 0.080, 0.100

    def joints(theta: float) -> np.ndarray:
        """Coupler (relative to the crank) and rocker angles, open branch."""
        crank = np.array([a * math.cos(theta), a * math.sin(theta)])
        to_pivot = np.array([d, 0.0]) - crank
        e = float(np.linalg.norm(to_pivot))
        psi = (
            math.atan2(to_pivot[1], to_pivot[0])
            + math.pi
            - math.acos((e**2 + c**2 - b**2) / (2 * e * c))
        )
        tip = np.array([d + c * math.cos(psi), c * math.sin(psi)])
        beta = math.atan2(*(tip - crank)[::-1])
        return np.array([beta - theta, psi])

    partition = Partition(chain, ["crank_joint"])
    for theta in (0.3, 1.2, 2.5, 4.0):
        q = partition.assemble(np.array([theta, *joints(theta)]))
        np.testing.assert_allclose(q[1:], joints(theta), atol=1e-9)  # the same branch
        h = 1e-5  # central differences: truncation h² ~ 1e-10, round-off 1e-16/h ~ 1e-11
        rates = (joints(theta + h) - joints(theta - h)) / (2 * h)
        assert partition.gain(q) == pytest.approx(float(np.linalg.norm(rates)), rel=1e-8)
    assert partition.gain_definition.endswith("[rad/rad]")


def test_refusals_name_the_loop_and_label_the_joints(tmp_path):
    """Each refusal is one line naming the loop (its cut) and the joints with their values and
    units, never an unlabelled q = [...]: a pose that does not close, too few independent joints,
    a cylinder whose line passes through the boom's pivot (the stroke cannot move the eye: a
    toggle), a gain past the limit."""
    partition = _boom(tmp_path)
    q = _pose(partition, 0.3)
    stroke = r"stroke = \d\.\d+ m"
    messages = []
    with pytest.raises(UnreachablePoseError) as caught:
        partition.check_closed(q + 0.01)
    messages.append(str(caught.value))
    assert re.match(r"loop rod_eye-boom_eye is open by [\d.e-]+ \[m, rad\]", messages[-1])
    assert re.search(
        rf"boom_pivot = 0\.31 rad, cylinder_pivot = [\d.]+ rad, {stroke}", messages[-1]
    )
    with pytest.raises(SingularPoseError) as caught:
        Partition(partition.chain, []).velocity(q, np.zeros(0))
    messages.append(str(caught.value))
    assert "can still move in loop rod_eye-boom_eye (boom_pivot = 0.3 rad, " in messages[-1]
    pivot = np.array(PIVOT)
    toward = -pivot / np.linalg.norm(pivot)  # the eye on the line from the pivot through O
    theta = math.atan2(toward[1], toward[0]) - math.atan2(EYE[1], EYE[0])
    toggle = _pose(partition, theta)
    with pytest.raises(SingularPoseError) as caught:
        partition.velocity(toggle, np.ones(1))
    messages.append(str(caught.value))
    assert re.match(
        rf"the dependent coordinates cannot follow the independent ones at {stroke}: "
        "moving stroke opens loop rod_eye-boom_eye \\(stroke = ",
        messages[-1],
    )
    with pytest.raises(SingularPoseError) as caught:
        Partition(partition.chain, ["stroke"], max_gain=2.0).velocity(q, np.ones(1))
    messages.append(str(caught.value))
    assert re.match(
        rf"near a singular pose \(toggle, dead centre\) at {stroke}: boom_pivot, "
        "cylinder_pivot must move up to [\\d.]+ times as fast as stroke in loop "
        "rod_eye-boom_eye \\(boom_pivot = 0.3 rad, cylinder_pivot = ",
        messages[-1],
    )
    assert not [m for m in messages if "\n" in m or "q = [" in m]
