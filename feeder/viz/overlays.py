"""What a client draws over a mechanism's bodies besides its arrows, given to the one scene
builder (:func:`~feeder.viz.scene.draw_scene`) as :class:`Overlay` objects: a straight rod
fixed in the model's axes (:class:`Rod`: the device's barrel axis), the line a body's point
traces (:class:`Trace`: the payload's path) and balls at the closure cuts (:class:`CutMarkers`).

Each overlay draws itself under :data:`~feeder.viz.nodes.BASE` (it rides on the base) and says
what it drew: the nodes to animate, the points the camera must see and its legend entries.
Lines and markers are drawn unlit, over the bodies (no depth test, rendered last).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Sequence
from dataclasses import dataclass, field

import meshcat
import meshcat.geometry as mg
import numpy as np
import pinocchio as pin

from ..chain import Closure
from .legend import LegendEntry, css
from .nodes import BASE, ON_TOP
from .placements import attached, homogeneous, y_onto


@dataclass(frozen=True)
class OverlayParts:
    """What an overlay drew.

    Attributes:
        tracks: Node path → its placements (N, 4, 4) in the model's axes (animated).
        points: Points (m, 3) [m] fixed in the model's axes that the camera must see.
        legend: Its colours and what they show.
    """

    tracks: dict[str, np.ndarray] = field(default_factory=dict)
    points: np.ndarray = field(default_factory=lambda: np.empty((0, 3)))
    legend: tuple[LegendEntry, ...] = ()


class Overlay(ABC):
    """Something drawn over the bodies (module docstring)."""

    @abstractmethod
    def draw(
        self, vis: meshcat.Visualizer, model: pin.Model, joints: np.ndarray, extent: float
    ) -> OverlayParts:
        """Draw it in ``vis`` for the mechanism ``model`` whose joints' placements over the
        motion are ``joints`` (N, njoints, 4, 4) and whose bodies are ``extent`` [m] across."""


@dataclass(frozen=True)
class Rod(Overlay):
    """A straight rod (a lit cylinder) fixed in the model's axes.

    Attributes:
        name: Its node under :data:`~feeder.viz.nodes.BASE`.
        ends: Its two ends (2, 3) [m], model axes (the camera sees both).
        radius: [m].
        color: 24-bit RGB.
        label: Its legend entry.
    """

    name: str
    ends: np.ndarray
    radius: float
    color: int
    label: str

    def draw(self, vis, model, joints, extent) -> OverlayParts:
        ends = np.asarray(self.ends, dtype=float)
        axis = ends[1] - ends[0]
        length = float(np.linalg.norm(axis))
        node = vis[f"{BASE}/{self.name}"]
        node.set_object(mg.Cylinder(length, self.radius), mg.MeshLambertMaterial(color=self.color))
        node.set_transform(homogeneous(y_onto(axis / length), ends.mean(axis=0)))
        return OverlayParts(
            points=ends,
            legend=(LegendEntry(css(self.color), "line", self.label),),
        )


@dataclass(frozen=True)
class Trace(Overlay):
    """The line a point of a body passes through (the payload's centre of gravity): the bodies'
    framing covers it, so the camera needs none of its points.

    Attributes:
        name: Its node under :data:`~feeder.viz.nodes.BASE`.
        points: The line's vertices (n, 3) [m], model axes.
        color: 24-bit RGB.
        label: Its legend entry.
    """

    name: str
    points: np.ndarray
    color: int
    label: str

    def draw(self, vis, model, joints, extent) -> OverlayParts:
        node = vis[f"{BASE}/{self.name}"]
        vertices = mg.PointsGeometry(np.asarray(self.points).T.astype(np.float32))
        node.set_object(mg.Line(vertices, mg.LineBasicMaterial(color=self.color, depthTest=False)))
        node.set_property("renderOrder", ON_TOP)
        return OverlayParts(legend=(LegendEntry(css(self.color), "line", self.label),))


@dataclass(frozen=True)
class CutMarkers(Overlay):
    """A ball at each closure's first frame (``frame_a``), moving with its body.

    Attributes:
        closures: The closures whose cuts are marked.
        color: 24-bit RGB.
        share: A ball's radius per metre of the bodies' extent.
    """

    closures: Sequence[Closure]
    color: int = 0xE53935
    share: float = 0.012

    def draw(self, vis, model, joints, extent) -> OverlayParts:
        if not self.closures:
            return OverlayParts()
        tracks = {}
        material = mg.MeshBasicMaterial(color=self.color, depthTest=False)
        for closure in self.closures:
            node = f"{BASE}/cuts/{closure.label}"
            vis[node].set_object(mg.Sphere(self.share * extent), material)
            vis[node].set_property("renderOrder", ON_TOP)
            frame = model.frames[model.getFrameId(closure.frame_a)]
            tracks[node] = attached(joints, frame.parentJoint, frame.placement)
        cuts = ", ".join(closure.label for closure in self.closures)
        return OverlayParts(
            tracks=tracks, legend=(LegendEntry(css(self.color), "body", f"closure cuts: {cuts}"),)
        )
