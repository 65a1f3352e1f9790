"""The geometric constraints of ``feeder design optimize``, in closed form over the arm's whole
travel (the loop of :mod:`feeder.device.loop`: no cycle is run for them).

The travel is the one :func:`~feeder.device.loop.check_travel` checks: from the loading pose to
the lowest elevation's ramming pose, at the same :data:`~feeder.device.loop.TRAVEL_SAMPLES` arm
angles, so that a geometry meeting these constraints passes every check of its parameter file.
Each constraint is a margin that holds when ≥ 0, in its unit:

* ``transmission_low``, ``transmission_high`` [deg]: the transmission angle μ inside the band;
* ``toggle`` [deg]: min(μ, 180° − μ) at least the toggle margin away;
* ``end_stop_retracted``, ``end_stop_extended`` [m]: the piston position r2 at least the
  clearance inside the end stops ``r2_min``, ``r2_max`` (the loop assembles in the cylinder);
* ``stroke`` [m]: the cylinder's stroke r2_max − r2_min at most ``max_stroke``;
* ``swing_low``, ``swing_high`` [deg]: the cylinder's angle φ1 inside its swing
  [phi1_min, phi1_max] (the loop assembles within the cylinder's joint limits).

The optimiser sees each margin divided by its :attr:`Constraint.scale`: 10° for an angle (the
transmission angle moves ~10° per unit of the scaled variables of the built-in design) and
0.1 m for a length (the size of the device's links, as the sensitivities' step).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..device.loop import TRAVEL_SAMPLES, arm_travel, solve_loop, transmission_angle
from ..device.parameters import FeederParameters
from .design_space import DesignSpace
from .epigraph import FEASIBLE

ANGLE_SCALE = 10.0
"""[deg] An angle margin of this size counts as 1 for the optimiser (module docstring)."""

LENGTH_SCALE = 0.1
"""[m] A length margin of this size counts as 1 for the optimiser (module docstring)."""


@dataclass(frozen=True)
class Constraint:
    """One constraint: a margin that holds when ≥ 0.

    Attributes:
        name: Its name in ``optimum.csv``.
        unit: The margin's unit (``deg``, ``m``, or a peak's SI unit).
        meaning: What holds.
        scale: The margin that counts as 1 for the optimiser [unit].
    """

    name: str
    unit: str
    meaning: str
    scale: float


def geometry_constraints(space: DesignSpace) -> tuple[Constraint, ...]:
    """The geometric constraints of ``space``, in the order of :func:`geometry_margins`."""
    low, high = space.band_deg
    margin, clearance = space.toggle_margin_deg, space.clearance
    angle, length = ANGLE_SCALE, LENGTH_SCALE
    return (
        Constraint("transmission_low", "deg", f"transmission angle ≥ {low:g}°", angle),
        Constraint("transmission_high", "deg", f"transmission angle ≤ {high:g}°", angle),
        Constraint("toggle", "deg", f"transmission angle ≥ {margin:g}° from the toggle", angle),
        Constraint("end_stop_retracted", "m", f"r2 ≥ r2_min + {clearance:g} m", length),
        Constraint("end_stop_extended", "m", f"r2 ≤ r2_max − {clearance:g} m", length),
        Constraint("stroke", "m", f"r2_max − r2_min ≤ {space.max_stroke:g} m", length),
        Constraint("swing_low", "deg", "cylinder angle φ1 ≥ phi1_min", angle),
        Constraint("swing_high", "deg", "cylinder angle φ1 ≤ phi1_max", angle),
    )


def travel(p: FeederParameters) -> np.ndarray:
    """The arm angles φ3 [rad] at which :func:`~feeder.device.loop.check_travel` checks ``p``,
    (TRAVEL_SAMPLES,)."""
    ends = p.phi3_load + np.array([arm_travel(p.elevation_max), arm_travel(p.elevation_min)])
    return np.linspace(min(p.phi3_load, ends[0]), max(p.phi3_load, ends[1]), TRAVEL_SAMPLES)


def geometry_margins(space: DesignSpace, p: FeederParameters) -> np.ndarray:
    """Each constraint's margin for the parameter set ``p`` [its unit], in the order of
    :func:`geometry_constraints`, (8,)."""
    q = solve_loop(p, travel(p)).q
    mu = np.degrees(transmission_angle(q))
    r2, phi1 = q[:, 1], np.degrees(q[:, 0])
    low, high = space.band_deg
    return np.array(
        [
            mu.min() - low,
            high - mu.max(),
            np.minimum(mu, 180.0 - mu).min() - space.toggle_margin_deg,
            r2.min() - (p.r2_min + space.clearance),
            (p.r2_max - space.clearance) - r2.max(),
            space.max_stroke - (p.r2_max - p.r2_min),
            phi1.min() - math.degrees(p.phi1_min),
            math.degrees(p.phi1_max) - phi1.max(),
        ]
    )


def geometry_met(space: DesignSpace, p: FeederParameters) -> bool:
    """Whether ``p`` meets every geometric constraint (within :data:`FEASIBLE`)."""
    scales = np.array([c.scale for c in geometry_constraints(space)])
    return bool((geometry_margins(space, p) / scales).min() >= -FEASIBLE)


def hugging_stops(space: DesignSpace, p: FeederParameters) -> FeederParameters:
    """``p`` with each end stop that is a variable moved to the travel ± the clearance, within
    its bounds: of all end stops in the bounds, those that meet the end-stop and stroke
    constraints whenever any do (the shortest stroke). A start for the search."""
    r2 = solve_loop(p, travel(p)).q[:, 1]
    wanted = {"r2_min": r2.min() - space.clearance, "r2_max": r2.max() + space.clearance}
    for variable in space.variables:
        if variable.name in wanted:
            value = min(max(wanted[variable.name], variable.lower), variable.upper)
            p = variable.parameter.changed(p, float(value))
    return p
