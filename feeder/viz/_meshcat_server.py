"""A MeshCat server whose web port listens on 127.0.0.1 only.

MeshCat 0.3.2's tornado server binds every interface (0.0.0.0 and [::]) unless told otherwise.
Here its web sockets are bound to the loopback address before tornado starts, so a busy port
fails cleanly (:class:`~feeder.exceptions.ViewerPortError`) and nothing else is ever bound; the
ZMQ port is on 127.0.0.1 already (on a free port the system gives: MeshCat's own search from port
6000 prints "Port: 6000 in use" for each busy one). The server runs on a background thread and
says nothing on the terminal: MeshCat's "opened:"/"closed:" lines for each browser tab and
tornado's access log (``404 GET /favicon.ico``) are left out. Its page
(``/static/``) is MeshCat's with :attr:`MeshcatServer.panels` inserted (the legend and player of
:mod:`feeder.viz._page`); every other file is MeshCat's own.
"""

from __future__ import annotations

import asyncio
import os
import queue
import socket
import threading

import tornado.httpserver
import tornado.netutil
import tornado.web
import zmq
from meshcat.servers import zmqserver
from zmq.eventloop.zmqstream import ZMQStream

from ..exceptions import FeederError, ViewerPortError
from ._page import with_panels

LOOPBACK = "127.0.0.1"
"""The only address the viewer's web server listens on."""


class _LoopbackApplication(tornado.web.Application):
    """MeshCat's web application on sockets bound beforehand to 127.0.0.1 (tornado's
    ``listen`` would bind every interface)."""

    def __init__(self, sockets: list[socket.socket], handlers: list):
        super().__init__(handlers, log_function=lambda handler: None)  # no access log
        self._sockets = sockets
        self.http_server: tornado.httpserver.HTTPServer | None = None

    def listen(self, port: int, address: str = "", **kwargs) -> tornado.httpserver.HTTPServer:
        self.http_server = tornado.httpserver.HTTPServer(self, **kwargs)
        self.http_server.add_sockets(self._sockets)
        return self.http_server


class _PageHandler(tornado.web.RequestHandler):
    """MeshCat's viewer page with the server's panels inserted before ``</body>``."""

    def initialize(self, server: MeshcatServer) -> None:
        self._server = server

    def get(self) -> None:
        with open(
            os.path.join(zmqserver.VIEWER_ROOT, zmqserver.VIEWER_HTML), encoding="utf-8"
        ) as f:
            page = f.read()
        self.set_header("Content-Type", "text/html; charset=utf-8")
        self.set_header("Cache-Control", "no-store")
        self.write(with_panels(page, self._server.panels))


class _QuietWebSocketHandler(zmqserver.WebSocketHandler):
    """MeshCat's websocket handler without its "opened:"/"closed:" lines on stderr."""

    def open(self) -> None:
        self.bridge.websocket_pool.add(self)
        self.bridge.send_scene(self)

    def on_close(self) -> None:
        self.bridge.websocket_pool.discard(self)


class _LoopbackBridge(zmqserver.ZMQWebSocketBridge):
    """MeshCat's ZMQ ↔ websocket bridge serving on pre-bound loopback sockets."""

    def __init__(self, sockets: list[socket.socket], server: MeshcatServer):
        self._sockets = sockets
        self._server = server
        super().__init__(
            zmq_url=f"tcp://{LOOPBACK}", host=LOOPBACK, port=sockets[0].getsockname()[1]
        )

    def setup_zmq(self, url: str):
        """The ZMQ socket on a free port of ``url`` (``tcp://127.0.0.1``), its stream and its
        full address."""
        zmq_socket = self.context.socket(zmq.REP)
        port = zmq_socket.bind_to_random_port(url)
        stream = ZMQStream(zmq_socket)
        stream.on_recv(self.handle_zmq)
        return zmq_socket, stream, f"{url}:{port}"

    def make_app(self) -> _LoopbackApplication:
        return _LoopbackApplication(
            self._sockets,
            [
                (r"/static/(?:index\.html)?", _PageHandler, {"server": self._server}),
                (
                    r"/static/(.*)",
                    zmqserver.StaticFileHandlerNoCache,
                    {"path": zmqserver.VIEWER_ROOT, "default_filename": zmqserver.VIEWER_HTML},
                ),
                (r"/", _QuietWebSocketHandler, {"bridge": self}),
            ],
        )


class MeshcatServer:
    """A MeshCat server on a background thread, its web port on 127.0.0.1:``port``."""

    def __init__(self, port: int | None):
        self.panels = ""
        """HTML inserted into the viewer page (set it before a browser loads the page)."""
        try:
            sockets = tornado.netutil.bind_sockets(port or 0, address=LOOPBACK)
        except OSError as exc:
            raise ViewerPortError(
                f"cannot serve the viewer on port {port} of {LOOPBACK}: {exc.strerror}; "
                "choose another port"
            ) from exc
        self.port: int = sockets[0].getsockname()[1]
        started: queue.Queue = queue.Queue()
        self._thread = threading.Thread(
            target=self._run, args=(sockets, started, self), name="meshcat-server", daemon=True
        )
        self._thread.start()
        bridge = started.get()
        if isinstance(bridge, BaseException):
            raise FeederError(f"cannot start the MeshCat server: {bridge}") from bridge
        self._bridge: _LoopbackBridge = bridge
        self.zmq_url: str = bridge.zmq_url
        self.web_url: str = bridge.web_url

    @staticmethod
    def _run(sockets: list[socket.socket], started: queue.Queue, server: MeshcatServer) -> None:
        loop = asyncio.new_event_loop()
        asyncio.set_event_loop(loop)
        try:
            bridge = _LoopbackBridge(sockets, server)
        except Exception as exc:  # reported to the starting thread
            for sock in sockets:
                sock.close()
            started.put(exc)
            loop.close()
            return
        started.put(bridge)
        bridge.run()
        bridge.app.http_server.stop()
        for websocket in list(bridge.websocket_pool):
            websocket.close()
        bridge.zmq_stream.close()
        bridge.ioloop.close()
        loop.close()

    def wait(self) -> None:
        """Block until the server stops (interruptible by Ctrl-C)."""
        while self._thread.is_alive():
            self._thread.join(timeout=0.5)

    def stop(self) -> None:
        """Stop serving and release both ports."""
        if self._thread.is_alive():
            self._bridge.ioloop.add_callback(self._bridge.ioloop.stop)
            self._thread.join()
