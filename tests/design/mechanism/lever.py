"""A lever lifted by a cylinder, written as a model, a mechanism file and a motion table for the
tests of :mod:`feeder.design.mechanism`, with its loads in closed form.

The lever turns about O (joint ``body_hinge``, at the origin, axis z; gravity −y); its centre of
mass is at (c, e) in its frame, its mass m, its moment of inertia about the centre I_c. A
cylinder (massless barrel and rod, the prismatic joint ``cylinder_slide`` between two pins)
runs from the ground pivot A = (a, −d) (joint ``cylinder_pivot``) to the lever pin B = (b, 0)
in the lever's frame (frame ``body_pin``). At the lever angle θ, B = b (cos θ, sin θ), and the
cylinder force (positive pushing) balances the lever about O:

    F(θ) = (I_O θ̈ + m g (c cos θ − e sin θ)) / h(θ),   I_O = I_c + m (c² + e²),
    h(θ) = (B × (B − A))_z / |B − A| = b (d cos θ + a sin θ) / |B − A|.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

G = 9.81


@dataclass(frozen=True)
class Lever:
    """The lever's numbers [kg, m, kg·m², rad]: mass, centre (c, e), I_c, pin b, pivot (a, −d),
    the motion's end angle and duration [s], its samples."""

    m: float = 500.0
    c: float = 0.6
    e: float = -0.8
    inertia: float = 20.0
    b: float = 0.8
    a: float = 1.0
    d: float = 0.3
    end: float = math.radians(60.0)
    duration: float = 2.0
    samples: int = 13

    def motion(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """t [s], θ [rad], θ̇ [rad/s], θ̈ [rad/s²] of the cosine ramp from 0 to the end angle."""
        t = np.linspace(0.0, self.duration, self.samples)
        w = math.pi / self.duration
        half = self.end / 2.0
        return t, half * (1 - np.cos(w * t)), half * w * np.sin(w * t), half * w**2 * np.cos(w * t)

    def force(self, a: float | np.ndarray, theta: np.ndarray, acceleration: np.ndarray):
        """F(θ) [N] at the pivot position ``a`` [m] (module docstring)."""
        io = self.inertia + self.m * (self.c**2 + self.e**2)
        moment = io * acceleration + self.m * G * (self.c * np.cos(theta) - self.e * np.sin(theta))
        bx, by = self.b * np.cos(theta), self.b * np.sin(theta)
        length = np.hypot(bx - a, by + self.d)
        return moment * length / (self.b * (self.d * np.cos(theta) + a * np.sin(theta)))

    def urdf(self) -> str:
        """The model (module docstring)."""
        return f"""<?xml version="1.0"?>
<robot name="lever">
  <link name="ground"/>
  <link name="body">
    <inertial>
      <origin xyz="{self.c!r} {self.e!r} 0" rpy="0 0 0"/>
      <mass value="{self.m!r}"/>
      <inertia ixx="{self.inertia!r}" ixy="0" ixz="0" iyy="{self.inertia!r}" iyz="0"
               izz="{self.inertia!r}"/>
    </inertial>
  </link>
  <joint name="body_hinge" type="revolute">
    <origin xyz="0 0 0" rpy="0 0 0"/>
    <parent link="ground"/><child link="body"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="2" effort="1e6" velocity="10"/>
  </joint>
  <link name="body_pin"/>
  <joint name="body_pin_joint" type="fixed">
    <origin xyz="{self.b!r} 0 0" rpy="0 0 0"/>
    <parent link="body"/><child link="body_pin"/>
  </joint>
  <link name="barrel"/>
  <joint name="cylinder_pivot" type="revolute">
    <origin xyz="{self.a!r} {-self.d!r} 0" rpy="0 0 0"/>
    <parent link="ground"/><child link="barrel"/><axis xyz="0 0 1"/>
    <limit lower="-3.14159" upper="3.14159" effort="1e6" velocity="10"/>
  </joint>
  <link name="rod"/>
  <joint name="cylinder_slide" type="prismatic">
    <origin xyz="0 0 0" rpy="0 0 0"/>
    <parent link="barrel"/><child link="rod"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="4" effort="1e6" velocity="10"/>
  </joint>
</robot>
"""

    def closures(self) -> str:
        """The mechanism file: the lever's angle prescribed, the cylinder actuated."""
        angle = math.atan2(self.d, self.b - self.a)
        length = math.hypot(self.b - self.a, self.d)
        return f"""[mechanism]
urdf = "lever.urdf"
actuated = ["cylinder_slide"]
independent = ["body_hinge"]
gravity = [0.0, -{G!r}, 0.0]
pose = {{cylinder_pivot = {angle!r}, cylinder_slide = {length!r}}}

[[closure]]
frames = ["rod", "body_pin"]
type = "revolute"
axis = [0.0, 0.0, 1.0]
"""

    def write(self, folder: Path, design: str) -> tuple[Path, Path, Path, Path]:
        """The model, mechanism file, motion table and the design file ``design`` in ``folder``."""
        model, closures = folder / "lever.urdf", folder / "closures.toml"
        motion, design_path = folder / "motion.csv", folder / "design.toml"
        model.write_text(self.urdf(), encoding="utf-8")
        closures.write_text(self.closures(), encoding="utf-8")
        rows = ["t,q_body_hinge,v_body_hinge,a_body_hinge"]
        rows += [",".join(repr(float(x)) for x in row) for row in zip(*self.motion(), strict=True)]
        motion.write_text("\n".join(rows) + "\n", encoding="utf-8")
        design_path.write_text(design, encoding="utf-8")
        return model, closures, motion, design_path
