"""MeshCat viewer of a feeding cycle, served on 127.0.0.1 only, and its static HTML page.

The device is drawn with Pinocchio's :class:`~pinocchio.visualize.MeshcatVisualizer` from the
URDF's visual primitives (frame, cylinder, piston, arm, forearm tray, payload) and animated over
the whole cycle (MeshCat's animation panel: play, pause, time scrubber). Also drawn: the barrel
axis at the elevation ε (a red rod through the rammed payload, muzzle towards −x), the payload's
path once gripped (a line through the payload centre of gravity), when given, force arrows to
one scale, a floor grid of 0.1 m squares under the device and MeshCat's x-y-z triad at the
cylinder pivot B. In stage 1 the payload waits on the conveyor where it is gripped at t = T1.

The scene lives under the node ``feeder`` in device coordinates (y up), turned onto MeshCat's
z-up world and centred on the device, whose centre is the camera's orbit target. MeshCat 0.3.2's
server listens on every interface unless told otherwise; :class:`CycleViewer` starts it here
with its web port bound to 127.0.0.1 (its ZMQ port is on 127.0.0.1 already). The static page
(:func:`write_html`) embeds MeshCat's JavaScript and the scene: it opens offline.
"""

from __future__ import annotations

import contextlib
import io
import math
import os
from collections.abc import Mapping
from pathlib import Path

import meshcat
import meshcat.animation
import meshcat.geometry as mg
import meshcat.transformations as mtf
import numpy as np
import pinocchio as pin
from pinocchio.visualize import MeshcatVisualizer

from ._meshcat_server import MeshcatServer
from .cycle import CycleKinematics
from .cycle_dynamics import CycleDynamics, cycle_dynamics
from .device import Feeder, load_feeder
from .exceptions import InputError, check_finite
from .kinematics import pin_position

FRAME_RATE = 40.0
"""Animation key frames per second of cycle time [1/s]; the 1 kHz cycle is subsampled."""

ARROW_LENGTH = 0.3
"""Drawn length [m] of the largest force over the cycle; all arrows share one scale [N/m]."""

CAMERA_AZIMUTH, CAMERA_ELEVATION = math.radians(35.0), math.radians(25.0)
"""Default view direction [rad]: from the +z side, turned towards +x, looking down."""

CAMERA_FOV = math.radians(75.0)
"""MeshCat's default camera: vertical field of view [rad]."""

ForceSeries = tuple[np.ndarray, np.ndarray]
"""(force, point): forces [N] and their application points [m] in the device's world frame
(x horizontal, y up), each (N, 3), one row per cycle sample."""

_ROOT = "feeder"
_DEVICE = f"{_ROOT}/device"
_BARREL_COLOR, _PATH_COLOR, _GRID_COLOR = 0xCC2222, 0xD4A017, 0x8A8F99
_BACKGROUND = ((0.93, 0.94, 0.95), (0.62, 0.65, 0.70))  # MeshCat gradient, top and bottom RGB
_GRID_STEP = 0.1  # [m] floor grid squares
_ARROW_COLORS = (0x8E24AA, 0x00897B, 0xD81B60, 0x37474F, 0x7CB342, 0x039BE5)
_ARROW_RADIUS, _HEAD_LENGTH, _HEAD_RADIUS = 0.008, 0.05, 0.02  # [m]
_INVISIBLE = 1e-6  # scale of a zero-length arrow part (a zero scale makes a singular matrix)
_FRAME_FILL = 0.9  # the scene's extent fills at most this share of the camera's view
_BARREL_RADIUS, _BARREL_BEHIND, _BARREL_AHEAD = 0.006, 0.4, 0.8  # [m] around the rammed CG
# Device (y up) → MeshCat world (z up): a quarter turn about x.
_DEVICE_TO_MESHCAT = mtf.rotation_matrix(math.pi / 2.0, [1.0, 0.0, 0.0])


class CycleViewer:
    """A live MeshCat viewer of one feeding cycle, served on 127.0.0.1 only.

    Use as a context manager, or call :meth:`close`.

    Attributes:
        url: The viewer's address, ``http://127.0.0.1:<port>/static/``.
        port: The web server's port.
        visualizer: Pinocchio's MeshCat visualizer holding the device's visual model.
        newtons_per_metre: Scale of the force arrows [N/m] (0 without forces).
    """

    def __init__(
        self,
        feeder: Feeder,
        cycle: CycleKinematics,
        forces: Mapping[str, ForceSeries] | None = None,
        *,
        port: int | None = None,
    ):
        forces = _check_forces(forces or {}, cycle.t.size)
        self._server = MeshcatServer(_check_port(port))
        try:
            with contextlib.redirect_stdout(io.StringIO()):  # meshcat prints the URL
                viewer = meshcat.Visualizer(zmq_url=self._server.zmq_url)
            visual_model = pin.buildGeomFromUrdfString(
                feeder.model, feeder.urdf, pin.GeometryType.VISUAL
            )
            self.visualizer = MeshcatVisualizer(feeder.model, None, visual_model)
            self.visualizer.initViewer(viewer=viewer)
            self.newtons_per_metre = _draw_cycle(self.visualizer, feeder, cycle, forces)
        except BaseException:
            self._server.stop()
            raise
        self.url: str = self._server.web_url
        self.port: int = self._server.port

    def static_html(self) -> str:
        """The scene and its animation as one self-contained HTML page (opens offline)."""
        return self.visualizer.viewer.static_html()

    def serve_forever(self) -> None:
        """Block until the server stops or the user presses Ctrl-C."""
        with contextlib.suppress(KeyboardInterrupt):
            self._server.wait()

    def close(self) -> None:
        """Disconnect and stop the server."""
        self.visualizer.viewer.window.zmq_socket.close(linger=0)
        self._server.stop()

    def __enter__(self) -> CycleViewer:
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()


def show_cycle(
    feeder: Feeder,
    cycle: CycleKinematics,
    forces: Mapping[str, ForceSeries] | None = None,
    *,
    port: int | None = None,
    open_browser: bool = False,
) -> CycleViewer:
    """Serve the animated cycle on ``http://127.0.0.1:<port>/static/``.

    Args:
        feeder: The device.
        cycle: Its sampled cycle (:func:`~feeder.cycle.feeding_cycle`), N samples.
        forces: Optional arrows by name: world-frame forces [N] and application points [m],
            each (N, 3) (see :data:`ForceSeries`).
        port: Web port; None picks a free one.
        open_browser: Open the viewer in the default web browser.

    Raises:
        InputError: Bad force arrays or port number.
        ViewerPortError: The port is busy.
    """
    viewer = CycleViewer(feeder, cycle, forces, port=port)
    if open_browser:
        viewer.visualizer.viewer.open()
    return viewer


def write_html(
    feeder: Feeder,
    cycle: CycleKinematics,
    path: str | Path,
    forces: Mapping[str, ForceSeries] | None = None,
    *,
    port: int | None = None,
) -> Path:
    """Write the animated cycle as a self-contained HTML page (about 1 MB, opens offline).

    A MeshCat server runs on 127.0.0.1 while the page is assembled (on ``port``, or a free one).

    Raises:
        InputError: ``path`` cannot be written, bad force arrays or port number.
        ViewerPortError: The port is busy.
    """
    path = _check_writable(Path(path))
    with CycleViewer(feeder, cycle, forces, port=port) as viewer:
        html = viewer.static_html()
    try:
        path.write_text(html, encoding="utf-8")
    except OSError as exc:
        raise InputError(f"cannot write the HTML file {path}: {exc.strerror}") from exc
    return path


def view_command(device: str, elevation_deg: float, html: str | None, port: int | None) -> int:
    """``feeder view``: serve the cycle at ``elevation_deg`` [deg] until Ctrl-C, or write it
    to the HTML file ``html``. Returns the exit status 0.

    Raises:
        InputError: Unknown device, non-finite elevation, unwritable HTML path, bad port.
        ElevationError: Elevation outside the device's range.
        ViewerPortError: The port is busy.
    """
    feeder = load_feeder(device)
    elevation = math.radians(float(check_finite("elevation [deg]", elevation_deg)))
    if html is not None:
        _check_writable(Path(html))
    _check_port(port)
    dynamics = cycle_dynamics(feeder, elevation, forward=False)
    cycle, forces = dynamics.kinematics, cycle_forces(feeder, dynamics)
    if html is not None:
        path = write_html(feeder, cycle, html, forces, port=port)
        print(f"wrote {path}")
        return 0
    with show_cycle(feeder, cycle, forces, port=port) as viewer:
        print(f"{feeder.params.name} feeder at {elevation_deg:g}°: open {viewer.url}")
        print("press Ctrl-C to stop the viewer")
        viewer.serve_forever()
    return 0


def cycle_forces(feeder: Feeder, dynamics: CycleDynamics) -> dict[str, ForceSeries]:
    """The arrows of ``feeder view``: the piston force at the pin and the pin reactions.

    * ``piston force``: the actuator force on the piston, along its axis, at the rod-eye pin;
    * ``pin force on the arm``: the closure force of the piston on the arm, at the pin;
    * ``arm pivot reaction``, ``cylinder pivot reaction``: the frame's force on the arm at its
      pivot (L1, L2) and on the cylinder at B.
    """
    p, q = feeder.params, dynamics.kinematics.q
    axis = np.column_stack([np.cos(q[:, 0]), np.sin(q[:, 0]), np.zeros(len(q))])
    pin_point = np.column_stack([pin_position(p, q[:, 2]).T, np.zeros(len(q))])
    joints = dynamics.reactions.joints
    return {
        "piston force": (dynamics.loads.piston_force[:, None] * axis, pin_point),
        "pin force on the arm": (dynamics.reactions.closure_force, pin_point),
        "arm pivot reaction": (joints["arm_frame"].force, np.tile([p.L1, p.L2, 0.0], (len(q), 1))),
        "cylinder pivot reaction": (joints["cylinder_frame"].force, np.zeros((len(q), 3))),
    }


def _check_port(port: int | None) -> int | None:
    if port is None:
        return None
    if isinstance(port, bool) or not isinstance(port, int) or not 1 <= port <= 65535:
        raise InputError(f"port must be an integer in 1 … 65535, got {port!r}")
    return port


def _check_writable(path: Path) -> Path:
    if path.is_dir():
        raise InputError(f"cannot write the HTML file {path}: it is a directory")
    if not path.parent.is_dir():
        raise InputError(f"cannot write the HTML file {path}: no directory {path.parent}")
    if not os.access(path.parent, os.W_OK) or (path.exists() and not os.access(path, os.W_OK)):
        raise InputError(f"cannot write the HTML file {path}: permission denied")
    return path


def _check_forces(forces: Mapping[str, ForceSeries], count: int) -> dict[str, ForceSeries]:
    checked = {}
    for name, series in forces.items():
        if not isinstance(name, str) or not name or "/" in name:
            raise InputError(f"force names must be non-empty strings without '/', got {name!r}")
        if len(series) != 2:
            raise InputError(f"force {name!r} must be a pair (force, point), got {series!r}")
        force, point = (check_finite(f"force {name!r}", x) for x in series)
        for what, array in (("forces", force), ("points", point)):
            if array.shape != (count, 3):
                raise InputError(
                    f"force {name!r}: {what} must have shape ({count}, 3) like the cycle, "
                    f"got {array.shape}"
                )
        checked[name] = (force, point)
    return checked


def _homogeneous(rotation: np.ndarray, translation: np.ndarray) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3] = rotation
    out[:3, 3] = translation
    return out


def _y_onto(direction: np.ndarray) -> np.ndarray:
    """A rotation (3, 3) turning the y axis onto the unit vector ``direction``."""
    y = np.array([0.0, 1.0, 0.0])
    axis = np.cross(y, direction)
    sine, cosine = np.linalg.norm(axis), float(y @ direction)
    if sine < 1e-9:
        return np.eye(3) if cosine > 0.0 else np.diag([1.0, -1.0, -1.0])
    return pin.AngleAxis(math.atan2(sine, cosine), axis / sine).matrix()


def _geometry_radius(geometry_object: pin.GeometryObject) -> float:
    """Radius [m] of a sphere about the geometry's origin that contains it (box or cylinder)."""
    shape = geometry_object.geometry
    if hasattr(shape, "halfSide"):
        return float(np.linalg.norm(shape.halfSide))
    return float(math.hypot(shape.radius, shape.halfLength))


def _placements(
    feeder: Feeder, visual_model: pin.GeometryModel, cycle: CycleKinematics, samples: np.ndarray
) -> np.ndarray:
    """World placements (len(samples), n_geometries, 4, 4) of the visual geometries.

    Before the grip (payload = 0) the payload's geometries stay where they are gripped."""
    model = feeder.model
    data, visual_data = model.createData(), pin.GeometryData(visual_model)
    on_payload = np.array(
        [model.frames[g.parentFrame].name == "projectile" for g in visual_model.geometryObjects]
    )

    def at(i: int) -> np.ndarray:
        pin.forwardKinematics(model, data, feeder.to_pinocchio(cycle.q[i]))
        pin.updateGeometryPlacements(model, data, visual_model, visual_data)
        return np.array([placement.homogeneous for placement in visual_data.oMg])

    gripped = at(int(np.argmax(cycle.payload)))
    out = np.empty((samples.size, len(visual_model.geometryObjects), 4, 4))
    for k, i in enumerate(samples):
        out[k] = at(i)
        if not cycle.payload[i]:
            out[k, on_payload] = gripped[on_payload]
    return out


def _arrows(force: np.ndarray, point: np.ndarray, newtons_per_metre: float) -> dict:
    """Placements of one force's arrow at n samples; ``force``, ``point`` (n, 3) [N], [m].

    The arrow starts at the point and is ``|force| / newtons_per_metre`` long; its head is at
    most a third of it. Shaft and head are MeshCat cylinders along y, of unit height and of
    height :data:`_HEAD_LENGTH`, scaled by ``shaft_scale`` and ``head_scale``.

    Returns:
        ``shaft``, ``head``: rigid placements (n, 4, 4); ``shaft_scale``, ``head_scale``:
        scale factors (n, 3); ``tip``: arrow tips (n, 3) [m].
    """
    magnitude = np.linalg.norm(force, axis=1)
    length = magnitude / newtons_per_metre if newtons_per_metre > 0.0 else 0.0 * magnitude
    direction = np.where(magnitude[:, None] > 0.0, force, [0.0, 1.0, 0.0])
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    head = np.clip(length / (3.0 * _HEAD_LENGTH), _INVISIBLE, 1.0)
    shaft = np.maximum(length - head * _HEAD_LENGTH, _INVISIBLE)
    rotations = [_y_onto(d) for d in direction]
    shaft_centres = point + direction * (shaft / 2.0)[:, None]
    head_centres = point + direction * (length - head * _HEAD_LENGTH / 2.0)[:, None]
    return {
        "shaft": np.array(
            [_homogeneous(*rc) for rc in zip(rotations, shaft_centres, strict=True)]
        ),
        "head": np.array([_homogeneous(*rc) for rc in zip(rotations, head_centres, strict=True)]),
        "shaft_scale": np.column_stack([np.ones_like(shaft), shaft, np.ones_like(shaft)]),
        "head_scale": np.repeat(head[:, None], 3, axis=1),
        "tip": point + direction * length[:, None],
    }


def _floor_grid(low: np.ndarray, high: np.ndarray) -> mg.LineSegments:
    """Square grid of :data:`_GRID_STEP` on the horizontal plane under the box ``low``–``high``
    (device frame, [m]), one step wider on every side."""
    xs = np.arange(math.floor(low[0] / _GRID_STEP) - 1, math.ceil(high[0] / _GRID_STEP) + 2)
    zs = np.arange(math.floor(low[2] / _GRID_STEP) - 1, math.ceil(high[2] / _GRID_STEP) + 2)
    xs, zs = xs * _GRID_STEP, zs * _GRID_STEP
    ends = [((x, zs[0]), (x, zs[-1])) for x in xs] + [((xs[0], z), (xs[-1], z)) for z in zs]
    points = np.array([(x, low[1], z) for segment in ends for x, z in segment], dtype=np.float32)
    return mg.LineSegments(mg.PointsGeometry(points.T), mg.LineBasicMaterial(color=_GRID_COLOR))


def _camera_position(points: np.ndarray, reach: np.ndarray) -> np.ndarray:
    """Camera position (3,) [m] relative to the orbit centre, device axes: along the default
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


def _frame_scene(vis: meshcat.Visualizer, points: np.ndarray, reach: np.ndarray) -> None:
    """Centre the scene on the box around every drawn sphere (centres ``points`` (n, 3),
    radii ``reach`` (n,), device frame [m]), which the camera orbits; floor grid under it."""
    low = (points - reach[:, None]).min(axis=0)
    high = (points + reach[:, None]).max(axis=0)
    centre = (low + high) / 2.0
    device_to_world = _DEVICE_TO_MESHCAT @ _homogeneous(np.eye(3), -centre)
    vis[_ROOT].set_transform(device_to_world)
    vis["/Axes"].set_transform(device_to_world)  # MeshCat's triad: device axes at B
    vis["/Grid"].set_property("visible", False)  # 20 m wide: replaced by a floor to scale
    vis[f"{_ROOT}/floor"].set_object(_floor_grid(low, high))
    vis["/Background"].set_property("top_color", _BACKGROUND[0])
    vis["/Background"].set_property("bottom_color", _BACKGROUND[1])
    # The camera lives in MeshCat's "rotated" frame, whose axes are the device's.
    vis["/Cameras/default/rotated/<object>"].set_property(
        "position", _camera_position(points - centre, reach).tolist()
    )


def _draw_references(vis: meshcat.Visualizer, cycle: CycleKinematics) -> np.ndarray:
    """Draw the barrel axis and the payload's path; return the axis' ends (2, 3) [m]."""
    direction = np.array([-math.cos(cycle.elevation), math.sin(cycle.elevation), 0.0])
    rammed = cycle.projectile_position[-1]
    ends = np.array([rammed - _BARREL_BEHIND * direction, rammed + _BARREL_AHEAD * direction])
    barrel = vis[f"{_ROOT}/barrel_axis"]
    barrel.set_object(
        mg.Cylinder(_BARREL_BEHIND + _BARREL_AHEAD, _BARREL_RADIUS),
        mg.MeshLambertMaterial(color=_BARREL_COLOR),
    )
    barrel.set_transform(_homogeneous(_y_onto(direction), ends.mean(axis=0)))
    path = cycle.projectile_position[cycle.payload == 1].T.astype(np.float32)
    vis[f"{_ROOT}/payload_path"].set_object(
        mg.Line(mg.PointsGeometry(path), mg.LineBasicMaterial(color=_PATH_COLOR))
    )
    return ends


def _draw_cycle(
    viz: MeshcatVisualizer, feeder: Feeder, cycle: CycleKinematics, forces: dict[str, ForceSeries]
) -> float:
    """Draw and animate the cycle in ``viz``; return the arrows' scale [N/m]."""
    vis = viz.viewer
    viz.loadViewerModel(rootNodeName=_DEVICE)
    step = max(1, round(cycle.spec.rate / FRAME_RATE))
    samples = np.unique(np.append(np.arange(0, cycle.t.size, step), cycle.t.size - 1))
    geometries = viz.visual_model.geometryObjects
    nodes = [viz.getViewerNodeName(g, pin.GeometryType.VISUAL) for g in geometries]
    placements = _placements(feeder, viz.visual_model, cycle, samples)
    points = [placements[:, :, :3, 3].reshape(-1, 3), _draw_references(vis, cycle)]
    reach = [np.tile([_geometry_radius(g) for g in geometries], samples.size), np.zeros(2)]

    peak = max((float(np.linalg.norm(f, axis=1).max()) for f, _ in forces.values()), default=0.0)
    newtons_per_metre = peak / ARROW_LENGTH
    arrows = {}
    for k, (name, (force, point)) in enumerate(forces.items()):
        node = f"{_ROOT}/forces/{name}"
        material = mg.MeshLambertMaterial(color=_ARROW_COLORS[k % len(_ARROW_COLORS)])
        vis[f"{node}/shaft"].set_object(mg.Cylinder(1.0, _ARROW_RADIUS), material)
        vis[f"{node}/head"].set_object(
            mg.Cylinder(_HEAD_LENGTH, radiusTop=0.0, radiusBottom=_HEAD_RADIUS), material
        )
        arrows[node] = _arrows(force[samples], point[samples], newtons_per_metre)
        points += [point[samples], arrows[node]["tip"]]
        reach += [np.zeros(samples.size), np.full(samples.size, _HEAD_RADIUS)]
    _frame_scene(vis, np.concatenate(points), np.concatenate(reach))

    animation = meshcat.animation.Animation(default_framerate=FRAME_RATE)
    for k, i in enumerate(samples):
        with animation.at_frame(vis, cycle.t[i] * FRAME_RATE) as frame:
            for node, placement in zip(nodes, placements[k], strict=True):
                frame[node].set_transform(placement)
            for node, arrow in arrows.items():
                for part in ("shaft", "head"):
                    frame[f"{node}/{part}"].set_transform(arrow[part][k])
                    frame[f"{node}/{part}"].set_property(
                        "scale", "vector3", arrow[f"{part}_scale"][k].tolist()
                    )
    for node, placement in zip(nodes, placements[0], strict=True):
        vis[node].set_transform(placement)
    for node, arrow in arrows.items():
        for part in ("shaft", "head"):
            scaling = np.diag(np.append(arrow[f"{part}_scale"][0], 1.0))
            vis[f"{node}/{part}"].set_transform(arrow[part][0] @ scaling)
    vis.set_animation(animation, play=True, repetitions=1)
    return newtons_per_metre
