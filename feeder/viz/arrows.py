"""Force and moment arrows of a scene: the series to draw (:class:`Arrows`, model axes), their
one scale per kind, and their shafts' and heads' placements at the animation's key frames.

Arrows are drawn unlit, over the bodies (no depth test, rendered last): they start at points
inside the bodies (a joint, a centre of gravity) and would otherwise be hidden at most poses.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import meshcat
import meshcat.animation
import meshcat.geometry as mg
import numpy as np

from .key_frames import key_property, key_transforms
from .legend import LegendEntry, css, note
from .nodes import BASE, ON_TOP
from .placements import homogeneous, in_level_axes, y_onto

ForceSeries = tuple[np.ndarray, np.ndarray]
"""(vector, point): forces [N] (or moments [N·m]) and their application points [m] in the
model's axes (moving with the base, if it moves), each (N, 3), one row per motion sample."""

ARROW_LENGTH = 0.45
"""Drawn length [m] of the largest force over the motion; all force arrows share one scale
[N/m] (moments another [N·m/m]). A third of the feeding device's size, so that a force a tenth
of the largest is still drawn 45 mm long (tests/viz/test_viewer.py checks that every such arrow
shows on screen at every stage of the cycle); a mechanism's arrows are scaled to its size
(:func:`arrow_length`)."""

ARROW_COLORS = (
    0x8E24AA, 0x00ACC1, 0xD81B60, 0x00C853, 0xFF6D00, 0x3949AB, 0x6D4C41, 0xC0CA33, 0x000000,
    0x00897B,
)  # fmt: skip
"""Colours of the arrows, in the order the loads are given: none is a device colour. A scene
draws at most this many arrows (:func:`draw_arrows` says which it left out)."""
_ARROW_RADIUS, _HEAD_RADIUS = 0.010, 0.025  # [m] at ARROW_LENGTH
HEAD_LENGTH = 0.06
"""[m] An arrow head's cone at :data:`ARROW_LENGTH` (scaled with an arrow's drawn length)."""
_INVISIBLE = 1e-6  # scale of a zero-length arrow part (a zero scale makes a singular matrix)
_PARTS = ("shaft", "head")


@dataclass(frozen=True)
class Arrows:
    """Arrows to draw: force series by name (one scale), moment series by name (another)."""

    forces: Mapping[str, ForceSeries]
    moments: Mapping[str, ForceSeries]

    def scales(self, length: float) -> tuple[float, float]:
        """[N/m] and [N·m/m]: the largest force, and the largest moment, drawn ``length`` long."""

        def peak(series: Mapping[str, ForceSeries]) -> float:
            peaks = (float(np.linalg.norm(v, axis=1).max()) for v, _ in series.values())
            return max(peaks, default=0.0)

        return peak(self.forces) / length, peak(self.moments) / length


def arrow_length(extent: float) -> float:
    """Drawn length [m] of the largest arrow for a drawing ``extent`` [m] across: a third of
    it, as the device's :data:`ARROW_LENGTH` is of its ~1.4 m."""
    return extent / 3.0 if extent > 0.0 else ARROW_LENGTH


def arrow_placements(force: np.ndarray, point: np.ndarray, per_metre: float, size: float) -> dict:
    """Placements of one arrow at n samples; ``force``, ``point`` (n, 3) [N or N·m], [m].

    The arrow starts at the point and is ``|force| / per_metre`` long; its head is at most a
    third of it. Shaft and head are MeshCat cylinders along y, of unit height and of height
    ``size`` × :data:`HEAD_LENGTH`, scaled by ``shaft_scale`` and ``head_scale``.

    Returns:
        ``shaft``, ``head``: rigid placements (n, 4, 4); ``shaft_scale``, ``head_scale``:
        scale factors (n, 3); ``tip``: arrow tips (n, 3) [m].
    """
    magnitude = np.linalg.norm(force, axis=1)
    length = magnitude / per_metre if per_metre > 0.0 else 0.0 * magnitude
    direction = np.where(magnitude[:, None] > 0.0, force, [0.0, 1.0, 0.0])
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    head_length = size * HEAD_LENGTH
    head = np.clip(length / (3.0 * head_length), _INVISIBLE, 1.0)
    shaft = np.maximum(length - head * head_length, _INVISIBLE)
    rotations = [y_onto(d) for d in direction]
    shaft_centres = point + direction * (shaft / 2.0)[:, None]
    head_centres = point + direction * (length - head * head_length / 2.0)[:, None]
    return {
        "shaft": np.array([homogeneous(*rc) for rc in zip(rotations, shaft_centres, strict=True)]),
        "head": np.array([homogeneous(*rc) for rc in zip(rotations, head_centres, strict=True)]),
        "shaft_scale": np.column_stack([np.ones_like(shaft), shaft, np.ones_like(shaft)]),
        "head_scale": np.repeat(head[:, None], 3, axis=1),
        "tip": point + direction * length[:, None],
    }


@dataclass(frozen=True)
class DrawnArrows:
    """The arrows :func:`draw_arrows` created, at the animation's K key frames.

    Attributes:
        newtons_per_metre, moment_scale: The forces' scale [N/m] and the moments' [N·m/m].
        keys: Each arrow's node → :func:`arrow_placements` at the key frames.
        legend: One entry per arrow, and a note naming those left out.
        points, reach: Spheres the camera must see: tails, tips and heads' radii, level axes,
            (2 K · arrows, 3) [m] and (2 K · arrows,) [m].
    """

    newtons_per_metre: float
    moment_scale: float
    keys: dict[str, dict]
    legend: tuple[LegendEntry, ...]
    points: np.ndarray
    reach: np.ndarray

    def place(self, vis: meshcat.Visualizer) -> None:
        """Place every arrow as at the first key frame (the scale in the matrix: a static page
        applies a node's transform after its properties)."""
        for node, arrow in self.keys.items():
            for part in _PARTS:
                scale = np.diag([*arrow[f"{part}_scale"][0], 1.0])
                vis[f"{node}/{part}"].set_transform(arrow[part][0] @ scale)

    def key_frames(
        self, animation: meshcat.animation.Animation, vis: meshcat.Visualizer, frames: list
    ) -> None:
        """Place every arrow in ``animation`` at its K key ``frames`` (K,)."""
        for node, arrow in self.keys.items():
            for part in _PARTS:
                key_transforms(animation, vis[f"{node}/{part}"], frames, arrow[part])
                scale = arrow[f"{part}_scale"]
                key_property(animation, vis[f"{node}/{part}"], frames, "scale", "vector3", scale)


def draw_arrows(
    vis: meshcat.Visualizer,
    arrows: Arrows,
    samples: np.ndarray,
    length: float,
    base: np.ndarray | None,
) -> DrawnArrows:
    """Create the arrows (at most one per colour of :data:`ARROW_COLORS`, the others named in
    a note) under :data:`~feeder.viz.nodes.BASE` and place them at the motion's ``samples``
    (K,) (the key frames), the largest force (and moment) drawn ``length`` [m] long, on the
    base's placements (N, 4, 4) in the level axes (None: at rest)."""
    size = length / ARROW_LENGTH  # arrow thickness follows its length
    newtons_per_metre, moment_scale = arrows.scales(length)
    series = [(n, s, newtons_per_metre, "") for n, s in arrows.forces.items()]
    moment = " (moment, right-hand rule)"
    series += [(n, s, moment_scale, moment) for n, s in arrows.moments.items()]
    left_out = [name for name, *_ in series[len(ARROW_COLORS) :]]
    placed = None if base is None else base[samples]
    keys, legend, points, reach = {}, [], [], []
    for k, (name, (vector, point), scale, kind) in enumerate(series[: len(ARROW_COLORS)]):
        node = f"{BASE}/forces/{name}"
        color = ARROW_COLORS[k]
        legend.append(LegendEntry(css(color), "arrow", name + kind))
        material = mg.MeshBasicMaterial(color=color, depthTest=False)
        vis[f"{node}/shaft"].set_object(mg.Cylinder(1.0, size * _ARROW_RADIUS), material)
        vis[f"{node}/head"].set_object(
            mg.Cylinder(size * HEAD_LENGTH, radiusTop=0.0, radiusBottom=size * _HEAD_RADIUS),
            material,
        )
        for part in _PARTS:
            vis[f"{node}/{part}"].set_property("renderOrder", ON_TOP)
        keys[node] = arrow_placements(vector[samples], point[samples], scale, size)
        ends = np.stack([point[samples], keys[node]["tip"]], axis=1)
        points.append(in_level_axes(ends, placed))
        reach.append(np.tile([0.0, size * _HEAD_RADIUS], samples.size))
    if left_out:
        legend.append(note(f"not drawn (one colour per arrow): {left_out}"))
    return DrawnArrows(
        newtons_per_metre,
        moment_scale,
        keys,
        tuple(legend),
        np.concatenate(points) if points else np.empty((0, 3)),
        np.concatenate(reach) if reach else np.empty(0),
    )
