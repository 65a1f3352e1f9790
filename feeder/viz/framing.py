"""The scene's setting: the camera's orbit centre and distance, "up" turned onto MeshCat's z,
the floor grid to scale under the drawing, the background, and the hull (a flat box under the
bodies) of a moving base.

The floor grid, the camera's "up" and MeshCat's triad stay level; the hull rides on the base
(:data:`~feeder.viz.nodes.BASE`).
"""

from __future__ import annotations

import math

import meshcat
import meshcat.geometry as mg
import meshcat.transformations as mtf
import numpy as np

from .nodes import BASE, ROOT
from .placements import bounds, homogeneous, y_onto

CAMERA_AZIMUTH, CAMERA_ELEVATION = math.radians(35.0), math.radians(25.0)
"""Default view direction [rad]: turned 35° from the model's horizontal axes, looking down 25°."""

CAMERA_FOV = math.radians(75.0)
"""MeshCat's default camera: vertical field of view [rad]."""

GRID_COLOR = 0x8A8F99
HULL_COLOR = 0x6B7353
"""The base's flat box (a vehicle's hull, olive): drawn on a moving base only."""
_HULL_DEPTH, _HULL_MARGIN = 0.04, 0.05  # the hull's thickness and overhang, shares of the extent
_BACKGROUND = ((0.93, 0.94, 0.95), (0.62, 0.65, 0.70))  # MeshCat gradient, top and bottom RGB
_FRAME_FILL = 0.9  # the scene's extent fills at most this share of the camera's view
_Y_UP_TO_MESHCAT = mtf.rotation_matrix(math.pi / 2.0, [1.0, 0.0, 0.0])  # y up → MeshCat's z up


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


def draw_hull(
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
