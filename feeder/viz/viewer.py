"""The MeshCat viewer of a mechanism's scene — the feeding device's cycle
(:func:`~feeder.viz.device_scene.device_scene`) or a user's model
(:func:`~feeder.viz.model_scene.model_scene`) — served on 127.0.0.1 only, and its static HTML
page: one live viewer (:class:`SceneViewer`) and one page writer (:func:`write_html`) for both.

Both the live page and the static one carry a legend for every colour and a player: play/pause,
loop, a time slider with the time and the stage (:mod:`feeder.viz._page`). MeshCat 0.3.2's
server listens on every interface unless told otherwise; :class:`SceneViewer` starts it here
with its web port bound to 127.0.0.1 (its ZMQ port is on 127.0.0.1 already). The static page
(:func:`scene_html`) embeds MeshCat's JavaScript and the scene: it opens offline, and is written
without a server. It carries
:data:`~feeder.viz._page.PAGE_MARKER` in its head, and replaces no file but such a page.
"""

from __future__ import annotations

import contextlib
import io
import os
from collections.abc import Sequence
from pathlib import Path

import meshcat

from ..exceptions import InputError
from ..files import check_replaceable, write_text
from ..study.view import MechanismView
from ._meshcat_server import MeshcatServer
from ._offline import OfflineWindow
from ._page import PAGE_MARKER, panels_html, static_page
from ._visualizer import MeshcatVisualizer
from .legend import DrawnScene
from .model_scene import model_scene
from .scene import MechanismScene, draw_scene


class SceneViewer:
    """A live MeshCat viewer of one scene, served on 127.0.0.1 only.

    Use as a context manager, or call :meth:`close`.

    Args:
        scene: What to draw (:class:`~feeder.viz.scene.MechanismScene`).
        port: Web port; None picks a free one.

    Raises:
        InputError: A bad port.
        ViewerPortError: The port is busy.

    Attributes:
        url: The viewer's address, ``http://127.0.0.1:<port>/static/``.
        port: The web server's port.
        visualizer: Pinocchio's MeshCat visualizer holding the visual model.
        drawn: What the scene shows: the arrows' scales, the legend, the time line.
        panels: The legend and player HTML of the page.
    """

    def __init__(self, scene: MechanismScene, *, port: int | None = None):
        self._server = MeshcatServer(check_port(port))
        try:
            with contextlib.redirect_stdout(io.StringIO()):  # meshcat prints the URL
                viewer = meshcat.Visualizer(zmq_url=self._server.zmq_url)
            self.visualizer = MeshcatVisualizer(scene.model, None, scene.visuals)
            self.visualizer.initViewer(viewer=viewer)
            self.drawn: DrawnScene = draw_scene(self.visualizer, scene)
            self.panels = panels_html(self.drawn, scene.title)
            self._server.panels = self.panels
        except BaseException:
            self._server.stop()
            raise
        self.url: str = self._server.web_url
        self.port: int = self._server.port

    def static_html(self) -> str:
        """The scene, its animation, legend and player as one self-contained HTML page (opens
        offline)."""
        return static_page(self.visualizer.viewer.static_html(), self.panels)

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


def show(
    scene: MechanismScene, *, port: int | None = None, open_browser: bool = False
) -> SceneViewer:
    """Serve the scene on ``http://127.0.0.1:<port>/static/`` (on ``port``, or a free one),
    opening it in the default web browser if ``open_browser``.

    Raises:
        InputError: A bad port number.
        ViewerPortError: The port is busy.
    """
    viewer = SceneViewer(scene, port=port)
    if open_browser:
        viewer.visualizer.viewer.open()
    return viewer


def scene_html(scene: MechanismScene) -> str:
    """The scene as a self-contained HTML page (about 1 MB, opens offline; meshes embedded),
    assembled in this process: MeshCat's page without its server (:class:`OfflineWindow`)."""
    window = OfflineWindow()
    visualizer = MeshcatVisualizer(scene.model, None, scene.visuals)
    visualizer.initViewer(viewer=meshcat.Visualizer(window=window))
    drawn = draw_scene(visualizer, scene)
    return static_page(window.get_scene(), panels_html(drawn, scene.title))


def write_html(scene: MechanismScene, path: str | Path) -> Path:
    """Write the scene as a self-contained HTML page (:func:`scene_html`).

    Raises:
        InputError: ``path`` cannot be written or is a file other than a page of the viewer
            (:func:`check_writable`).
    """
    path = check_writable(path)
    return write_text(path, scene_html(scene))


def mechanism_html(view: MechanismView, reactions: Sequence[str] | None = None) -> str:
    """A user's mechanism's view as a self-contained HTML page (the 3-D view of
    ``report.html``), with the reaction forces of ``reactions`` (default: the largest)."""
    return scene_html(model_scene(view, reactions))


def check_port(port: int | None) -> int | None:
    """The web port if it is None (a free one) or an integer in 1 … 65535, else InputError."""
    if port is None:
        return None
    if isinstance(port, bool) or not isinstance(port, int) or not 1 <= port <= 65535:
        raise InputError(f"port must be an integer in 1 … 65535, got {port!r}")
    return port


def check_writable(path: str | Path) -> Path:
    """``path`` as a Path if an HTML page can be written there: a new file, or a page that the
    viewer wrote (:data:`~feeder.viz._page.PAGE_MARKER`); else InputError."""
    path = check_replaceable(path, "an HTML page that feeder view wrote", PAGE_MARKER)
    if not path.parent.is_dir():
        raise InputError(f"cannot write the HTML file {path}: no directory {path.parent}")
    if not os.access(path.parent, os.W_OK) or (path.exists() and not os.access(path, os.W_OK)):
        raise InputError(f"cannot write the HTML file {path}: permission denied")
    return path
