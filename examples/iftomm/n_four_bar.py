"""Write the IFToMM benchmark A02, the N-four-bar mechanism, for any N: a URDF and its mechanism
file (``python examples/iftomm/n_four_bar.py N`` writes ``n_four_bar_N.urdf`` and
``n_four_bar_N.toml`` beside this script; the files for N = 2 and N = 40 are shipped).

The mechanism (IFToMM benchmark A02, values stated in README.md): N + 1 vertical rockers
A_i B_i hinged to the ground at A_i = (i L, 0), i = 0 … N, and N horizontal couplers B_{i-1} B_i,
every bar of length L = 1 m and mass m = 1 kg, uniform (moment of inertia m L²/12 about its
centre), gravity g = 9.81 m/s² along −y. The tree: every rocker on the ground (joint ``r<i>``,
its angle θ_i from the x axis), coupler i on the tip of rocker i − 1 (joint ``c<i>``, its angle
relative to that rocker); each coupler's tip is closed onto rocker i's tip by a point closure
(the loops are planar: each closure's z row is redundant). It starts with every rocker vertical,
θ = π/2, and point B0 moving at 1 m/s along +x (θ̇ = −1 rad/s). Along its parallelogram motion
the rockers turn together; each time they lie horizontal (θ = 0 or π) every bar is on the
x axis and the closure loses N of its rank: the mechanism's freedom jumps from 1 to N + 1.
"""

from __future__ import annotations

import sys
from pathlib import Path

LENGTH, MASS = 1.0, 1.0
"""Every bar's length [m] and mass [kg]."""

HALF_PI = "1.5707963267948966"


def _bar(name: str) -> str:
    """A uniform bar along its link's x axis, from the joint to x = L (its tip frame below)."""
    centre = LENGTH / 2.0
    moment = MASS * LENGTH**2 / 12.0
    return (
        f'<link name="{name}">\n'
        f'  <inertial><origin xyz="{centre} 0 0"/><mass value="{MASS}"/>'
        f'<inertia ixx="0" ixy="0" ixz="0" iyy="{moment!r}" iyz="0" izz="{moment!r}"/>'
        "</inertial>\n"
        f'  <visual><origin xyz="{centre} 0 0"/><geometry><box size="{LENGTH} 0.02 0.02"/>'
        "</geometry></visual>\n</link>\n"
        f'<link name="{name}_tip"/>\n'
        f'<joint name="{name}_tip_fixed" type="fixed"><origin xyz="{LENGTH} 0 0"/>'
        f'<parent link="{name}"/><child link="{name}_tip"/></joint>\n'
    )


def _revolute(name: str, parent: str, child: str, x: float) -> str:
    return (
        f'<joint name="{name}" type="continuous"><origin xyz="{x!r} 0 0"/>'
        f'<parent link="{parent}"/><child link="{child}"/><axis xyz="0 0 1"/></joint>\n'
    )


def urdf(n: int) -> str:
    """The URDF of the N-four-bar (module docstring)."""
    parts = [f'<?xml version="1.0"?>\n<!-- IFToMM A02, the N-four-bar with N = {n} '
             "(examples/iftomm/n_four_bar.py wrote it) -->\n"]  # fmt: skip
    parts.append(f'<robot name="n_four_bar_{n}">\n<link name="ground"/>\n')
    for i in range(n + 1):
        parts.append(_bar(f"rocker{i}"))
        parts.append(_revolute(f"r{i}", "ground", f"rocker{i}", i * LENGTH))
    for i in range(1, n + 1):
        parts.append(_bar(f"coupler{i}"))
        parts.append(_revolute(f"c{i}", f"rocker{i - 1}", f"coupler{i}", LENGTH))
    parts.append("</robot>\n")
    return "".join(parts)


def mechanism(n: int) -> str:
    """The mechanism file of the N-four-bar (module docstring): its closures, the start pose
    (rockers vertical, couplers horizontal) and its rates (the first rocker's −1 rad/s: B0 at
    1 m/s along +x); the first rocker is the independent joint, and nothing is actuated."""
    pose = ", ".join([f"r{i} = {HALF_PI}" for i in range(n + 1)] + [
        f"c{i} = -{HALF_PI}" for i in range(1, n + 1)
    ])  # fmt: skip
    lines = [
        f"# IFToMM A02, the N-four-bar with N = {n} (examples/iftomm/n_four_bar.py wrote it;",
        "# see README.md). Start: every rocker vertical, B0 moving at 1 m/s along +x, the",
        "# first rocker's rate −1 rad/s; nothing drives it (a passive run).",
        "[mechanism]",
        f'urdf = "n_four_bar_{n}.urdf"',
        "actuated = []",
        'independent = ["r0"]',
        "gravity = [0.0, -9.81, 0.0]      # [m/s²]",
        f"pose = {{ {pose} }}",
        "rates = { r0 = -1.0 }            # [rad/s]",
        "",
    ]
    for i in range(1, n + 1):
        lines += ["[[closure]]", f'frames = ["coupler{i}_tip", "rocker{i}_tip"]', 'type = "point"']
        lines.append("")
    return "\n".join(lines)


def write(n: int, folder: Path) -> tuple[Path, Path]:
    """Write ``n_four_bar_<n>.urdf`` and ``.toml`` into ``folder``; returns their paths."""
    if n < 1:
        raise SystemExit(f"N must be a whole number ≥ 1, got {n}")
    paths = folder / f"n_four_bar_{n}.urdf", folder / f"n_four_bar_{n}.toml"
    paths[0].write_text(urdf(n))
    paths[1].write_text(mechanism(n))
    return paths


if __name__ == "__main__":
    if len(sys.argv) != 2 or not sys.argv[1].isdigit():
        raise SystemExit("usage: python examples/iftomm/n_four_bar.py N")
    for path in write(int(sys.argv[1]), Path(__file__).parent):
        print(f"wrote {path}")
