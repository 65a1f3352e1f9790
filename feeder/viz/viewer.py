"""MeshCat viewer of a feeding cycle or of a user's mechanism, served on 127.0.0.1 only, and its
static HTML page.

A user's mechanism (:class:`MechanismViewer`) is drawn from its URDF's visuals (or as a stick
figure) with its closure cuts and load arrows (:mod:`feeder.viz.mechanism_scene`).

The device is drawn with Pinocchio's :class:`~pinocchio.visualize.MeshcatVisualizer` from the
URDF's visual primitives (frame, cylinder, piston, arm, forearm tray, payload) and animated over
the whole cycle. Also drawn: the barrel axis at the elevation ε (a red rod through the rammed
payload, muzzle towards −x), the payload's path once gripped (a line through the payload centre
of gravity), when given, force arrows to one scale over the bodies, a floor grid of 0.1 m squares
under the device and MeshCat's x-y-z triad at the cylinder pivot B. On a vehicle (``base``) the
device rides on its hull, a flat box under it that moves as the base does, over the level floor
grid (:mod:`feeder.viz.scene`). In stage 1 the payload waits
on the conveyor where it is gripped at t = T1. Both the live page and the static one carry a
legend for every colour and a player: play/pause, loop, a time slider with the time and the
stage (:mod:`feeder.viz._overlay`).

Both scenes are drawn by :mod:`feeder.viz.scene`. MeshCat 0.3.2's server listens on every
interface unless told otherwise; :class:`SceneViewer` starts it here with its web port bound to
127.0.0.1 (its ZMQ port is on 127.0.0.1 already). The static page (:func:`write_html`) embeds
MeshCat's JavaScript and the scene: it opens offline. It carries :data:`PAGE_MARKER` in its
head, and replaces no file but such a page.
"""

from __future__ import annotations

import contextlib
import io
import os
from collections.abc import Callable, Mapping, Sequence
from functools import partial
from pathlib import Path

import meshcat
import numpy as np
import pinocchio as pin
from pinocchio.visualize import MeshcatVisualizer

from ..chain.model.base import BaseMotion
from ..device.feeder import Feeder
from ..dynamics.cycle import CycleDynamics
from ..exceptions import InputError
from ..files import check_replaceable, write_text
from ..motion.cycle import CycleKinematics
from ..study.view import MechanismView
from ..validation import check_finite
from ._meshcat_server import MeshcatServer
from ._overlay import overlay_html, static_page
from .cycle_scene import draw_cycle
from .mechanism_scene import draw_mechanism, pick_reactions, visual_model
from .scene import DrawnScene, ForceSeries

PAGE_MARKER = '<meta name="generator" content="feeder view">'
"""In the head of every static page of the viewer: the pages it may replace."""


class SceneViewer:
    """A live MeshCat viewer of one scene, served on 127.0.0.1 only.

    Use as a context manager, or call :meth:`close`.

    Args:
        model: The Pinocchio model whose bodies are drawn.
        visuals: Their visual geometries.
        draw: Draws the scene into Pinocchio's visualizer and says what it drew.
        title: The legend's title.
        port: Web port; None picks a free one.

    Attributes:
        url: The viewer's address, ``http://127.0.0.1:<port>/static/``.
        port: The web server's port.
        visualizer: Pinocchio's MeshCat visualizer holding the visual model.
        drawn: What the scene shows: the arrows' scales, the legend, the time line.
        overlay: The legend and player HTML of the page.
    """

    def __init__(
        self,
        model: pin.Model,
        visuals: pin.GeometryModel,
        draw: Callable[[MeshcatVisualizer], DrawnScene],
        title: str,
        port: int | None,
    ):
        self._server = MeshcatServer(check_port(port))
        try:
            with contextlib.redirect_stdout(io.StringIO()):  # meshcat prints the URL
                viewer = meshcat.Visualizer(zmq_url=self._server.zmq_url)
            self.visualizer = MeshcatVisualizer(model, None, visuals)
            self.visualizer.initViewer(viewer=viewer)
            self.drawn: DrawnScene = draw(self.visualizer)
            self.overlay = overlay_html(self.drawn, title)
            self._server.overlay = self.overlay
        except BaseException:
            self._server.stop()
            raise
        self.url: str = self._server.web_url
        self.port: int = self._server.port

    def static_html(self) -> str:
        """The scene, its animation, legend and player as one self-contained HTML page (opens
        offline)."""
        page = static_page(self.visualizer.viewer.static_html(), self.overlay)
        return page.replace("<head>", f"<head>{PAGE_MARKER}", 1)

    def serve_forever(self) -> None:
        """Block until the server stops or the user presses Ctrl-C."""
        with contextlib.suppress(KeyboardInterrupt):
            self._server.wait()

    def close(self) -> None:
        """Disconnect and stop the server."""
        self.visualizer.viewer.window.zmq_socket.close(linger=0)
        self._server.stop()

    def __enter__(self) -> SceneViewer:
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()


class CycleViewer(SceneViewer):
    """A live MeshCat viewer of one feeding cycle, served on 127.0.0.1 only
    (:class:`SceneViewer`).

    Args:
        feeder: The device.
        cycle: Its sampled cycle (:func:`~feeder.motion.cycle.feeding_cycle`), N samples.
        forces: Optional arrows by name: forces [N] and application points [m] in the device's
            axes (moving with the hull on a vehicle), each (N, 3) (see
            :data:`~feeder.viz.scene.ForceSeries`).
        base: The vehicle's motion the device rides on (None: standing level).
        port: Web port; None picks a free one.
    """

    def __init__(
        self,
        feeder: Feeder,
        cycle: CycleKinematics,
        forces: Mapping[str, ForceSeries] | None = None,
        *,
        base: BaseMotion | None = None,
        port: int | None = None,
    ):
        forces = _check_forces(forces or {}, cycle.t.size)
        visuals = pin.buildGeomFromUrdfString(feeder.model, feeder.urdf, pin.GeometryType.VISUAL)
        title = f"{feeder.params.name} feeder, ε = {np.degrees(cycle.elevation):g}°"
        if base is not None:
            title += f"; {base.describe()}"
        draw = partial(draw_cycle, feeder=feeder, cycle=cycle, forces=forces, base=base)
        super().__init__(feeder.model, visuals, draw, title, port)


class MechanismViewer(SceneViewer):
    """A live MeshCat viewer of a user's mechanism (:class:`SceneViewer`): its bodies, cuts and
    load arrows over its motion, on its vehicle's moving hull if its file has a ``[base]``
    (:mod:`feeder.viz.mechanism_scene`).

    Args:
        view: The mechanism's poses and loads (:mod:`feeder.study.view`).
        reactions: Joints whose reaction force is drawn (default: those of largest peak).
        port: Web port; None picks a free one.

    Raises:
        InputError: A picked reaction that is not in the view's table; a bad port.
        ViewerPortError: The port is busy.

    Warns:
        FeederWarning: Mesh files that are not found (their visuals are not drawn).
    """

    def __init__(
        self,
        view: MechanismView,
        reactions: Sequence[str] | None = None,
        *,
        port: int | None = None,
    ):
        picked = pick_reactions(view, reactions)  # refused before a server starts
        visuals, kind, left_out = visual_model(view)
        title = f"{view.spec.model.name}: {view.source}"
        if view.base is not None:
            title += f"; {view.spec.base.describe()}"
        draw = partial(draw_mechanism, view=view, kind=kind, reactions=picked, left_out=left_out)
        super().__init__(view.chain.model, visuals, draw, title, port)


def show_cycle(
    feeder: Feeder,
    cycle: CycleKinematics,
    forces: Mapping[str, ForceSeries] | None = None,
    *,
    base: BaseMotion | None = None,
    port: int | None = None,
    open_browser: bool = False,
) -> CycleViewer:
    """Serve the animated cycle on ``http://127.0.0.1:<port>/static/``.

    Args:
        feeder: The device.
        cycle: Its sampled cycle (:func:`~feeder.motion.cycle.feeding_cycle`), N samples.
        forces: Optional arrows by name: forces [N] and application points [m] in the device's
            axes, each (N, 3) (see :data:`ForceSeries`).
        base: The vehicle's motion the device rides on (None: standing level).
        port: Web port; None picks a free one.
        open_browser: Open the viewer in the default web browser.

    Raises:
        InputError: Bad force arrays or port number.
        ViewerPortError: The port is busy.
    """
    viewer = CycleViewer(feeder, cycle, forces, base=base, port=port)
    if open_browser:
        viewer.visualizer.viewer.open()
    return viewer


def write_html(
    feeder: Feeder,
    cycle: CycleKinematics,
    path: str | Path,
    forces: Mapping[str, ForceSeries] | None = None,
    *,
    base: BaseMotion | None = None,
    port: int | None = None,
) -> Path:
    """Write the animated cycle (on the vehicle's motion ``base``, if any; see
    :class:`CycleViewer`) as a self-contained HTML page (about 1 MB, opens offline).

    A MeshCat server runs on 127.0.0.1 while the page is assembled (on ``port``, or a free one).

    Raises:
        InputError: ``path`` cannot be written or is a file other than a page of the viewer
            (:func:`check_writable`), bad force arrays or port number.
        ViewerPortError: The port is busy.
    """
    path = check_writable(path)
    with CycleViewer(feeder, cycle, forces, base=base, port=port) as viewer:
        return write_text(path, viewer.static_html())


def show_mechanism(
    view: MechanismView,
    reactions: Sequence[str] | None = None,
    *,
    port: int | None = None,
    open_browser: bool = False,
) -> MechanismViewer:
    """Serve the mechanism's view on ``http://127.0.0.1:<port>/static/`` (see
    :class:`MechanismViewer`)."""
    viewer = MechanismViewer(view, reactions, port=port)
    if open_browser:
        viewer.visualizer.viewer.open()
    return viewer


def mechanism_html(
    view: MechanismView, reactions: Sequence[str] | None = None, *, port: int | None = None
) -> str:
    """The mechanism's view as a self-contained HTML page (opens offline; meshes embedded). A
    MeshCat server runs on 127.0.0.1 while the page is assembled."""
    with MechanismViewer(view, reactions, port=port) as viewer:
        return viewer.static_html()


def write_mechanism_html(
    view: MechanismView,
    path: str | Path,
    reactions: Sequence[str] | None = None,
    *,
    port: int | None = None,
) -> Path:
    """Write the mechanism's view as a self-contained HTML page (:func:`mechanism_html`).

    Raises:
        InputError: ``path`` cannot be written or is a file other than a page of the viewer
            (:func:`check_writable`), a bad reaction or port.
    """
    path = check_writable(path)
    return write_text(path, mechanism_html(view, reactions, port=port))


MOUNT_FORCE = "mount force (vehicle on device)"
"""The name (and legend label) of the mount's arrow in :func:`cycle_forces`."""


def cycle_forces(feeder: Feeder, dynamics: CycleDynamics) -> dict[str, ForceSeries]:
    """The arrows of ``feeder view``: five loads, at five places, in the device's axes (moving
    with the hull on a vehicle).

    * ``piston force``: the cylinder's force on the piston along its axis (Fig. 14), drawn at
      the piston's centre of gravity S (on its line of action);
    * ``arm pivot reaction``: the frame's force on the arm at its pivot A = (L1, L2);
    * ``forearm hinge force``: the arm's force on the forearm at the hinge origin (Fig. 11);
    * ``grip force``: the tray's force on the payload at its centre of gravity (zero before
      the grip);
    * :data:`MOUNT_FORCE`: the force of the vehicle (or of the ground) on the whole device
      through its frame, at the cylinder pivot B (the model's origin): it carries the device's
      weight and inertia.

    The pin force on the arm and the cylinder pivot's reaction are left out: the cylinder and
    piston carry the loop's load along their axis, so both lie on the piston force's line
    with nearly its size, and would hide it.
    """
    p, kinematics = feeder.params, dynamics.kinematics
    q = kinematics.q
    axis = np.column_stack([np.cos(q[:, 0]), np.sin(q[:, 0]), np.zeros(len(q))])
    model, data = feeder.model, feeder.model.createData()
    hinge_joint = model.getJointId("forearm_joint")
    hinge = np.empty((len(q), 3))
    for k, q_k in enumerate(feeder.to_pinocchio(q)):
        pin.forwardKinematics(model, data, q_k)
        hinge[k] = data.oMi[hinge_joint].translation
    reactions = dynamics.reactions
    return {
        "piston force": (dynamics.loads.piston_force[:, None] * axis, q[:, 1:2] * axis),
        "arm pivot reaction": (
            reactions.joints["arm_frame"].force,
            np.tile([p.L1, p.L2, 0.0], (len(q), 1)),
        ),
        "forearm hinge force": (reactions.joints["forearm_arm"].force, hinge),
        "grip force": (reactions.grip_force, kinematics.payload_position),
        MOUNT_FORCE: (reactions.mount.force, np.zeros((len(q), 3))),
    }


def check_port(port: int | None) -> int | None:
    """The web port if it is None (a free one) or an integer in 1 … 65535, else InputError."""
    if port is None:
        return None
    if isinstance(port, bool) or not isinstance(port, int) or not 1 <= port <= 65535:
        raise InputError(f"port must be an integer in 1 … 65535, got {port!r}")
    return port


def check_writable(path: str | Path) -> Path:
    """``path`` as a Path if an HTML page can be written there: a new file, or a page that the
    viewer wrote (:data:`PAGE_MARKER`); else InputError."""
    path = check_replaceable(path, "an HTML page that feeder view wrote", PAGE_MARKER)
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
