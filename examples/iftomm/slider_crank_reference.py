"""The IFToMM spatial rigid slider-crank: its reference motion computed without multibody code.

The mechanism of ``slider_crank.urdf`` (README.md): a crank AB (0.08 m, 0.12 kg, its centre at
the middle, 1e-4 kg·m² about its axis through that centre) turning about x at
A = (0, 0.1, 0.12) m; a rod BC (0.3 m, 0.5 kg, its centre at the middle, 4e-4 kg·m² about its
axis and 4e-3 across it) with a spherical joint at B and a universal joint at C; a slider (2 kg)
at C = (x, 0, 0) moving along x. The universal joint turns about the slider's y, then about the
turned x (the rod's axis that was x at the start). Gravity 9.81 m/s² along −z. Start: the crank
up (θ = 0, B = (0, 0.1, 0.2)), C = (0.2, 0, 0), the crank turning at θ̇ = 6 rad/s.

It has one freedom, the crank angle θ, and here it is written in it, in closed form:
B = A + 0.08 (0, −sin θ, cos θ); x = √(0.3² − B_y² − B_z²) (the slider's branch x > 0); the rod's
axis d = (B − C)/0.3 and its angular velocity ω = α̇ y + β̇ R_y(α) x (the universal joint's two
rates, from ω × d = ḋ: three equations, two unknowns, consistent); per unit θ̇ these give the
generalised mass m(θ) = I_A + m_rod |v_G|² + ωᵀ I_rod ω + m_slider ẋ² (I_A the crank's inertia
about its axis, v_G the rod centre's velocity (v_B + v_C)/2, I_rod = 4e-3 1 − 3.6e-3 d dᵀ) and the
potential V(θ) = g (m_crank z_crank + m_rod z_G). The energy ½ m(θ) θ̇² + V(θ) = E0 keeps θ̇ > 0
(V is largest at the start, where the crank is up), so the time to reach θ is the quadrature
t(θ) = ∫ √(m / 2(E0 − V)) dθ, smooth and 2π-periodic: one turn's time T by SciPy's ``quad``,
and t(θ) within a turn by a Chebyshev interpolant, inverted for θ(t) and the slider's x(t).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.integrate
import scipy.optimize
from numpy.polynomial import chebyshev

G = 9.81
A = np.array([0.0, 0.1, 0.12])
"""The crank's pivot [m]."""
CRANK, ROD = 0.08, 0.3
"""Lengths AB and BC [m]."""
M_CRANK, M_ROD, M_SLIDER = 0.12, 0.5, 2.0
"""Masses [kg]."""
I_CRANK = 1e-4 + M_CRANK * (CRANK / 2.0) ** 2
"""The crank's moment about its axis through A [kg·m²] (1e-4 about its centre, Steiner)."""
I_AXIAL, I_ACROSS = 4e-4, 4e-3
"""The rod's moments about its axis and across it, through its centre [kg·m²]."""
RATE = 6.0
"""The crank's rate at the start [rad/s]."""
NODES = 256
"""Chebyshev nodes of one turn's time map t(θ)."""


def pose(theta: float) -> tuple[np.ndarray, float, np.ndarray]:
    """B (3,) [m], the slider's x [m] and the rod's axis d (3,) (unit, from C to B) at the crank
    angle θ [rad]."""
    b = A + CRANK * np.array([0.0, -math.sin(theta), math.cos(theta)])
    x = math.sqrt(ROD**2 - b[1] ** 2 - b[2] ** 2)
    return b, x, (b - [x, 0.0, 0.0]) / ROD


def joint_angles(d: np.ndarray) -> tuple[float, float]:
    """The universal joint's angles (α about y, β about the turned x) [rad] that turn the rod's
    start axis d0 into d: R_y(α) R_x(β) d0 = d."""
    d0 = pose(0.0)[2]
    # y: cos β d0_y − sin β d0_z = d_y (β near 0 on this motion: the branch through the start)
    radius, phase = math.hypot(d0[1], d0[2]), math.atan2(d0[2], d0[1])
    beta = math.acos(d[1] / radius) - phase
    w = np.array([d0[0], 0.0, math.sin(beta) * d0[1] + math.cos(beta) * d0[2]])
    alpha = math.atan2(d[0], d[2]) - math.atan2(w[0], w[2])
    return alpha, beta


def energy_terms(theta: float) -> tuple[float, float]:
    """The generalised mass m(θ) [kg·m²] and the potential V(θ) [J] at the crank angle θ."""
    b, x, d = pose(theta)
    rate_b = CRANK * np.array([0.0, -math.cos(theta), -math.sin(theta)])  # dB/dθ
    rate_x = -(b[1] * rate_b[1] + b[2] * rate_b[2]) / x  # from x² + B_y² + B_z² = ROD²
    rate_d = (rate_b - [rate_x, 0.0, 0.0]) / ROD
    alpha, _ = joint_angles(d)
    second = np.array([math.cos(alpha), 0.0, -math.sin(alpha)])  # R_y(α) x
    axes = np.c_[np.cross([0.0, 1.0, 0.0], d), np.cross(second, d)]
    rates = np.linalg.lstsq(axes, rate_d, rcond=None)[0]  # (α̇, β̇) per unit θ̇
    omega = rates[0] * np.array([0.0, 1.0, 0.0]) + rates[1] * second
    centre = (rate_b + [rate_x, 0.0, 0.0]) / 2.0
    rod = I_ACROSS * omega @ omega - (I_ACROSS - I_AXIAL) * (d @ omega) ** 2
    mass = I_CRANK + M_ROD * centre @ centre + rod + M_SLIDER * rate_x**2
    z_crank = A[2] + CRANK / 2.0 * math.cos(theta)
    potential = G * (M_CRANK * z_crank + M_ROD * b[2] / 2.0)  # the rod's centre: (B + C)/2
    return mass, potential


class Reference:
    """The reference motion: one turn's time T [s] and θ(t), x(t) (module docstring)."""

    def __init__(self) -> None:
        mass, potential = energy_terms(0.0)
        self.energy = 0.5 * mass * RATE**2 + potential
        """E0 [J]."""
        self.turn, self.quad_error = scipy.integrate.quad(
            self._integrand, 0.0, 2.0 * math.pi, epsabs=1e-14, epsrel=1e-14, limit=200
        )
        """T [s], one turn of the crank, by quad."""
        nodes = math.pi * (1.0 - np.cos(np.pi * (np.arange(NODES) + 0.5) / NODES))
        values = [self._integrand(theta) for theta in nodes]
        series = chebyshev.Chebyshev.fit(nodes, values, NODES - 1, domain=[0.0, 2.0 * math.pi])
        self.tail = float(np.abs(series.coef[-8:]).max() / np.abs(series.coef[0]))
        """The Chebyshev series' last coefficients relative to its first: its resolution."""
        self._time = series.integ(lbnd=0.0)
        self.chebyshev_turn = float(self._time(2.0 * math.pi))
        """T [s] by the Chebyshev interpolant (agrees with :attr:`turn` when resolved)."""

    def _integrand(self, theta: float) -> float:
        """dt/dθ = √(m / 2(E0 − V)) [s/rad]."""
        mass, potential = energy_terms(theta)
        return math.sqrt(mass / (2.0 * (self.energy - potential)))

    def angle(self, t: np.ndarray) -> np.ndarray:
        """θ(t) (N,) [rad], wound (not wrapped), at the times t (N,) [s] from the start."""
        out = np.empty(len(t))
        for i, time in enumerate(np.asarray(t, dtype=float)):
            turns, phase = divmod(time, self.chebyshev_turn)
            within = scipy.optimize.brentq(
                lambda theta, phase=phase: self._time(theta) - phase,
                0.0, 2.0 * math.pi, xtol=1e-15,
            )  # fmt: skip
            out[i] = 2.0 * math.pi * turns + within
        return out

    def rate(self, theta: np.ndarray) -> np.ndarray:
        """θ̇ (N,) [rad/s] at the crank angles θ (N,), from the energy."""
        return np.array([1.0 / self._integrand(value) for value in theta])

    def slider(self, theta: np.ndarray) -> np.ndarray:
        """The slider's x (N,) [m] at the crank angles θ (N,)."""
        return np.array([pose(value)[1] for value in theta])


if __name__ == "__main__":
    reference = Reference()
    print(f"one turn: {reference.turn:.12f} s (quad, error {reference.quad_error:.1e})")
    print(f"one turn: {reference.chebyshev_turn:.12f} s (Chebyshev, tail {reference.tail:.1e})")
    times = np.array([0.0, 0.5, 1.0, 2.0, 5.0])
    angles = reference.angle(times)
    for time, theta, x, rate in zip(
        times, angles, reference.slider(angles), reference.rate(angles), strict=True
    ):
        print(f"t = {time:3.1f} s: crank {theta:.9f} rad, {rate:.9f} rad/s; slider at {x:.9f} m")
