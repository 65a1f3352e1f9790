"""IFToMM A04, Bricard's mechanism: its reference motion computed without multibody code.

The mechanism of ``bricard.urdf`` (README.md): five uniform slender bars of L = 1 m and
m = 1 kg, six hinges at the joints J0 … J5 below (the sixth, J5, back to the ground), gravity
g = 9.81 m/s² along −y, released at rest from that pose. It moves with one freedom. Here it is
written from its description alone, with numpy and SciPy:

- positions by the product of exponentials: bar k (k = 1 … 5) is carried by the turns q_1 … q_k
  about the hinges J0 … J(k−1) (axes and points at the start); the loop closes when bar 5's end
  is back at J5 and its hinge axis there is still x: five equations in the five angles, of rank
  four, solved for q_2 … q_5 given θ = q_1 by SciPy's least squares, following the branch from
  the start;
- the one-freedom dynamics by energy: the tangent dq/dθ (the closure's null vector, analytic
  Jacobians), the generalised mass m(θ) = Σ m |dc_k/dθ|² + ω'_kᵀ I_k ω'_k (c_k the bar's centre,
  ω'_k its angular velocity per unit θ̇, I_k its inertia m L²/12 across the bar, world axes) and
  the potential V(θ) = Σ m g y(c_k); from rest at θ = 0, ½ m(θ) θ̇² + V(θ) = V(0);
- the swing: released at θ = 0 it turns to θ_1 where V(θ_1) = V(0), and back. The half period
  T/2 = ∫ dθ / θ̇ from 0 to θ_1 has an inverse-square-root singularity at both ends; with
  θ = θ_1 (1 − cos φ) / 2 the integrand in φ ∈ [0, π] is smooth (V(0) − V ∝ sin² φ near either
  end cancels dθ/dφ ∝ sin φ), integrated by SciPy's ``quad`` (the period) and by a Chebyshev
  interpolant (the time t(φ) at any φ, inverted for the motion θ(t));
- the release acceleration θ̈(0) = −V'(0) / m(0).

Run it (``python examples/iftomm/bricard_reference.py``) to print the period, the release
acceleration and P3 at a few times; the tests (``tests/chain/test_iftomm_bricard.py``) and
``benchmarks/bench_iftomm.py`` compare ``feeder simulate``'s run of ``bricard.toml`` with it.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.integrate
import scipy.optimize
from numpy.polynomial import chebyshev

LENGTH, MASS, G = 1.0, 1.0, 9.81
JOINTS = np.array([[0, 0, 0], [1, 0, 0], [1, -1, 0], [1, -1, 1], [0, -1, 1], [0, 0, 1.0]])
"""The hinges J0 … J5 at the start [m], world axes; bar k runs from J(k−1) to Jk."""
AXES = np.array([[0, 1, 0], [0, 0, 1], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 0, 0.0]])
"""Their axes at the start (unit vectors, world axes)."""
P3 = JOINTS[2]
"""The benchmark's point P3 at the start [m]: the hinge of bars 2 and 3, carried by bar 2."""
NODES = 80
"""Chebyshev nodes of the time map t(φ) (its coefficients fall below 1e-12 of the first)."""


def _turn(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rotation matrix (3, 3) of ``angle`` [rad] about the unit ``axis`` (Rodrigues)."""
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * k @ k


def placements(q: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """Each bar's displacement from the start, (R_k, o_k) with x ↦ R_k x + o_k, for the joint
    angles q (5,) [rad]: the product of the turns about J0 … J(k−1)."""
    rotation, offset, out = np.eye(3), np.zeros(3), []
    for k in range(5):
        turn = _turn(AXES[k], q[k])
        offset = rotation @ (JOINTS[k] - turn @ JOINTS[k]) + offset
        rotation = rotation @ turn
        out.append((rotation, offset))
    return out


def _hinges(placed) -> tuple[np.ndarray, np.ndarray]:
    """The hinges J0 … J4 where they are now: their axes and points (5, 3) [–, m]."""
    axes, points = [AXES[0]], [JOINTS[0]]
    for k in range(1, 5):
        rotation, offset = placed[k - 1]
        axes.append(rotation @ AXES[k])
        points.append(rotation @ JOINTS[k] + offset)
    return np.array(axes), np.array(points)


def residual(q: np.ndarray) -> np.ndarray:
    """The loop's gap (5,): bar 5's end minus J5 [m], and the y, z components of bar 5's hinge
    axis at J5 (zero when it is still x)."""
    rotation, offset = placements(q)[4]
    return np.r_[rotation @ JOINTS[5] + offset - JOINTS[5], (rotation @ AXES[5])[1:]]


def jacobian(q: np.ndarray) -> np.ndarray:
    """d residual / dq (5, 5), analytic: a turn about hinge j moves a point p of the bars it
    carries by a_j × (p − J_j) and turns a direction d by a_j × d."""
    placed = placements(q)
    axes, points = _hinges(placed)
    rotation, offset = placed[4]
    end, direction = rotation @ JOINTS[5] + offset, rotation @ AXES[5]
    columns = [
        np.r_[np.cross(a, end - p), np.cross(a, direction)[1:]]
        for a, p in zip(axes, points, strict=True)
    ]
    return np.array(columns).T


def tangent(q: np.ndarray) -> np.ndarray:
    """dq/dθ (5,) along the closed motion, θ = q_1: J_dep dq_dep = −J_1 (rank 4, solved in
    least squares: the fifth row is the redundant one)."""
    j = jacobian(q)
    dependent = np.linalg.lstsq(j[:, 1:], -j[:, 0], rcond=None)[0]
    return np.r_[1.0, dependent]


def energy_terms(q: np.ndarray) -> tuple[float, float, float]:
    """At the closed pose q (5,): the generalised mass m(θ) [kg·m²], the potential V(θ) [J] and
    its slope V'(θ) [J/rad] along the motion."""
    rate = tangent(q)
    placed = placements(q)
    axes, points = _hinges(placed)
    mass = potential = slope = 0.0
    for k, (rotation, offset) in enumerate(placed):
        start, end = rotation @ JOINTS[k] + offset, rotation @ JOINTS[k + 1] + offset
        centre, along = (start + end) / 2.0, (end - start) / LENGTH
        omega = (rate[: k + 1, None] * axes[: k + 1]).sum(axis=0)
        velocity = sum(rate[j] * np.cross(axes[j], centre - points[j]) for j in range(k + 1))
        across = omega - along * (along @ omega)  # the slender bar's inertia: m L²/12 across it
        mass += MASS * velocity @ velocity + MASS * LENGTH**2 / 12.0 * across @ across
        potential += MASS * G * centre[1]
        slope += MASS * G * velocity[1]
    return mass, potential, slope


def point_p3(q: np.ndarray) -> np.ndarray:
    """P3 (3,) [m] at the pose q: bar 2's end."""
    rotation, offset = placements(q)[1]
    return rotation @ P3 + offset


class Branch:
    """The closed poses along the motion from the start, by θ = q_1: each solve starts from the
    nearest pose already found, predicted along its tangent, in steps of at most 0.05 rad."""

    STEP = 0.05

    def __init__(self) -> None:
        self._thetas, self._poses = [0.0], [np.zeros(5)]

    def pose(self, theta: float) -> np.ndarray:
        """The closed joint angles q (5,) [rad] at q_1 = θ [rad]."""
        nearest = int(np.argmin(np.abs(np.array(self._thetas) - theta)))
        start, q = self._thetas[nearest], self._poses[nearest]
        steps = max(1, math.ceil(abs(theta - start) / self.STEP))
        for value in np.linspace(start, theta, steps + 1)[1:]:
            guess = q + tangent(q) * (value - q[0])
            solution = scipy.optimize.least_squares(
                lambda d, value=value: residual(np.r_[value, d]),
                guess[1:],
                jac=lambda d, value=value: jacobian(np.r_[value, d])[:, 1:],
                xtol=1e-15, ftol=1e-15, gtol=1e-15, method="lm",
            )  # fmt: skip
            q = np.r_[value, solution.x]
            self._thetas.append(float(value))
            self._poses.append(q)
        gap = float(np.abs(residual(q)).max())
        if gap > 1e-12:
            raise RuntimeError(f"the loop does not close at θ = {theta}: gap {gap:.3g}")
        return q


class Reference:
    """The reference motion: the swing's end θ_1, the period T [s], the release acceleration and
    θ(t) (module docstring)."""

    def __init__(self) -> None:
        self.branch = Branch()
        _, self.v0, slope0 = self._terms(0.0)
        self.release = -slope0 / self._terms(0.0)[0]
        """θ̈ at release [rad/s²]."""
        grid = np.linspace(0.1, 3.5, 35)  # steps of 0.1 rad, past π
        gaps = [self._terms(theta)[1] - self.v0 for theta in grid]
        turn = next(i for i, gap in enumerate(gaps) if gap > 0.0)  # V back above V(0)
        self.end = scipy.optimize.brentq(
            lambda theta: self._terms(theta)[1] - self.v0, grid[turn - 1], grid[turn], xtol=1e-15
        )
        """θ_1 [rad], the other turning point."""
        half, self.quad_error = scipy.integrate.quad(
            self._integrand, 0.0, math.pi, epsabs=1e-13, epsrel=1e-13, limit=200
        )
        self.period = 2.0 * half
        """T [s] by quad."""
        nodes = math.pi / 2.0 * (1.0 - np.cos(np.pi * (np.arange(NODES) + 0.5) / NODES))
        values = [self._integrand(phi) for phi in nodes]
        series = chebyshev.Chebyshev.fit(nodes, values, NODES - 1, domain=[0.0, math.pi])
        self.tail = float(np.abs(series.coef[-8:]).max() / np.abs(series.coef[0]))
        """The Chebyshev series' last coefficients relative to its first: its resolution."""
        self._time = series.integ(lbnd=0.0)
        self.chebyshev_period = 2.0 * float(self._time(math.pi))
        """T [s] by the Chebyshev interpolant (agrees with :attr:`period` when resolved)."""

    def _terms(self, theta: float) -> tuple[float, float, float]:
        return energy_terms(self.branch.pose(theta))

    def _angle(self, phi: float) -> float:
        return self.end * (1.0 - math.cos(phi)) / 2.0

    def _integrand(self, phi: float) -> float:
        """dt/dφ = (dθ/dφ) √(m / 2(V(0) − V)), smooth on [0, π]."""
        theta = self._angle(phi)
        mass, potential, _ = self._terms(theta)
        drop = max(self.v0 - potential, 1e-300)
        return self.end / 2.0 * math.sin(phi) * math.sqrt(mass / (2.0 * drop))

    def angle(self, t: np.ndarray) -> np.ndarray:
        """θ(t) (N,) [rad] at the times t (N,) [s] from the release: each half swing is the
        previous one backwards."""
        half = self.chebyshev_period / 2.0
        out = np.empty(len(t))
        for i, time in enumerate(np.asarray(t, dtype=float)):
            phase = time % self.chebyshev_period
            phase = phase if phase <= half else self.chebyshev_period - phase
            phi = scipy.optimize.brentq(
                lambda p, phase=phase: self._time(p) - phase, 0.0, math.pi, xtol=1e-15
            )
            out[i] = self._angle(phi)
        return out

    def p3(self, t: np.ndarray) -> np.ndarray:
        """P3 (N, 3) [m] at the times t (N,) [s]."""
        return np.array([point_p3(self.branch.pose(theta)) for theta in self.angle(t)])


if __name__ == "__main__":
    reference = Reference()
    print(f"swing 0 → {reference.end:.12f} rad of joint J0 and back")
    print(f"period {reference.period:.12f} s (quad, error estimate {reference.quad_error:.1e})")
    print(f"period {reference.chebyshev_period:.12f} s (Chebyshev, tail {reference.tail:.1e})")
    print(f"release acceleration {reference.release:.12f} rad/s²")
    times = np.array([0.0, 1.0, 2.5, 5.0, 10.0])
    for time, point in zip(times, reference.p3(times), strict=True):
        print(f"P3({time:4.1f} s) = {np.array2string(point, precision=9)}")
