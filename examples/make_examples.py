"""Write the example mechanisms: a Grashof four-bar and an in-line slider-crank (URDF, closures,
one revolution of the crank at 60 rpm)."""
import math
from pathlib import Path

import numpy as np

STEEL = 7850.0  # kg/m³
BAR = (0.020, 0.010)  # bar section, width × thickness [m]


def bar(name: str, length: float, colour: str) -> str:
    """A link: a steel bar along its x axis from 0 to ``length``."""
    w, t = BAR
    m = STEEL * w * t * length
    ixx = m * (w**2 + t**2) / 12.0
    iyy = m * (length**2 + t**2) / 12.0
    izz = m * (length**2 + w**2) / 12.0
    return f"""  <link name="{name}">
    <inertial>
      <origin xyz="{length / 2!r} 0 0" rpy="0 0 0"/>
      <mass value="{m!r}"/>
      <inertia ixx="{ixx!r}" ixy="0" ixz="0" iyy="{iyy!r}" iyz="0" izz="{izz!r}"/>
    </inertial>
    <visual>
      <origin xyz="{length / 2!r} 0 0" rpy="0 0 0"/>
      <geometry><box size="{length!r} {w!r} {t!r}"/></geometry>
      <material name="{colour}"/>
    </visual>
  </link>
"""


def joint(name, kind, parent, child, xyz, axis=None, limits=None):
    text = f'  <joint name="{name}" type="{kind}">\n    <origin xyz="{xyz}" rpy="0 0 0"/>\n'
    text += f'    <parent link="{parent}"/>\n    <child link="{child}"/>\n'
    if axis:
        text += f'    <axis xyz="{axis}"/>\n'
    if limits:
        text += f'    <limit lower="{limits[0]!r}" upper="{limits[1]!r}" effort="1000" velocity="100"/>\n'
    return text + "  </joint>\n"


def frame(name, parent, xyz):
    return f'  <link name="{name}"/>\n' + joint(f"{name}_joint", "fixed", parent, name, xyz)


MATERIALS = """  <material name="grey"><color rgba="0.5 0.5 0.5 1"/></material>
  <material name="blue"><color rgba="0.2 0.35 0.6 1"/></material>
  <material name="orange"><color rgba="0.85 0.55 0.1 1"/></material>
  <material name="green"><color rgba="0.3 0.55 0.25 1"/></material>
"""
TURN = (-4 * math.pi, 4 * math.pi)  # two turns either way: the crank turns fully


def four_bar(a=0.040, b=0.120, c=0.080, d=0.100) -> str:
    return (
        '<?xml version="1.0"?>\n<!-- Grashof crank-rocker four-bar, link lengths a = 40, b = 120, '
        "c = 80, d = 100 mm (crank, coupler, rocker, ground), steel bars 20 x 10 mm; "
        "the loop is cut at the coupler-rocker pin (frames coupler_tip, rocker_tip). -->\n"
        '<robot name="four_bar">\n' + MATERIALS
        + '  <link name="ground"/>\n'
        + bar("crank", a, "blue") + joint("crank_joint", "revolute", "ground", "crank", "0 0 0", "0 0 1", TURN)
        + bar("coupler", b, "orange") + joint("coupler_joint", "revolute", "crank", "coupler", f"{a!r} 0 0", "0 0 1", TURN)
        + frame("coupler_tip", "coupler", f"{b!r} 0 0")
        + bar("rocker", c, "green") + joint("rocker_joint", "revolute", "ground", "rocker", f"{d!r} 0 0", "0 0 1", TURN)
        + frame("rocker_tip", "rocker", f"{c!r} 0 0")
        + "</robot>\n"
    )


def slider_crank(r=0.050, l=0.200) -> str:
    w, t = BAR
    m = 0.5  # slider (piston) mass [kg]
    return (
        '<?xml version="1.0"?>\n<!-- In-line slider-crank, crank r = 50 mm, connecting rod l = 200 mm '
        "(l/r = 4), steel bars 20 x 10 mm, a 0.5 kg slider; the loop is cut at the rod-slider "
        "pin (frames rod_tip, slider_pin). -->\n"
        '<robot name="slider_crank">\n' + MATERIALS
        + '  <link name="ground"/>\n'
        + bar("crank", r, "blue") + joint("crank_joint", "revolute", "ground", "crank", "0 0 0", "0 0 1", TURN)
        + bar("rod", l, "orange") + joint("rod_joint", "revolute", "crank", "rod", f"{r!r} 0 0", "0 0 1", TURN)
        + frame("rod_tip", "rod", f"{l!r} 0 0")
        + f'''  <link name="slider">
    <inertial>
      <origin xyz="0 0 0" rpy="0 0 0"/>
      <mass value="{m!r}"/>
      <inertia ixx="{m * 0.05**2 / 6!r}" ixy="0" ixz="0" iyy="{m * 0.05**2 / 6!r}" iyz="0" izz="{m * 0.05**2 / 6!r}"/>
    </inertial>
    <visual><geometry><box size="0.05 0.05 0.05"/></geometry><material name="grey"/></visual>
  </link>
'''
        + joint("slider_joint", "prismatic", "ground", "slider", "0 0 0", "1 0 0", (0.0, 0.5))
        + frame("slider_pin", "slider", "0 0 0")
        + "</robot>\n"
    )


def closures(urdf, frames, actuated, independent, note) -> str:
    return f'''# {note}
[mechanism]
urdf = "{urdf}"
actuated = ["{actuated}"]        # joints whose generalized forces are the unknown drive loads
independent = ["{independent}"]  # joints whose motion is prescribed (motion.csv)
gravity = [0.0, -9.81, 0.0]      # [m/s²], world frame: the mechanism moves in the x-y plane

[[closure]]
frames = ["{frames[0]}", "{frames[1]}"]
type = "revolute"                # point | weld | revolute
axis = [0.0, 0.0, 1.0]           # hinge axis in both frames' axes
'''


def motion(guess_joint, q0, rate=100.0, speed=2 * math.pi) -> str:
    """One revolution at constant speed (60 rpm), from q0."""
    t = np.arange(int(rate) + 1) / rate
    lines = [f"t,q_{guess_joint},v_{guess_joint},a_{guess_joint}"]
    for ti in t:
        lines.append(f"{float(ti)!r},{float(q0 + speed * ti)!r},{speed!r},0.0")
    return "\n".join(lines) + "\n"


root = Path(__file__).resolve().parent
for name, urdf, frames, joint_name, q0, note in (
    ("four_bar", four_bar(), ("coupler_tip", "rocker_tip"), "crank_joint", math.radians(40.0),
     "Four-bar: the crank is driven (a motor torque), the coupler and rocker follow."),
    ("slider_crank", slider_crank(), ("rod_tip", "slider_pin"), "crank_joint", 0.0,
     "Slider-crank: the crank is driven (a motor torque), the rod and slider follow."),
):
    folder = root / name
    folder.mkdir(parents=True, exist_ok=True)
    (folder / f"{name}.urdf").write_text(urdf)
    (folder / "closures.toml").write_text(closures(f"{name}.urdf", frames, joint_name, joint_name, note))
    (folder / "motion.csv").write_text(motion(joint_name, q0))
print("ok")
