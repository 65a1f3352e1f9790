"""A MeshCat window without a server, for the static page (:func:`feeder.viz.viewer.scene_html`).

MeshCat's static page is written by its server: the visualizer sends each command over ZMQ, the
server keeps them in its scene tree and, asked for the scene, packs the tree into its HTML page.
:class:`OfflineWindow` takes the visualizer's commands in-process and hands them to the server's
own handler (``ZMQWebSocketBridge.handle_zmq``, called on this window: the tree, the page and
their order are MeshCat's), so that no thread, socket or port is opened to write a page.
"""

from __future__ import annotations

import umsgpack
from meshcat.servers.tree import SceneTree
from meshcat.servers.zmqserver import ZMQWebSocketBridge


class _Reply:
    """Where MeshCat's handler puts its answer (its ZMQ socket's ``send``)."""

    def __init__(self) -> None:
        self.data = b""

    def send(self, data: bytes) -> None:
        self.data = data


class OfflineWindow:
    """What :class:`meshcat.Visualizer` needs of a window (``send``, ``get_scene``), with
    MeshCat's scene tree in this process: ``meshcat.Visualizer(window=OfflineWindow())``."""

    def __init__(self) -> None:
        self.tree = SceneTree()
        self.websocket_pool: set = set()  # no browser is connected
        self.zmq_socket = _Reply()

    def forward_to_websockets(self, frames: list[bytes]) -> None:
        """Nothing to forward: no browser is connected."""

    def send(self, command) -> None:
        """One drawing command, packed as :class:`meshcat.visualizer.ViewerWindow` packs it."""
        data = command.lower()
        path = data["path"].encode("utf-8")
        self._handle([data["type"].encode("utf-8"), path, umsgpack.packb(data)])

    def get_scene(self) -> str:
        """MeshCat's static HTML page of the scene (its JavaScript and every command)."""
        self._handle([b"get_scene"])
        return self.zmq_socket.data.decode("utf-8")

    def _handle(self, frames: list[bytes]) -> None:
        ZMQWebSocketBridge.handle_zmq(self, frames)
