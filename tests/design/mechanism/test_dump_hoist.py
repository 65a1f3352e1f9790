"""The example examples/dump_hoist: its cylinder force against the hand check of its README,
and its one command's optimum within the cylinder's stroke in an independent feeder analyze."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from feeder.cli import main
from feeder.study.analyze import analyze

EXAMPLE = Path(__file__).parents[3] / "examples" / "dump_hoist"

M, G = 3000.0, 9.81  # [kg], [m/s²] the body
CG = (2.0, 0.6)  # [m] its centre of gravity in the body's frame (hinge O at the origin)
I_CG = 4360.0  # [kg·m²] its moment of inertia about the centre (a 4.0 × 1.2 m box)
A = (1.2, -0.6)  # [m] the cylinder's chassis pivot
B = (1.9, -0.15)  # [m] the body pivot, in the body's frame


def hand_check(theta: np.ndarray, acceleration: np.ndarray) -> np.ndarray:
    """F = (m g x_cg(θ) + I_O θ̈) / h(θ) [N] (the README's hand check): x_cg the centre's
    horizontal distance from the hinge, I_O = I_cg + m |cg|², h the cylinder's moment arm about
    the hinge, |B × u| with u the unit vector from A to B."""
    c, s = np.cos(theta), np.sin(theta)
    x_cg = CG[0] * c - CG[1] * s
    io = I_CG + M * (CG[0] ** 2 + CG[1] ** 2)
    bx, by = B[0] * c - B[1] * s, B[0] * s + B[1] * c
    dx, dy = bx - A[0], by - A[1]
    h = (bx * dy - by * dx) / np.hypot(dx, dy)
    return (M * G * x_cg + io * acceleration) / h


def test_the_cylinder_force_is_the_hand_check_at_every_sample():
    analysis = analyze(EXAMPLE / "closures.toml", EXAMPLE / "motion.csv")
    table = analysis.motion
    theta, acceleration = table.x[:, 0], table.ddx[:, 0]
    expected = hand_check(theta, acceleration)
    tau = analysis.loads.actuators["cylinder_slide"]
    # The cylinder is massless (no <inertial>), so the hand check is exact: agreement to the
    # loads' consistency (1e-9 of their largest term; measured ~1e-13).
    np.testing.assert_allclose(tau, expected, rtol=1e-10)
    # the classic sizing case: the largest force at the lowest position
    assert int(np.argmax(np.abs(tau))) == 0
    assert abs(tau[0]) == pytest.approx(51673.2, rel=1e-6)  # the README's number


def test_the_examples_command_keeps_the_stroke_in_an_independent_run(tmp_path):
    out = tmp_path / "optimum"
    argv = ["design", "optimize", str(EXAMPLE / "dump_hoist.urdf"), "--closures",
            str(EXAMPLE / "closures.toml"), "--design", str(EXAMPLE / "design.toml"),
            "--motion", str(EXAMPLE / "motion.csv"), "--out", str(out), "--workers", "1",
            "--no-figures"]  # fmt: skip
    assert main(argv) == 0
    check = tmp_path / "check"
    assert main(["analyze", str(out / "optimum.urdf"), "--closures",
                 str(out / "optimum_mechanism.toml"), "--motion", str(EXAMPLE / "motion.csv"),
                 "--out", str(check)]) == 0  # fmt: skip
    with open(check / "loads.csv", encoding="utf-8", newline="") as handle:
        rows = list(csv.DictReader(handle))
    stroke = [float(row["q_cylinder_slide"]) for row in rows]
    # design.toml: 0.78 m ≤ the pin-to-pin length ≤ 2.05 m; met to SLSQP's 1e-8 of the range
    assert min(stroke) >= 0.78 - 1e-8 * 1.27 and max(stroke) <= 2.05 + 1e-8 * 1.27
    force = max(abs(float(row["tau_cylinder_slide"])) for row in rows)
    assert force < 0.8 * 51673.2  # the optimum lowers the peak by a fifth at least
