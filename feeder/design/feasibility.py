"""Points that meet the geometric constraints, found without running a cycle: the nearest such
point to a given one, and the check that the bounds admit any.

The geometric constraints (:mod:`feeder.design.constraints`) are closed forms of the loop, so
the nearest point that meets them, in the variables scaled to [0, 1] by their bounds, is a small
SLSQP problem (min |z − z₀|² subject to the scaled margins ≥ 0, central differences) that costs
milliseconds. The global start moves each sample there before running its cycles (a sample of
the bounds seldom meets a stroke constraint that leaves a few millimetres to spare); the check
below tries it from the start and from a few samples, before the output folder is made.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import minimize
from scipy.stats import qmc

from ..exceptions import InputError
from .constraints import FEASIBLE, geometry_constraints, geometry_margins
from .design_space import DesignSpace, with_values
from .differences import step

TRIES = 8
"""Samples of the bounds (besides the start) the check of :func:`check_feasible` moves to the
constraints before it refuses the bounds."""


def _scaled_margins(space: DesignSpace, x: np.ndarray) -> np.ndarray:
    scales = np.array([c.scale for c in geometry_constraints(space)])
    return geometry_margins(space, with_values(space, x)) / scales


def nearest_feasible(space: DesignSpace, x: np.ndarray, tolerance: float = 0.0) -> np.ndarray:
    """The point nearest ``x`` [the variables' units] in the scaled variables that meets every
    geometric constraint to ``tolerance`` (scaled), or the point SLSQP ended at (check it)."""
    lower = np.array([v.lower for v in space.variables])
    width = np.array([v.upper for v in space.variables]) - lower

    def margins(z: np.ndarray) -> np.ndarray:
        return _scaled_margins(space, lower + z * width) - tolerance

    def jacobian(z: np.ndarray) -> np.ndarray:
        x = lower + z * width
        columns = []
        for k, variable in enumerate(space.variables):
            h = step(x[k], variable.parameter.scale) * np.eye(len(x))[k]
            columns.append((margins((x + h - lower) / width) - margins((x - h - lower) / width))
                           / (2.0 * h[k] / width[k]))  # fmt: skip
        return np.array(columns).T

    z0 = (np.asarray(x, dtype=float) - lower) / width
    if margins(z0).min() >= -FEASIBLE:
        return np.asarray(x, dtype=float)
    result = minimize(
        lambda z: float(np.sum((z - z0) ** 2)),
        z0,
        jac=lambda z: 2.0 * (z - z0),
        method="SLSQP",
        bounds=[(0.0, 1.0)] * len(z0),
        constraints={"type": "ineq", "fun": margins, "jac": jacobian},
        options={"maxiter": 200, "ftol": 1e-12},
    )
    return lower + np.clip(result.x, 0.0, 1.0) * width


def check_feasible(space: DesignSpace, seed: int = 0) -> None:
    """Raise unless some point within the bounds meets every geometric constraint.

    Raises:
        InputError: None found from the start and :data:`TRIES` samples; the message names the
            constraint the closest point found misses, and by how much.
    """
    lower = np.array([v.lower for v in space.variables])
    width = np.array([v.upper for v in space.variables]) - lower
    points = [np.array([v.start for v in space.variables])]
    points += list(lower + qmc.LatinHypercube(d=len(lower), seed=seed).random(TRIES) * width)
    closest, worst = None, np.inf
    for x in points:
        found = nearest_feasible(space, x)
        margins = _scaled_margins(space, found)
        if margins.min() >= -FEASIBLE:
            return
        if -margins.min() < worst:
            closest, worst = (found, margins), -margins.min()
    found, margins = closest
    constraints = geometry_constraints(space)
    k = int(np.argmin(margins))
    miss = -margins[k] * constraints[k].scale
    where = ", ".join(
        f"{v.name} = {value:.4g} {v.unit}" for v, value in zip(space.variables, found, strict=True)
    )
    unit = constraints[k].unit
    raise InputError(
        f"the bounds admit no geometry that meets the constraints: the closest found ({where}) "
        f"misses {constraints[k].name} ({constraints[k].meaning}) by {miss:.3g} {unit}; widen "
        "the bounds or relax [constraints]"
    )
