"""What a drawn scene tells its page: the legend (every colour drawn and what it shows), the
arrows' scales and the motion's time line (:class:`DrawnScene`), and the CSS colours they use."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass


@dataclass(frozen=True)
class LegendEntry:
    """One colour of the scene and what it shows.

    Attributes:
        color: CSS colour, ``#rrggbb``.
        mark: How it is drawn: ``"body"``, ``"line"`` or ``"arrow"`` (``"note"``: no colour,
            a remark).
        label: What it is.
    """

    color: str
    mark: str
    label: str


def note(label: str) -> LegendEntry:
    """A legend remark without a colour."""
    return LegendEntry("", "note", label)


@dataclass(frozen=True)
class DrawnScene:
    """What the scene builder drew (:func:`~feeder.viz.scene.draw_scene`).

    Attributes:
        newtons_per_metre: Scale of the force arrows [N/m] (0 without forces).
        moment_scale: Scale of the moment arrows [N·m/m] (0 without moments).
        arrow_length: Drawn length [m] of the largest force (and of the largest moment).
        legend: Every colour of the scene with what it shows.
        boundaries: The motion's time line [s]: its start, the ends of its stages, its end (a
            single time for a pose).
        stages: What happens in each stage (len(boundaries) − 1 texts, or none).
        slow_motion: Playback time per second of motion (≥ 1).
        axes: What MeshCat's x-y-z triad marks.
    """

    newtons_per_metre: float
    moment_scale: float
    arrow_length: float
    legend: tuple[LegendEntry, ...]
    boundaries: tuple[float, ...]
    stages: tuple[str, ...]
    slow_motion: float
    axes: str


def css(color: int) -> str:
    """A 24-bit colour as CSS ``#rrggbb``."""
    return f"#{color:06x}"


def material_css(rgba: Sequence[float]) -> str:
    """The CSS colour Pinocchio's MeshCat visualizer draws for a URDF ``rgba``."""
    r, g, b = (int(255 * float(x)) for x in list(rgba)[:3])
    return f"#{r:02x}{g:02x}{b:02x}"
