"""What the figures show, without drawing anything (no matplotlib): the time histories of a
cycle, their file names (named for the payload), the words for each quantity, the unit an
engineer reads for each SI unit, and the one format of the elevation and of a set of them.

:mod:`feeder.viz.report` names and ships the figures from here before matplotlib is loaded;
:mod:`feeder.viz.figures` draws them.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass

from ..study.columns import COLUMNS

UNITS = {column.name: column.unit for column in COLUMNS}
"""SI unit of every ``cycle.csv`` column."""

DISPLAY_UNITS = {
    "m": (1e3, "mm"),
    "N": (1e-3, "kN"),
    "Pa": (1e-5, "bar"),
    "rad": (180 / math.pi, "deg"),
}
"""SI unit → (factor, the unit figures show); any other unit (N·m, m/s, s) is shown as it is."""


WORDS = {
    "projectile_speed": "payload speed",
    "piston_force": "piston force",
    "forearm_torque": "forearm moment",
    "cylinder_cap_pressure": "cap-side pressure",
    "cylinder_rod_pressure": "rod-side pressure",
    "cylinder_frame_force": "cylinder–frame joint force",
    "piston_cylinder_force": "piston guide side force",
    "piston_cylinder_moment": "piston guide moment",
    "piston_arm_force": "piston–arm pin force",
    "arm_frame_force": "arm–frame joint force",
    "arm_frame_moment": "arm–frame bearing moment",
    "forearm_joint_force": "forearm–arm joint force",
    "forearm_joint_moment": "forearm–arm joint moment",
    "grip_force": "grip force",
    "grip_moment": "grip moment",
    "rack_force": "rack force",
}
"""``cycle.csv`` column → the words a legend or axis label uses for it (the loads and
reactions that figures compare; the columns' meanings are in
:data:`~feeder.study.columns.COLUMNS`)."""


def words(column: str) -> str:
    """The words for a ``cycle.csv`` column (:data:`WORDS`; another column's name with spaces
    for its underscores)."""
    return WORDS.get(column, column.replace("_", " "))


PAYLOAD = "{payload}"
"""Where a figure's name holds the payload's (:func:`file_name`)."""


def file_name(figure: str, payload: str) -> str:
    """The file name of the figure ``figure`` for a payload named ``payload``:
    ``fig08_{payload}_speed.png`` is ``fig08_charge_speed.png`` for the charge (the payload's
    name in lower case, runs of other characters than letters and digits as one ``_``)."""
    slug = re.sub(r"[^a-z0-9]+", "_", payload.lower()).strip("_") or "payload"
    return figure.replace(PAYLOAD, slug)


def display_unit(unit: str) -> tuple[float, str]:
    """(factor, unit) that turns a value in the SI ``unit`` into the unit a figure shows."""
    return DISPLAY_UNITS.get(unit, (1.0, unit))


def elevation_text(elevation: float) -> str:
    """``ε = −4°``: the elevation [rad] as every title writes it (to 0.01°, no trailing zeros,
    a true minus sign)."""
    degrees = round(math.degrees(elevation), 2) + 0.0  # + 0.0: no "−0"
    return f"ε = {degrees:g}°".replace("-", "−")


SAME_STEP = 1e-9
"""[deg] Elevations are evenly spaced when their steps differ by no more."""


def elevations_text(elevations_deg: Sequence[float]) -> str:
    """``ε = 30°``, ``ε = −4° … 70° (every 2°)`` for evenly spaced elevations [deg], or
    ``ε = −4°, 30°, 70°`` listed when they are not (a true minus sign)."""
    e = [float(x) for x in elevations_deg]
    steps = [b - a for a, b in zip(e, e[1:], strict=False)]
    if steps and all(abs(s - steps[0]) <= SAME_STEP for s in steps):
        text = f"ε = {e[0]:g}° … {e[-1]:g}° (every {steps[0]:g}°)"
    else:
        text = "ε = " + ", ".join(f"{x:g}°" for x in e)
    return text.replace("-", "−")


@dataclass(frozen=True)
class CycleFigure:
    """One time history of a cycle.

    Attributes:
        file: File name, :data:`PAYLOAD` standing for the payload's name (:func:`file_name`).
        title: Title (the elevation is appended).
        quantity: Axis label without the unit.
        curves: (legend, ``cycle.csv`` column) pairs; all columns share one unit.
        magnitude: Legend of the curve drawn over the others, or None.
    """

    file: str
    title: str
    quantity: str
    curves: tuple[tuple[str, str], ...]
    magnitude: str | None = None

    @property
    def unit(self) -> str:
        """The SI unit of the curves."""
        return UNITS[self.curves[0][1]]


def _vector(file: str, title: str, name: str, quantity: str = "force") -> CycleFigure:
    curves = (("magnitude", name), *((axis, f"{name}_{axis}") for axis in "xyz"))
    return CycleFigure(file, title, quantity, curves, magnitude="magnitude")


CYCLE_FIGURES: tuple[CycleFigure, ...] = (
    CycleFigure(
        "fig08_{payload}_speed.png",
        "Payload CG speed (cf. paper Fig. 8)",
        "speed |v_G|",
        (("|v_G|", "projectile_speed"),),
    ),
    _vector(
        "fig11_forearm_joint_force.png",
        "Reaction force in the forearm–arm joint (cf. Fig. 11)",
        "forearm_joint_force",
    ),
    _vector(
        "fig12_cylinder_frame_force.png",
        "Reaction force in the cylinder–frame joint (cf. Fig. 12)",
        "cylinder_frame_force",
    ),
    _vector(
        "fig13_piston_arm_force.png",
        "Pin force between piston and arm (cf. Fig. 13)",
        "piston_arm_force",
    ),
    CycleFigure(
        "fig14_piston_force.png",
        "Actuator force along the piston axis (cf. Fig. 14)",
        "piston force",
        (("piston force", "piston_force"),),
    ),
    CycleFigure(
        "fig15_forearm_torque.png",
        "Actuator moment about the forearm axis (cf. Fig. 15)",
        "forearm moment",
        (("forearm moment", "forearm_torque"),),
    ),
    _vector("arm_frame_force.png", "Reaction force in the arm–frame joint", "arm_frame_force"),
    CycleFigure(
        "cylinder_pressure.png",
        "Lift-cylinder chamber pressure (ideal, push on the cap side)",
        "pressure",
        (("cap side", "cylinder_cap_pressure"), ("rod side", "cylinder_rod_pressure")),
    ),
    CycleFigure(
        "rack_force.png", "Forearm rack force", "rack force", (("rack force", "rack_force"),)
    ),
)
"""The time histories of a full cycle."""
