"""The MeshCat scene of any mechanism's motion: its visuals animated over the motion, force (and
moment) arrows to one scale, the floor grid and the camera.

One builder for the feeding device (:mod:`feeder.viz.cycle_scene`) and for a user's mechanism
(:mod:`feeder.viz.mechanism_scene`). The scene lives under the node ``feeder`` in the model's
own coordinates standing level (the level axes), turned so that "up" (against gravity) is
MeshCat's z and centred on the drawing, whose centre is the camera's orbit target. Arrows and
lines are drawn unlit, over the bodies (no depth test, rendered last): they start at points
inside the bodies (a joint, a centre of gravity) and would otherwise be hidden at most poses.
Every colour drawn has an entry in :attr:`DrawnScene.legend`.

A moving base (a vehicle's hull, :mod:`feeder.chain.model.base`): whatever rides on it — the
bodies, the arrows (their vectors are in the model's axes moving with the base), the lines —
is drawn under the node :data:`BASE`, whose transform at each key frame is the base's placement
in the level axes, over a flat box (the hull) under the bodies; the floor grid, the camera's
"up" and MeshCat's triad stay level. On a base at rest :data:`BASE` keeps MeshCat's identity.

Time: the animation plays the motion at its own pace, or slower for a short one (at least
:data:`MIN_PLAYBACK` seconds); :attr:`DrawnScene.slow_motion` says by how much.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import meshcat
import meshcat.animation
import meshcat.geometry as mg
import meshcat.transformations as mtf
import numpy as np
import pinocchio as pin

from ..chain.model.base import BaseState

FRAME_RATE = 40.0
"""Animation key frames per second of playback [1/s]; the motion's samples are subsampled."""

MIN_PLAYBACK = 3.0
"""Shortest playback [s]: a faster motion (a 30 ms forward run) is played in slow motion."""

ARROW_LENGTH = 0.45
"""Drawn length [m] of the largest force over the motion; all force arrows share one scale
[N/m] (moments another [N·m/m]). A third of the feeding device's size, so that a force a tenth
of the largest is still drawn 45 mm long (tests/viz/test_viewer.py checks that every such arrow
shows on screen at every stage of the cycle); a mechanism's arrows are scaled to its size
(:func:`arrow_length`)."""

CAMERA_AZIMUTH, CAMERA_ELEVATION = math.radians(35.0), math.radians(25.0)
"""Default view direction [rad]: turned 35° from the model's horizontal axes, looking down 25°."""

CAMERA_FOV = math.radians(75.0)
"""MeshCat's default camera: vertical field of view [rad]."""

ForceSeries = tuple[np.ndarray, np.ndarray]
"""(vector, point): forces [N] (or moments [N·m]) and their application points [m] in the
model's axes (moving with the base, if it moves), each (N, 3), one row per motion sample."""

ROOT = "feeder"
"""The scene's MeshCat node: the level axes."""
BASE = f"{ROOT}/base"
"""The node of whatever rides on the base (bodies, arrows, lines; the model's axes): its
transform is the base's placement in the level axes (identity on a base at rest)."""
ANIMATION = "animation"
GRID_COLOR = 0x8A8F99
HULL_COLOR = 0x6B7353
"""The base's flat box (a vehicle's hull, olive): drawn on a moving base only."""
_HULL_DEPTH, _HULL_MARGIN = 0.04, 0.05  # the hull's thickness and overhang, shares of the extent
_BACKGROUND = ((0.93, 0.94, 0.95), (0.62, 0.65, 0.70))  # MeshCat gradient, top and bottom RGB
ARROW_COLORS = (
    0x8E24AA, 0x00ACC1, 0xD81B60, 0x00C853, 0xFF6D00, 0x3949AB, 0x6D4C41, 0xC0CA33, 0x000000,
    0x00897B,
)  # fmt: skip
"""Colours of the arrows, in the order the loads are given: none is a device colour. A scene
draws at most this many arrows (:func:`draw_scene` says which it left out)."""
_ARROW_RADIUS, _HEAD_RADIUS = 0.010, 0.025  # [m] at ARROW_LENGTH
HEAD_LENGTH = 0.06
"""[m] An arrow head's cone at :data:`ARROW_LENGTH` (scaled with an arrow's drawn length)."""
ON_TOP = 10
"""Render order of arrows and lines: after the bodies, over them."""
_INVISIBLE = 1e-6  # scale of a zero-length arrow part (a zero scale makes a singular matrix)
_FRAME_FILL = 0.9  # the scene's extent fills at most this share of the camera's view
_Y_UP_TO_MESHCAT = mtf.rotation_matrix(math.pi / 2.0, [1.0, 0.0, 0.0])  # y up → MeshCat's z up


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


@dataclass(frozen=True)
class DrawnScene:
    """What a scene builder drew.

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


def homogeneous(rotation: np.ndarray, translation: np.ndarray) -> np.ndarray:
    """The 4 × 4 homogeneous transform of a rotation (3, 3) and a translation (3,)."""
    out = np.eye(4)
    out[:3, :3] = rotation
    out[:3, 3] = translation
    return out


def y_onto(direction: np.ndarray) -> np.ndarray:
    """A rotation (3, 3) turning the y axis onto the unit vector ``direction``."""
    y = np.array([0.0, 1.0, 0.0])
    axis = np.cross(y, direction)
    sine, cosine = np.linalg.norm(axis), float(y @ direction)
    if sine < 1e-9:
        return np.eye(3) if cosine > 0.0 else np.diag([1.0, -1.0, -1.0])
    return pin.AngleAxis(math.atan2(sine, cosine), axis / sine).matrix()


def up_of(gravity: np.ndarray) -> np.ndarray:
    """The unit "up" vector (3,) against ``gravity`` [m/s²]: z (URDF's convention) without
    gravity."""
    norm = float(np.linalg.norm(gravity))
    return -np.asarray(gravity) / norm if norm > 0.0 else np.array([0.0, 0.0, 1.0])


def geometry_sphere(geometry_object: pin.GeometryObject) -> tuple[np.ndarray, float]:
    """A sphere that contains the geometry: its centre (3,) in the geometry's frame and its
    radius [m] (a mesh's bounding box, whose vertices need not surround the frame's origin: CAD
    exports often keep the assembly's origin)."""
    shape = geometry_object.geometry
    if hasattr(shape, "halfSide"):
        return np.zeros(3), float(np.linalg.norm(shape.halfSide))
    if hasattr(shape, "halfLength"):
        return np.zeros(3), float(math.hypot(shape.radius, shape.halfLength))
    if hasattr(shape, "radius"):
        return np.zeros(3), float(shape.radius)
    shape.computeLocalAABB()
    box = shape.aabb_local
    low, high = (np.asarray(x) * geometry_object.meshScale for x in (box.min_, box.max_))
    return (low + high) / 2.0, float(np.linalg.norm(high - low) / 2.0)


def sphere_centres(placements: np.ndarray, centres: np.ndarray) -> np.ndarray:
    """Model-frame centres (N, n, 3) [m] of the geometries' spheres (:func:`geometry_sphere`),
    from their placements (N, n, 4, 4) and local centres (n, 3)."""
    local = np.concatenate([centres, np.ones((len(centres), 1))], axis=1)
    return np.einsum("knij,nj->kni", placements, local)[..., :3]


def base_placements(state: BaseState | None) -> np.ndarray | None:
    """The base's placements (N, 4, 4) in the level axes: the model's moving axes and origin
    (:class:`~feeder.chain.model.base.BaseState` ``rotation``, ``position`` [m]); None for a base
    at rest."""
    if state is None:
        return None
    return np.array([homogeneous(*rp) for rp in zip(state.rotation, state.position, strict=True)])


def joint_placements(model: pin.Model, q: np.ndarray) -> np.ndarray:
    """World placements (N, njoints, 4, 4) of every joint at the poses q (N, nq): one forward
    kinematics pass per pose, from which the geometries' and frames' placements follow."""
    data = model.createData()
    out = np.empty((len(q), model.njoints, 4, 4))
    for k, q_k in enumerate(q):
        pin.forwardKinematics(model, data, q_k)
        out[k] = [placement.homogeneous for placement in data.oMi]
    return out


def attached(joints: np.ndarray, joint: int, placement: pin.SE3) -> np.ndarray:
    """World placements (N, 4, 4) of something fixed at ``placement`` in joint ``joint``'s
    frame, from the joints' placements (N, njoints, 4, 4) of :func:`joint_placements`."""
    return joints[:, joint] @ placement.homogeneous


def geometry_placements(joints: np.ndarray, visual_model: pin.GeometryModel) -> np.ndarray:
    """World placements (N, n_geometries, 4, 4) of the visual geometries, from the joints'
    placements (N, njoints, 4, 4)."""
    items = visual_model.geometryObjects
    return np.stack([attached(joints, g.parentJoint, g.placement) for g in items], axis=1)


def arrow_length(extent: float) -> float:
    """Drawn length [m] of the largest arrow for a drawing ``extent`` [m] across: a third of
    it, as the device's :data:`ARROW_LENGTH` is of its ~1.4 m."""
    return extent / 3.0 if extent > 0.0 else ARROW_LENGTH


def _arrows(force: np.ndarray, point: np.ndarray, per_metre: float, size: float) -> dict:
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


def grid_step(extent: float) -> float:
    """Floor grid square [m] for a drawing ``extent`` [m] across: 1, 2 or 5 × 10ᵏ, about a
    tenth of it (0.1 m for the feeding device)."""
    if extent <= 0.0:
        return 0.1
    decade = 10.0 ** math.floor(math.log10(extent / 10.0))
    return next(m * decade for m in (1.0, 2.0, 5.0, 10.0) if m * decade >= extent / 14.0)


def _floor_grid(low: np.ndarray, high: np.ndarray, step: float, to_model: np.ndarray):
    """Square grid of ``step`` [m] on the horizontal plane under the box ``low``–``high`` (y-up
    coordinates, [m]), one step wider on every side, drawn in model coordinates (``to_model``
    turns y-up coordinates into the model's)."""
    xs = np.arange(math.floor(low[0] / step) - 1, math.ceil(high[0] / step) + 2) * step
    zs = np.arange(math.floor(low[2] / step) - 1, math.ceil(high[2] / step) + 2) * step
    ends = [((x, zs[0]), (x, zs[-1])) for x in xs] + [((xs[0], z), (xs[-1], z)) for z in zs]
    points = np.array([(x, low[1], z) for segment in ends for x, z in segment]) @ to_model.T
    return mg.LineSegments(
        mg.PointsGeometry(points.T.astype(np.float32)), mg.LineBasicMaterial(color=GRID_COLOR)
    )


def _camera_position(points: np.ndarray, reach: np.ndarray) -> np.ndarray:
    """Camera position (3,) [m] relative to the orbit centre, y-up axes: along the default
    view direction, at the smallest distance at which every sphere (centres ``points`` (n, 3)
    relative to the orbit centre, radii ``reach`` (n,)) is inside the field of view."""
    view = np.array(
        [
            math.sin(CAMERA_AZIMUTH) * math.cos(CAMERA_ELEVATION),
            math.sin(CAMERA_ELEVATION),
            math.cos(CAMERA_AZIMUTH) * math.cos(CAMERA_ELEVATION),
        ]
    )
    up = np.array([0.0, 1.0, 0.0]) - math.sin(CAMERA_ELEVATION) * view
    up /= np.linalg.norm(up)
    right = np.cross(up, view)
    lateral = np.maximum(np.abs(points @ right), np.abs(points @ up)) + reach
    half_width = math.tan(CAMERA_FOV / 2.0) * _FRAME_FILL
    return view * float(np.max(points @ view + lateral / half_width))


def bounds(points: np.ndarray, reach: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lowest and highest corners (3,) [m] of the box around the spheres: centres (..., n, 3),
    radii (n,) [m]."""
    low = (points - reach[:, None]).reshape(-1, 3).min(axis=0)
    high = (points + reach[:, None]).reshape(-1, 3).max(axis=0)
    return low, high


def extent_of(points: np.ndarray, reach: np.ndarray) -> float:
    """Largest side [m] of the box around the spheres (centres (..., n, 3), radii (n,))."""
    low, high = bounds(points, reach)
    return float((high - low).max())


def in_level_axes(points: np.ndarray, base: np.ndarray | None) -> np.ndarray:
    """Points (S, n, 3) [m] in the model's moving axes at S samples, in the level axes
    (S · n, 3): placed by the base's placements (S, 4, 4) at those samples (None: at rest)."""
    if base is not None:
        points = np.einsum("sij,snj->sni", base[:, :3, :3], points) + base[:, None, :3, 3]
    return points.reshape(-1, 3)


def _draw_hull(
    vis: meshcat.Visualizer, points: np.ndarray, reach: np.ndarray, up: np.ndarray
) -> np.ndarray:
    """Draw the base as a flat box under the bodies (spheres of centres (N, n, 3) over the
    motion, radii (n,), model axes [m]): its top at their lowest point along ``up`` (3,),
    :data:`_HULL_DEPTH` of their extent thick, under their centres and :data:`_HULL_MARGIN` of
    the extent wider on every side (the spheres overstate a long body's width); return its
    corners (8, 3) [m], model axes."""
    to_y_up = y_onto(up).T  # model coordinates → y-up coordinates
    upright = points @ to_y_up.T
    low, high = bounds(upright, reach)
    first, last = bounds(upright, np.zeros_like(reach))  # the centres' box
    margin, depth = (share * float((high - low).max()) for share in (_HULL_MARGIN, _HULL_DEPTH))
    size = np.array([last[0] - first[0] + 2.0 * margin, depth, last[2] - first[2] + 2.0 * margin])
    centre = np.array(
        [(first[0] + last[0]) / 2.0, low[1] - depth / 2.0, (first[2] + last[2]) / 2.0]
    )
    vis[f"{BASE}/hull"].set_object(mg.Box(size.tolist()), mg.MeshLambertMaterial(color=HULL_COLOR))
    vis[f"{BASE}/hull"].set_transform(homogeneous(to_y_up.T, to_y_up.T @ centre))
    signs = np.array([(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)])
    return (centre + signs * size / 2.0) @ to_y_up


def frame_scene(
    vis: meshcat.Visualizer, points: np.ndarray, reach: np.ndarray, up: np.ndarray
) -> float:
    """Centre the scene on the box around every drawn sphere (centres ``points`` (n, 3), radii
    ``reach`` (n,), level axes [m]), which the camera orbits; turn ``up`` onto MeshCat's z;
    draw a floor grid under it. Returns the grid's square [m]."""
    to_y_up = y_onto(up).T  # model coordinates → y-up coordinates
    upright = points @ to_y_up.T
    low, high = bounds(upright, reach)
    centre = (low + high) / 2.0
    model_to_world = _Y_UP_TO_MESHCAT @ homogeneous(to_y_up, -centre)
    step = grid_step(float((high - low).max()))
    vis[ROOT].set_transform(model_to_world)
    vis["/Axes"].set_transform(model_to_world)  # MeshCat's triad: the model's axes
    vis["/Grid"].set_property("visible", False)  # 20 m wide: replaced by a floor to scale
    vis[f"{ROOT}/floor"].set_object(_floor_grid(low, high, step, to_y_up.T))
    vis["/Background"].set_property("top_color", _BACKGROUND[0])
    vis["/Background"].set_property("bottom_color", _BACKGROUND[1])
    # The camera lives in MeshCat's "rotated" frame, whose axes are the y-up ones.
    vis["/Cameras/default/rotated/<object>"].set_property(
        "position", _camera_position(upright - centre, reach).tolist()
    )
    return step


@dataclass(frozen=True)
class DrawnParts:
    """What :func:`draw_scene` drew: the arrows' scales [N/m], [N·m/m] and length [m], the
    playback time per second of motion, the legend of the floor grid and the arrows."""

    newtons_per_metre: float
    moment_scale: float
    arrow_length: float
    slow_motion: float
    legend: tuple[LegendEntry, ...]


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


def draw_scene(
    vis: meshcat.Visualizer,
    t: np.ndarray,
    tracks: Mapping[str, np.ndarray],
    points: np.ndarray,
    reach: np.ndarray,
    arrows: Arrows,
    up: np.ndarray,
    *,
    fixed: np.ndarray | None = None,
    base: np.ndarray | None = None,
    length: float | None = None,
) -> DrawnParts:
    """Frame, draw the arrows (and the base, if it moves) and animate a motion whose bodies are
    already loaded under :data:`BASE`.

    Args:
        vis: The MeshCat visualizer (nodes relative to its root).
        t: Motion sample times [s], (N,).
        tracks: Node path (under :data:`BASE`) → its placements (N, 4, 4) in the model's axes
            (the bodies).
        points, reach: Spheres around the bodies over the motion, which the camera must see:
            centres (N, n, 3) [m] in the model's axes at each sample, radii (n,) [m].
        arrows: Force and moment arrows, each (N, 3) series, model axes.
        up: Unit vector against gravity (3,), the model's standing (level) gravity.
        fixed: Points (m, 3) [m] fixed in the model's axes that the camera must see too (the
            ends of lines drawn by the caller).
        base: The base's placements (N, 4, 4) in the level axes (:func:`base_placements`);
            None for a base at rest.
        length: Drawn length [m] of the largest force and moment (default: a third of the
            drawing's extent).

    Returns:
        The scales, the playback speed and the legend of the floor grid, the base and the
        arrows.
    """
    length = length or arrow_length(extent_of(points, reach))
    size = length / ARROW_LENGTH  # arrow thickness follows its length
    newtons_per_metre, moment_scale = arrows.scales(length)
    duration = float(t[-1] - t[0])
    slow = max(1.0, MIN_PLAYBACK / duration) if duration > 0.0 else 1.0
    frames = max(2, math.ceil(duration * slow * FRAME_RATE) + 1)
    samples = np.unique(np.linspace(0, t.size - 1, min(frames, t.size)).round().astype(int))
    legend, drawn = [LegendEntry(css(GRID_COLOR), "line", "")], {}  # the grid's, set below
    all_points, all_reach = [in_level_axes(points, base)], [np.tile(reach, t.size)]
    if fixed is not None:
        all_points.append(in_level_axes(np.broadcast_to(fixed, (t.size, *fixed.shape)), base))
        all_reach.append(np.zeros(t.size * len(fixed)))
    if base is not None:
        hull = _draw_hull(vis, points, reach, up)
        all_points.append(in_level_axes(np.broadcast_to(hull, (t.size, *hull.shape)), base))
        all_reach.append(np.zeros(t.size * len(hull)))
        legend.append(
            LegendEntry(
                css(HULL_COLOR), "body", "the moving base (a vehicle's hull): the bodies and the "
                "arrows ride on it; the floor grid stays level",
            )
        )  # fmt: skip
    placed = None if base is None else base[samples]
    series = [(n, s, newtons_per_metre, "") for n, s in arrows.forces.items()]
    moment = " (moment, right-hand rule)"
    series += [(n, s, moment_scale, moment) for n, s in arrows.moments.items()]
    left_out = [name for name, *_ in series[len(ARROW_COLORS) :]]
    series = series[: len(ARROW_COLORS)]  # one colour each
    for k, (name, (vector, point), scale, note) in enumerate(series):
        node = f"{BASE}/forces/{name}"
        color = ARROW_COLORS[k % len(ARROW_COLORS)]
        legend.append(LegendEntry(css(color), "arrow", name + note))
        material = mg.MeshBasicMaterial(color=color, depthTest=False)
        vis[f"{node}/shaft"].set_object(mg.Cylinder(1.0, size * _ARROW_RADIUS), material)
        vis[f"{node}/head"].set_object(
            mg.Cylinder(size * HEAD_LENGTH, radiusTop=0.0, radiusBottom=size * _HEAD_RADIUS),
            material,
        )
        for part in ("shaft", "head"):
            vis[f"{node}/{part}"].set_property("renderOrder", ON_TOP)
        drawn[node] = _arrows(vector[samples], point[samples], scale, size)
        ends = np.stack([point[samples], drawn[node]["tip"]], axis=1)
        all_points.append(in_level_axes(ends, placed))
        all_reach.append(np.tile([0.0, size * _HEAD_RADIUS], samples.size))
    step = frame_scene(vis, np.concatenate(all_points), np.concatenate(all_reach), up)
    legend[0] = LegendEntry(css(GRID_COLOR), "line", f"floor grid, {step:g} m squares")
    if left_out:
        legend.append(LegendEntry("", "note", f"not drawn (one colour per arrow): {left_out}"))

    if base is not None:
        vis[BASE].set_transform(base[0])
    for node, placements in tracks.items():
        vis[node].set_transform(placements[0])
    for node, arrow in drawn.items():  # the scale in the matrix: a static page applies a
        for part in ("shaft", "head"):  # node's transform after its properties
            scale = np.diag([*arrow[f"{part}_scale"][0], 1.0])
            vis[f"{node}/{part}"].set_transform(arrow[part][0] @ scale)
    if t.size > 1:
        animation = meshcat.animation.Animation(default_framerate=FRAME_RATE)
        for k, i in enumerate(samples):
            with animation.at_frame(vis, (t[i] - t[0]) * slow * FRAME_RATE) as frame:
                if base is not None:
                    frame[BASE].set_transform(base[i])
                for node, placements in tracks.items():
                    frame[node].set_transform(placements[i])
                for node, arrow in drawn.items():
                    for part in ("shaft", "head"):
                        frame[f"{node}/{part}"].set_transform(arrow[part][k])
                        frame[f"{node}/{part}"].set_property(
                            "scale", "vector3", arrow[f"{part}_scale"][k].tolist()
                        )
        # Kept on a node of its own, created last: MeshCat sends a scene node by node in
        # creation order, so the animation comes after every set_transform (Pinocchio's
        # included) and a late transform cannot undo a pause at a chosen time.
        vis[ANIMATION].set_animation(animation, play=True, repetitions=1)
    return DrawnParts(newtons_per_metre, moment_scale, length, slow, tuple(legend))
