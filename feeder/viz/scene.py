"""The one MeshCat scene of a mechanism's motion — the feeding device's
(:mod:`feeder.viz.device_scene`) and a user's model (:mod:`feeder.viz.model_scene`) alike: what
to draw (:class:`MechanismScene`) and its builder (:func:`draw_scene`), which loads the bodies,
draws the client's overlays (:mod:`feeder.viz.overlays`) and arrows
(:mod:`feeder.viz.arrows`), frames the drawing (:mod:`feeder.viz.framing`) and animates it.

The scene lives under the node :data:`~feeder.viz.nodes.ROOT` in the model's own coordinates
standing level (the level axes), turned so that "up" (against gravity) is MeshCat's z and
centred on the drawing, whose centre is the camera's orbit target. Every colour drawn has an
entry in :attr:`~feeder.viz.legend.DrawnScene.legend`.

A moving base (a vehicle's hull, :class:`~feeder.chain.BaseMotion`): whatever rides on it — the
bodies, the arrows (their vectors are in the model's axes moving with the base), the overlays —
is drawn under the node :data:`~feeder.viz.nodes.BASE`, whose transform at each key frame is the
base's placement in the level axes, over a flat box (the hull) under the bodies; the floor grid,
the camera's "up" and MeshCat's triad stay level. On a base at rest :data:`BASE` keeps MeshCat's
identity.

Time: the animation plays the motion at its own pace, or slower for a short one (at least
:data:`MIN_PLAYBACK` seconds); :attr:`DrawnScene.slow_motion` says by how much.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import meshcat
import meshcat.animation
import numpy as np
import pinocchio as pin

from ..chain.results import BaseState
from ._visualizer import MeshcatVisualizer
from .arrows import Arrows, DrawnArrows, arrow_length, draw_arrows
from .framing import GRID_COLOR, HULL_COLOR, draw_hull, frame_scene
from .key_frames import key_transforms
from .legend import DrawnScene, LegendEntry, css
from .nodes import ANIMATION, BASE
from .overlays import Overlay
from .placements import (
    base_placements,
    extent_of,
    geometry_placements,
    geometry_sphere,
    in_level_axes,
    sphere_centres,
    up_of,
)

FRAME_RATE = 40.0
"""Animation key frames per second of playback [1/s]; the motion's samples are subsampled."""

MIN_PLAYBACK = 3.0
"""Shortest playback [s]: a faster motion (a 30 ms forward run) is played in slow motion."""
_HULL_LABEL = (
    "the moving base (a vehicle's hull): the bodies and the arrows ride on it; the floor grid "
    "stays level"
)


@dataclass(frozen=True)
class MechanismScene:
    """A mechanism's motion as the scene builder draws it, N samples.

    Attributes:
        model: The Pinocchio model (open tree) whose bodies are drawn.
        visuals: Their visual geometries (a URDF's visuals, or a stick figure).
        node: The bodies' node under :data:`~feeder.viz.nodes.BASE` (``device``,
            ``mechanism``).
        t: Sample times [s], (N,).
        joints: World placements of every joint at the samples (N, njoints, 4, 4)
            (:func:`~feeder.viz.placements.joint_placements`), model axes.
        arrows: Force and moment arrows, model axes (moving with the base).
        title: The legend's title.
        axes: What MeshCat's x-y-z triad marks.
        boundaries: The time line [s]: start, the ends of the stages, end.
        body_legend: The bodies' legend entries (first in the legend).
        overlays: Drawn after the bodies, in this order; their entries follow the bodies'.
        notes: Legend entries after the arrows'.
        stages: What happens in each stage (len(boundaries) − 1 texts, or none).
        base: The base's motion at the samples (None: at rest).
        arrow_length: Drawn length [m] of the largest force and moment (None: a third of the
            bodies' extent, :func:`~feeder.viz.arrows.arrow_length`).
        waiting: Link name → (N,) bool: the samples at which the link's visuals wait where
            they are at its first other sample instead of following their joint (the device's
            payload on the conveyor until the grip).
    """

    model: pin.Model
    visuals: pin.GeometryModel
    node: str
    t: np.ndarray
    joints: np.ndarray
    arrows: Arrows
    title: str
    axes: str
    boundaries: tuple[float, ...]
    body_legend: tuple[LegendEntry, ...]
    overlays: tuple[Overlay, ...] = ()
    notes: tuple[LegendEntry, ...] = ()
    stages: tuple[str, ...] = ()
    base: BaseState | None = None
    arrow_length: float | None = None
    waiting: Mapping[str, np.ndarray] = field(default_factory=dict)


def _placements(scene: MechanismScene, visuals: pin.GeometryModel) -> np.ndarray:
    """World placements (N, n_geometries, 4, 4) of the visual geometries over the motion, the
    :attr:`~MechanismScene.waiting` links' held where they wait."""
    out = geometry_placements(scene.joints, visuals)
    for link, waiting in scene.waiting.items():
        frame = scene.model.getFrameId(link)
        on_link = np.array([g.parentFrame == frame for g in visuals.geometryObjects])
        out[np.ix_(waiting, on_link)] = out[int(np.argmin(waiting))][on_link]
    return out


def _fixed(
    points: list[np.ndarray], count: int, base: np.ndarray | None
) -> tuple[np.ndarray, np.ndarray]:
    """Points (m, 3) [m] fixed in the model's axes (concatenated from ``points``) as spheres of
    no radius at ``count`` samples, in the level axes (on the base's placements (count, 4, 4))."""
    fixed = np.concatenate([np.empty((0, 3)), *points])
    placed = in_level_axes(np.broadcast_to(fixed, (count, *fixed.shape)), base)
    return placed, np.zeros(count * len(fixed))


def _key_frames(t: np.ndarray) -> tuple[float, np.ndarray]:
    """The playback time per second of motion and the samples (K,) shown at key frames."""
    duration = float(t[-1] - t[0])
    slow = max(1.0, MIN_PLAYBACK / duration) if duration > 0.0 else 1.0
    frames = max(2, math.ceil(duration * slow * FRAME_RATE) + 1)
    return slow, np.unique(np.linspace(0, t.size - 1, min(frames, t.size)).round().astype(int))


def draw_scene(viz: MeshcatVisualizer, scene: MechanismScene) -> DrawnScene:
    """Draw and animate ``scene`` in Pinocchio's visualizer ``viz`` (holding the scene's model
    and visuals): the bodies, the overlays, the arrows, the hull of a moving base, the floor
    grid and the camera; return the arrows' scales, the legend and the time line."""
    vis, t = viz.viewer, scene.t
    viz.loadViewerModel(rootNodeName=f"{BASE}/{scene.node}")
    items = viz.visual_model.geometryObjects
    placements = _placements(scene, viz.visual_model)
    centres, radii = zip(*(geometry_sphere(g) for g in items), strict=True)
    points, reach = sphere_centres(placements, np.array(centres)), np.array(radii)
    extent = extent_of(points, reach)
    nodes = [viz.getViewerNodeName(g, pin.GeometryType.VISUAL) for g in items]
    tracks = {node: placements[:, k] for k, node in enumerate(nodes)}
    legend, fixed = list(scene.body_legend), []
    for overlay in scene.overlays:
        drawn = overlay.draw(vis, scene.model, scene.joints, extent)
        tracks |= drawn.tracks
        fixed.append(drawn.points)
        legend += drawn.legend
    base, up = base_placements(scene.base), up_of(scene.model.gravity.linear)
    length = scene.arrow_length or arrow_length(extent)
    slow, samples = _key_frames(t)
    seen = [(in_level_axes(points, base), np.tile(reach, t.size)), _fixed(fixed, t.size, base)]
    hull = ()
    if base is not None:
        seen.append(_fixed([draw_hull(vis, points, reach, up)], t.size, base))
        hull = (LegendEntry(css(HULL_COLOR), "body", _HULL_LABEL),)
    arrows = draw_arrows(vis, scene.arrows, samples, length, base)
    seen.append((arrows.points, arrows.reach))
    seen_points, seen_reach = zip(*seen, strict=True)
    step = frame_scene(vis, np.concatenate(seen_points), np.concatenate(seen_reach), up)
    grid = LegendEntry(css(GRID_COLOR), "line", f"floor grid, {step:g} m squares")
    _animate(vis, t, samples, slow, tracks, arrows, base)
    return DrawnScene(
        newtons_per_metre=arrows.newtons_per_metre,
        moment_scale=arrows.moment_scale,
        arrow_length=length,
        legend=(*legend, grid, *hull, *arrows.legend, *scene.notes),
        boundaries=scene.boundaries,
        stages=scene.stages,
        slow_motion=slow,
        axes=scene.axes,
    )


def _animate(
    vis: meshcat.Visualizer,
    t: np.ndarray,
    samples: np.ndarray,
    slow: float,
    tracks: Mapping[str, np.ndarray],
    arrows: DrawnArrows,
    base: np.ndarray | None,
) -> None:
    """Place everything at the first sample and, over a motion of times t [s] (N,), animate
    the key frames of ``samples`` (K,) played ``slow`` times slower: the base's placements
    (N, 4, 4) or None, the nodes' ``tracks`` (N, 4, 4) and the arrows."""
    if base is not None:
        vis[BASE].set_transform(base[0])
    for node, placements in tracks.items():
        vis[node].set_transform(placements[0])
    arrows.place(vis)
    if t.size == 1:
        return
    animation = meshcat.animation.Animation(default_framerate=FRAME_RATE)
    frames = ((t[samples] - t[0]) * slow * FRAME_RATE).tolist()
    if base is not None:
        key_transforms(animation, vis[BASE], frames, base[samples])
    for node, placements in tracks.items():
        key_transforms(animation, vis[node], frames, placements[samples])
    arrows.key_frames(animation, vis, frames)
    # Kept on a node of its own, created last: MeshCat sends a scene node by node in creation
    # order, so the animation comes after every set_transform (Pinocchio's included) and a late
    # transform cannot undo a pause at a chosen time.
    vis[ANIMATION].set_animation(animation, play=True, repetitions=1)
