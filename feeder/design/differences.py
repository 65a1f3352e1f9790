"""Central differences of a function sampled at five points, with the step chosen and checked
here, and the test that tells a kink from a smooth function.

**The step.** A parameter p [unit] is stepped by h = :data:`STEP_FACTOR` · max(|p|, scale)
(:func:`step`; the scale, 0.1 m or 1 kg, keeps the step of a number near zero from vanishing).
ε^(1/3) (ε the float64 machine epsilon) balances the two errors of a central difference of a
function with relative round-off δ and variation on the scale of p: truncation ~ (h/p)²·f and
round-off ~ δ·f·p/h, both ~ ε^(2/3) ≈ 4e-11 of f/p at that step.

**The check.** The function is evaluated at p − h, p − h/2, p, p + h/2, p + h (the steps taken
as the exact differences of the stepped floats, :func:`offsets`). The derivative is the central
difference over h/2, D(h/2); the error estimate is |D(h) − D(h/2)|. For a smooth function the
leading error of D(s) is c·s², so |D(h) − D(h/2)| = ¾ c h², three times the error of D(h/2).

**The kink.** A peak that is the largest of several smooth branches (samples of a cycle,
elevations of a range) has one-sided derivatives that differ where the largest branch changes.
Where that happens between p − h and p + h, the five values are not on one smooth curve: a
least-squares parabola through them leaves a residual of the order of the slope jump times h,
at any position of the kink inside the step (of five points, three always lie on one side, on
one line, and a parabola through three points on a line is that line). A smooth function leaves
its cubic term, 0.3·|f'''|h³, which at the step above is of the order of ε·f, and the
round-off. The kink test (:func:`estimate`) therefore flags a residual larger than
:data:`KINK_MARGIN` × (:data:`NOISE` + STEP_FACTOR³) × max |f|; the forward and backward
differences over h/2 are then the one-sided derivatives a user reads instead of the central one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..exceptions import InputError
from ..validation import check_number

STEP_FACTOR = float(np.finfo(float).eps) ** (1.0 / 3.0)
"""Relative step [-] (6.06e-6): ε^(1/3), module docstring."""

OFFSETS = (-1.0, -0.5, 0.0, 0.5, 1.0)
"""Where the function is evaluated, in multiples of the step h."""

NOISE = 1e-12
"""Relative round-off [-] of one computed peak. Measured on the projectile feeder at −4° and
30° for every parameter: the residual of the five-point parabola (above) is below 1e-15 of the
peak for every load, 5e-14 for the piston guide moment and 2.4e-13 for the piston guide side
force (6.8 N left over from cylinder forces of 3.4 kN); 1e-12 covers the worst with a factor 4."""

KINK_MARGIN = 10.0
"""How many times the round-off and smooth-cubic residual the parabola's residual must exceed
to be called a kink. A kink of slope jump J located anywhere in (p − 0.99 h, p + 0.99 h) leaves
at least 0.003·J·h (0.06·J·h at its median position): at the default step the test sees a
jump of 3e-5 of f/p, a thousandth of a typical derivative."""


def check_step_factor(factor: object) -> float:
    """``factor`` as a relative step in (0, 0.1], else :class:`InputError` naming it."""
    value = check_number("the relative step", factor)
    if not 0.0 < value <= 0.1:
        raise InputError(
            f"the relative step must be positive and at most 0.1 (10 % of each parameter), "
            f"got {factor!r}"
        )
    return value


def step(value: float, scale: float, factor: float = STEP_FACTOR) -> float:
    """The step h = factor · max(|value|, scale) [unit of value] (module docstring)."""
    return factor * max(abs(value), scale)


def offsets(value: float, h: float) -> tuple[np.ndarray, np.ndarray]:
    """The values p + o·h for o in :data:`OFFSETS` and the exact steps taken: (values, steps),
    each (5,). The step of a stepped float is what it differs from p by after rounding, which
    the subtraction gives exactly; the differences below divide by it, not by o·h."""
    stepped = np.array([value + o * h for o in OFFSETS])
    return stepped, stepped - value


@dataclass(frozen=True)
class Estimate:
    """The derivative of a function at p from its values at the five :data:`OFFSETS`.

    Attributes:
        derivative: Central difference over h/2 [unit of f per unit of p].
        error: |D(h) − D(h/2)|, the central differences over h and h/2 [same unit].
        forward: One-sided difference (f(p + h/2) − f(p)) / (h/2) [same unit].
        backward: One-sided difference (f(p) − f(p − h/2)) / (h/2) [same unit].
        residual: Largest residual of the least-squares parabola through the five values,
            relative to their largest magnitude [-].
        kink: The residual exceeds the kink threshold (module docstring): the function is
            not differentiable within the step; read ``forward`` and ``backward``.
    """

    derivative: float
    error: float
    forward: float
    backward: float
    residual: float
    kink: bool


def estimate(values: np.ndarray, steps: np.ndarray, factor: float = STEP_FACTOR) -> Estimate:
    """The :class:`Estimate` from five values of f [unit] at p + ``steps`` (:func:`offsets`).

    Args:
        values: f at the five offsets, (5,), finite.
        steps: The exact steps [unit of p], (5,): −h, −h/2, 0, h/2, h to rounding.
        factor: The relative step the steps were made with (sets the smooth residual allowed).
    """
    f = np.asarray(values, dtype=float)
    x = np.asarray(steps, dtype=float)
    wide = (f[4] - f[0]) / (x[4] - x[0])
    narrow = (f[3] - f[1]) / (x[3] - x[1])
    size = float(np.max(np.abs(f)))
    fit = np.polynomial.polynomial.Polynomial.fit(x, f, 2)
    residual = float(np.max(np.abs(f - fit(x)))) / size if size > 0.0 else 0.0
    return Estimate(
        derivative=float(narrow),
        error=float(abs(wide - narrow)),
        forward=float((f[3] - f[2]) / x[3]),
        backward=float((f[2] - f[1]) / -x[1]),
        residual=residual,
        kink=residual > KINK_MARGIN * (NOISE + factor**3),
    )
