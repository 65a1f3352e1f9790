"""The quintic Hermite interpolant of sampled motions (feeder.hermite): exact for
a quintic, sixth order on a smooth motion, and SciPy's BPoly.from_derivatives."""

from __future__ import annotations

import numpy as np
from scipy.interpolate import BPoly

from feeder.hermite import quintic_hermite


def _samples(h: float):
    t = np.arange(0.0, 1.0 + 0.5 * h, h)
    q = np.column_stack([np.sin(3.0 * t), np.exp(t)])
    v = np.column_stack([3.0 * np.cos(3.0 * t), np.exp(t)])
    a = np.column_stack([-9.0 * np.sin(3.0 * t), np.exp(t)])
    return t, q, v, a


def test_a_quintic_is_its_own_interpolant_and_a_smooth_motion_converges_at_sixth_order():
    t = np.linspace(0.0, 2.0, 9)
    c = np.array([0.3, -1.0, 0.5, 2.0, -0.7, 0.11])  # c0 … c5
    powers = t[:, None] ** np.arange(6)
    q = powers @ c
    v = (powers[:, :5] * np.arange(1, 6)) @ c[1:]
    a = (powers[:, :4] * np.arange(1, 5) * np.arange(2, 6)) @ c[2:]
    fine = np.linspace(0.0, 2.0, 101)
    exact = (fine[:, None] ** np.arange(6)) @ c
    interpolant = quintic_hermite(t, q[:, None], v[:, None], a[:, None])
    # a quintic is its own Hermite interpolant: round-off of terms of size ~10
    np.testing.assert_allclose(interpolant(fine)[:, 0], exact, rtol=0, atol=1e-12)
    errors = []
    for h in (0.1, 0.05):
        t, q, v, a = _samples(h)
        x = np.linspace(0.0, 1.0, 997)
        errors.append(np.abs(quintic_hermite(t, q, v, a)(x)[:, 0] - np.sin(3.0 * x)).max())
    # halving h divides an O(h⁶) error by 64; 40 leaves room for the higher terms
    assert errors[0] / errors[1] > 40.0


def test_it_is_scipys_interpolant_from_the_derivatives():
    rng = np.random.default_rng(7)
    t = np.cumsum(rng.uniform(0.1, 1.0, 40))
    x, dx, ddx = (rng.normal(size=(40, 3)) for _ in range(3))
    ours = quintic_hermite(t, x, dx, ddx)
    fine = np.linspace(t[0], t[-1], 2001)
    for i in range(3):
        scipys = BPoly.from_derivatives(t, np.stack([x[:, i], dx[:, i], ddx[:, i]], axis=1))
        for order in range(3):
            # the same polynomials, their coefficients formed in another order: round-off of
            # unit data, grown by the second derivative's 1/h² ≤ 100 and 20 · 5 Bernstein terms
            np.testing.assert_allclose(
                ours.derivative(order)(fine)[:, i] if order else ours(fine)[:, i],
                scipys.derivative(order)(fine) if order else scipys(fine),
                rtol=0,
                atol=1e-15 * 100**order * 100,
            )
