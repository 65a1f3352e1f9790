"""MeshCat viewer of a feeding cycle, served on 127.0.0.1 only, and its static HTML page.

The device is drawn with Pinocchio's :class:`~pinocchio.visualize.MeshcatVisualizer` from the
URDF's visual primitives (frame, cylinder, piston, arm, forearm tray, payload) and animated over
the whole cycle (MeshCat's animation panel: play, pause, time scrubber). Also drawn: the barrel
axis at the elevation ε (a red rod through the rammed payload, muzzle towards −x), the payload's
path once gripped (a line through the payload centre of gravity), when given, force arrows to
one scale, a floor grid of 0.1 m squares under the device and MeshCat's x-y-z triad at the
cylinder pivot B. In stage 1 the payload waits on the conveyor where it is gripped at t = T1.

The scene is drawn by :mod:`feeder.viz.scene`. MeshCat 0.3.2's server listens on every
interface unless told otherwise; :class:`CycleViewer` starts it here with its web port bound to
127.0.0.1 (its ZMQ port is on 127.0.0.1 already). The static page (:func:`write_html`) embeds
MeshCat's JavaScript and the scene: it opens offline.
"""

from __future__ import annotations

import contextlib
import io
import os
from collections.abc import Mapping
from pathlib import Path

import meshcat
import numpy as np
import pinocchio as pin
from pinocchio.visualize import MeshcatVisualizer

from ..device.feeder import Feeder
from ..device.loop import pin_position
from ..dynamics.cycle import CycleDynamics
from ..exceptions import InputError
from ..motion.cycle import CycleKinematics
from ..validation import check_finite
from ._meshcat_server import MeshcatServer
from .scene import ForceSeries, draw_cycle


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
        self._server = MeshcatServer(check_port(port))
        try:
            with contextlib.redirect_stdout(io.StringIO()):  # meshcat prints the URL
                viewer = meshcat.Visualizer(zmq_url=self._server.zmq_url)
            visual_model = pin.buildGeomFromUrdfString(
                feeder.model, feeder.urdf, pin.GeometryType.VISUAL
            )
            self.visualizer = MeshcatVisualizer(feeder.model, None, visual_model)
            self.visualizer.initViewer(viewer=viewer)
            self.newtons_per_metre = draw_cycle(self.visualizer, feeder, cycle, forces)
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
        cycle: Its sampled cycle (:func:`~feeder.motion.cycle.feeding_cycle`), N samples.
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
    path = check_writable(path)
    with CycleViewer(feeder, cycle, forces, port=port) as viewer:
        html = viewer.static_html()
    try:
        path.write_text(html, encoding="utf-8")
    except OSError as exc:
        raise InputError(f"cannot write the HTML file {path}: {exc.strerror}") from exc
    return path


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


def check_port(port: int | None) -> int | None:
    """The web port if it is None (a free one) or an integer in 1 … 65535, else InputError."""
    if port is None:
        return None
    if isinstance(port, bool) or not isinstance(port, int) or not 1 <= port <= 65535:
        raise InputError(f"port must be an integer in 1 … 65535, got {port!r}")
    return port


def check_writable(path: str | Path) -> Path:
    """``path`` as a Path if an HTML file can be written there, else InputError."""
    path = Path(path)
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
