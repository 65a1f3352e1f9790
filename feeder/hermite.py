"""The quintic Hermite interpolant of sampled motions (a prescribed motion of the engine's hybrid
runs, :mod:`feeder.chain.dynamics.hybrid_equations`; the device's servo reference,
:mod:`feeder.dynamics.servo`): positions, rates and accelerations at the samples, C² between
them (error O(h⁶) in the position, O(h⁵) in the rate, O(h⁴) in the acceleration for a smooth
motion sampled every h).

On each interval [t_k, t_k+1] of length h the interpolant is the quintic whose Bernstein
coefficients are

    x_k,   x_k + h ẋ_k / 5,   x_k + 2 h ẋ_k / 5 + h² ẍ_k / 20,
    x_k+1 − 2 h ẋ_k+1 / 5 + h² ẍ_k+1 / 20,   x_k+1 − h ẋ_k+1 / 5,   x_k+1

(a Bernstein quintic's first and second derivatives at an end are 5 and 20 times the first and
second differences of its end coefficients over h and h²): the polynomial SciPy's
``BPoly.from_derivatives`` builds, which does it interval by interval in Python (0.13 s for
1 000 samples of two columns, measured); here all intervals and columns at once.
"""

from __future__ import annotations

import numpy as np


def quintic_hermite(t: np.ndarray, x: np.ndarray, dx: np.ndarray, ddx: np.ndarray):
    """The quintic Hermite interpolant (module docstring) of the samples t [s] (N,), N ≥ 2,
    increasing, and x, ẋ, ẍ (N, n) of n columns: one ``scipy.interpolate.BPoly`` whose value at
    a time is the n columns (n,)."""
    from scipy.interpolate import BPoly  # here: only the runs that interpolate pay its import

    h = np.diff(t)[:, None]
    start, end = slice(None, -1), slice(1, None)
    coefficients = np.stack(
        [
            x[start],
            x[start] + h * dx[start] / 5.0,
            x[start] + 2.0 * h * dx[start] / 5.0 + h**2 * ddx[start] / 20.0,
            x[end] - 2.0 * h * dx[end] / 5.0 + h**2 * ddx[end] / 20.0,
            x[end] - h * dx[end] / 5.0,
            x[end],
        ]
    )  # (6, N − 1, n): BPoly's (degree + 1, intervals, columns)
    return BPoly(coefficients, t)
