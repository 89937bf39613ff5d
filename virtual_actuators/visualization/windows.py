"""Where the scene's commands go: a MeshCat server, a recorder, or nowhere but the HTML page.

``meshcat.Visualizer(window=w)`` calls ``w.send(command)`` with MeshCat command objects
(``SetObject``, ``SetTransform``, ``SetProperty``, ``Delete``, ...). Every window here keeps a
mirror of the scene those commands build (the same tree MeshCat's server keeps), so that
:meth:`SceneWindow.static_html` can write a standalone page without any server:

- :class:`OfflineWindow`: no server, nothing sent; used to record HTML files headless.
- :class:`CommandRecorder`: also keeps every command in order (tests inspect them).
- :class:`LiveWindow`: a MeshCat server (started as a subprocess, or an existing one at a ZMQ
  URL) fed through a relay process: drawing costs the control loop the packing and one pipe
  write per frame, and a lagging server makes the viewer skip frames instead of slowing the
  loop down.
- :class:`ForwardingWindow`: mirrors, then forwards to any object with ``send`` (e.g. MeshCat's
  own ``ViewerWindow``).
"""

from __future__ import annotations

import base64
import html
import os
import struct
import subprocess
import sys
import threading
import time
from pathlib import Path

import meshcat.commands as mc
import numpy as np
import umsgpack
from meshcat.path import Path as MeshcatPath

from ..exceptions import InvalidInputError, VirtualActuatorError


def _path_of(command: object) -> str:
    path = getattr(command, "path", None)
    if path is None:
        return str(command.lower().get("path", ""))
    return path.lower() if hasattr(path, "lower") and not isinstance(path, str) else str(path)


class _Node:
    __slots__ = ("object", "properties", "transform")

    def __init__(self) -> None:
        self.object = None
        self.properties: dict[str, object] = {}
        self.transform = None


def pack(command: object) -> bytes:
    """MessagePack bytes of a MeshCat command (what the server and the browser decode)."""
    return umsgpack.packb(command.lower())


class SceneWindow:
    """Base window: mirrors the scene built by the commands it receives.

    Subclasses deliver the commands somewhere in :meth:`_deliver`.

    Attributes:
        live: Whether commands reach a viewer as they are sent (a server or a recorder standing
            for one); the :class:`~virtual_actuators.visualization.Viewer` only throttles and
            sends live updates to live windows.
        web_url: URL of the live viewer, or None.

    """

    live: bool = False
    web_url: str | None = None

    def __init__(self) -> None:
        self._nodes: dict[str, _Node] = {}
        self._lock = threading.Lock()

    # -- the meshcat window interface ----------------------------------------------------------

    def send(self, command: object) -> None:
        """Apply a MeshCat command to the mirror and deliver it."""
        self._mirror(command)
        self._deliver(command)

    def open(self) -> SceneWindow:
        """Open the live viewer in a browser, if there is one."""
        if self.web_url:
            import webbrowser

            webbrowser.open(self.web_url, new=2)
        return self

    def send_transform(self, path: str, matrix: np.ndarray) -> None:
        """Fast path of ``send(SetTransform(matrix, path))`` for a path given as a string."""
        self._node(path).transform = matrix
        self._deliver_transform(path, matrix)

    def _deliver(self, command: object) -> None:
        """Send the command on (nothing by default)."""

    def _deliver_transform(self, path: str, matrix: np.ndarray) -> None:
        """Send a transform on (by default as a MeshCat command to :meth:`_deliver`)."""
        self._deliver(mc.SetTransform(matrix, MeshcatPath(tuple(p for p in path.split("/") if p))))

    def commit(self) -> None:
        """Deliver the commands queued since the last commit (nothing to do by default)."""

    def flush(self, timeout: float | None = None) -> bool:
        """Wait until every command was delivered; True if they were (always, here)."""
        return True

    def close(self) -> None:
        """Release the window's resources (nothing by default)."""

    # -- the mirror ----------------------------------------------------------------------------

    def _mirror(self, command: object) -> None:
        if isinstance(command, mc.SetTransform):
            self._node(_path_of(command)).transform = command.matrix
        elif isinstance(command, mc.SetProperty):
            self._node(_path_of(command)).properties[command.key] = command
        elif isinstance(command, mc.SetObject):
            node = self._node(_path_of(command))
            node.object, node.properties = command, {}
        elif isinstance(command, mc.Delete):
            self._delete(_path_of(command))
        elif isinstance(command, (mc.SetAnimation, mc.CaptureImage)):
            pass  # animations belong to a page, not to the scene tree
        else:  # other objects with a set_object lowering (Pinocchio's Collada meshes)
            data = command.lower()
            if data.get("type") == "set_object":
                node = self._node(str(data.get("path", "")))
                node.object, node.properties = command, {}

    def _node(self, path: str) -> _Node:
        node = self._nodes.get(path)
        if node is None:
            with self._lock:
                node = self._nodes.setdefault(path, _Node())
        return node

    def _delete(self, path: str) -> None:
        with self._lock:
            if path in ("", "/"):
                self._nodes.clear()
                return
            prefix = path.rstrip("/") + "/"
            for key in [k for k in self._nodes if k == path or k.startswith(prefix)]:
                del self._nodes[key]

    def scene_commands(self) -> list[object]:
        """The commands that rebuild the current scene: objects, properties, then transforms."""
        with self._lock:
            nodes = list(self._nodes.items())
        out = []
        for path, node in nodes:
            if node.object is not None:
                out.append(node.object)
            out.extend(node.properties.values())
            if node.transform is not None:
                entries = tuple(p for p in path.split("/") if p)
                out.append(mc.SetTransform(node.transform, MeshcatPath(entries)))
        return out

    def static_html(
        self, extra: list[object] = (), title: str = "MeshCat", overlay: str = ""
    ) -> str:
        """A self-contained HTML page showing the current scene (and ``extra`` commands).

        The three.js viewer bundled with MeshCat is inlined and the commands are embedded as
        base64 MessagePack decoded in order by the page itself: the file opens offline.

        Args:
            extra: Commands applied after the scene (e.g. a ``set_animation``).
            title: Page title.
            overlay: HTML placed over the 3D view (a legend).

        Returns:
            The page.

        """
        blobs = [pack(c) for c in [*self.scene_commands(), *extra]]
        return page(blobs, title=title, overlay=overlay)

    def __repr__(self) -> str:
        return f"{type(self).__name__}({len(self._nodes)} nodes)"


class OfflineWindow(SceneWindow):
    """A window with no viewer: only the mirror (for HTML recordings without a server)."""

    live = False


class CommandRecorder(SceneWindow):
    """Keeps every command in order, for tests and inspection; stands for a live viewer.

    Attributes:
        commands: Every command received, as MeshCat command objects.

    """

    live = True

    def __init__(self) -> None:
        super().__init__()
        self.commands: list[object] = []

    def _deliver(self, command: object) -> None:
        self.commands.append(command)

    def clear(self) -> None:
        """Forget the recorded commands (the mirror stays)."""
        self.commands.clear()

    def lowered(self) -> list[dict]:
        """Every command as the dict MeshCat sends (``type``, ``path``, ...)."""
        return [c.lower() for c in self.commands]

    def paths(self, kind: str | None = None) -> list[str]:
        """Paths of the recorded commands, optionally of one type (``"set_transform"``, ...)."""
        names = {
            "set_transform": mc.SetTransform,
            "set_object": mc.SetObject,
            "set_property": mc.SetProperty,
            "delete": mc.Delete,
        }
        return [
            _path_of(c)
            for c in self.commands
            if kind is None or isinstance(c, names.get(kind, type(None)))
        ]

    def last_transform(self, path: str):
        """The last matrix sent to ``path`` (a ``(4, 4)`` array), or None."""
        for command in reversed(self.commands):
            if isinstance(command, mc.SetTransform) and _path_of(command) == path:
                return command.matrix
        return None

    def objects(self) -> dict[str, dict]:
        """The lowered object of every ``set_object`` command, by path (last one wins)."""
        out = {}
        for command in self.commands:
            if isinstance(command, mc.SetObject):
                out[_path_of(command)] = command.object.lower()
        return out

    def visible(self, path: str) -> bool | None:
        """The last ``visible`` property sent to ``path``, or None if never sent."""
        for command in reversed(self.commands):
            if (
                isinstance(command, mc.SetProperty)
                and command.key == "visible"
                and _path_of(command) == path
            ):
                return bool(command.value)
        return None

    def __repr__(self) -> str:
        return f"CommandRecorder({len(self.commands)} commands, {len(self._nodes)} nodes)"


class ForwardingWindow(SceneWindow):
    """Mirror the scene, then forward every command to another window.

    Args:
        target: Any object with ``send(command)`` (MeshCat's ``ViewerWindow``...).
        live: Whether the target shows commands as they come.

    """

    def __init__(self, target: object, live: bool = True) -> None:
        super().__init__()
        if not callable(getattr(target, "send", None)):
            raise InvalidInputError(
                f"window must have a send(command) method (a MeshCat window), got {target!r}."
            )
        self.target = target
        self.live = live
        self.web_url = getattr(target, "web_url", None)

    def _deliver(self, command: object) -> None:
        self.target.send(command)

    def __repr__(self) -> str:
        return f"ForwardingWindow({self.target!r})"


class LiveWindow(SceneWindow):
    """A MeshCat server, fed through a relay process that never makes the caller wait.

    MeshCat's own client waits for the server's reply after every command. This window packs
    the commands (transforms by a fast path), queues them, and on :meth:`commit` writes the
    whole batch to a small relay process (:mod:`.relay`) in one pipe write; the relay sends them
    to the server without waiting and reports how many were answered. The control loop thus
    pays the packing and one write per frame; when more than ``max_backlog`` commands are
    unanswered the window is :attr:`congested` and the viewer skips live frames until the server
    catches up.

    Args:
        zmq_url: ZMQ URL of a running MeshCat server (``meshcat-server`` prints it); None
            starts a server as a subprocess (it stops with this process).
        timeout: Seconds to wait for an existing server's answer.
        max_backlog: Unanswered commands above which the window is congested.

    Raises:
        VirtualActuatorError: No server answers at ``zmq_url``, or the server or the relay
            cannot start.

    """

    live = True

    def __init__(
        self, zmq_url: str | None = None, timeout: float = 5.0, max_backlog: int = 600
    ) -> None:
        super().__init__()
        import zmq

        self._zmq = zmq
        self.server_process = None
        if zmq_url is None:
            from meshcat.servers.zmqserver import start_zmq_server_as_subprocess

            try:
                self.server_process, zmq_url, web_url = start_zmq_server_as_subprocess()
            except Exception as error:  # noqa: BLE001 - any start-up failure, reported typed
                raise VirtualActuatorError(f"Could not start a MeshCat server: {error}") from error
        else:
            web_url = self._ask(zmq_url, b"url", timeout).decode("utf-8")
        self.zmq_url, self.web_url = zmq_url, web_url
        self.max_backlog = int(max_backlog)
        self.sent = 0
        self.answered = 0
        self._batch = bytearray()
        self._acks = b""
        relay = Path(__file__).with_name("relay.py")
        try:
            self.relay_process = subprocess.Popen(
                [sys.executable, str(relay), zmq_url],
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                start_new_session=True,
            )
        except OSError as error:
            raise VirtualActuatorError(f"Could not start the MeshCat relay: {error}") from error
        os.set_blocking(self.relay_process.stdout.fileno(), False)

    def _ask(self, zmq_url: str, request: bytes, timeout: float) -> bytes:
        socket = self._zmq.Context.instance().socket(self._zmq.REQ)
        socket.setsockopt(self._zmq.LINGER, 0)
        try:
            socket.connect(zmq_url)
            socket.send(request)
            if not socket.poll(int(timeout * 1000)):
                raise VirtualActuatorError(
                    f"No MeshCat server answers at zmq_url={zmq_url!r} within {timeout:g} s; "
                    "start one with `meshcat-server` or pass zmq_url=None."
                )
            return socket.recv()
        finally:
            socket.close()

    def _deliver(self, command: object) -> None:
        if isinstance(command, mc.SetTransform):
            self._deliver_transform(_path_of(command), command.matrix)
            return
        lowered = command.lower()
        kind, path = lowered["type"].encode("utf-8"), lowered["path"].encode("utf-8")
        data = umsgpack.packb(lowered)
        self._batch += _LENGTH.pack(len(kind)) + kind + _LENGTH.pack(len(path)) + path
        self._batch += _LENGTH.pack(len(data)) + data
        self.sent += 1

    def _deliver_transform(self, path: str, matrix: np.ndarray) -> None:
        prefix = _FRAME_PREFIXES.get(path)
        if prefix is None:
            encoded = path.encode("utf-8")
            header = _transform_header(path)
            size = len(header) + _DOUBLE.itemsize * 16
            prefix = _FRAME_PREFIXES[path] = (
                _LENGTH.pack(13) + b"set_transform" + _LENGTH.pack(len(encoded)) + encoded
                + _LENGTH.pack(size) + header
            )  # fmt: skip
        self._batch += prefix + _matrix_bytes(matrix)
        self.sent += 1

    def commit(self) -> None:
        """Hand the queued commands to the relay (one pipe write)."""
        if not self._batch:
            return
        batch, self._batch = bytes(self._batch), bytearray()
        stream = self.relay_process.stdin
        try:
            stream.write(_LENGTH.pack(len(batch)) + batch)
            stream.flush()
        except (BrokenPipeError, ValueError) as error:
            raise VirtualActuatorError(
                "The MeshCat relay process stopped; create a new viewer."
            ) from error

    def _read_acks(self) -> None:
        try:
            data = os.read(self.relay_process.stdout.fileno(), 1 << 16)
        except BlockingIOError:
            return
        if not data:
            return
        self._acks = (self._acks + data)[-16:]
        whole = len(self._acks) - len(self._acks) % 8
        if whole:
            (self.answered,) = _COUNT.unpack(self._acks[whole - 8 : whole])
            self._acks = self._acks[whole:]

    @property
    def backlog(self) -> int:
        """Commands sent and not answered yet."""
        self._read_acks()
        return self.sent - self.answered

    @property
    def congested(self) -> bool:
        """Whether the server lags by more than ``max_backlog`` commands."""
        return self.backlog > self.max_backlog

    def flush(self, timeout: float | None = 10.0) -> bool:
        """Send what is queued and wait until the server answered everything.

        Args:
            timeout: Seconds at most (None: forever).

        Returns:
            Whether everything was answered in time.

        """
        self.commit()
        deadline = None if timeout is None else time.monotonic() + timeout
        while self.backlog > 0:
            if deadline is not None and time.monotonic() > deadline:
                return False
            if self.relay_process.poll() is not None:
                return False
            time.sleep(0.005)
        return True

    def close(self) -> None:
        """Stop the relay and the server this window started (if any)."""
        relay = self.relay_process
        if relay.poll() is None:
            try:
                relay.stdin.close()
                relay.wait(timeout=2.0)
            except (OSError, subprocess.TimeoutExpired):
                relay.kill()
                relay.wait()
        if self.server_process is not None and self.server_process.poll() is None:
            self.server_process.kill()
            self.server_process.wait()

    def __repr__(self) -> str:
        server = "own server" if self.server_process is not None else f"zmq {self.zmq_url}"
        return f"LiveWindow({self.web_url!r}, {server}, {self.sent} commands sent)"


_LENGTH = struct.Struct(">I")
_COUNT = struct.Struct(">Q")


def _transform_header(path: str) -> bytes:
    header = _TRANSFORM_HEADERS.get(path)
    if header is None:
        header = umsgpack.packb({"type": "set_transform", "path": path, "matrix": []})[:-1]
        header = _TRANSFORM_HEADERS[path] = header + b"\xdc\x00\x10"  # an array of 16
    return header


def _matrix_bytes(matrix: np.ndarray) -> bytes:
    buffer = _MATRIX_BUFFER
    buffer["value"] = matrix.T.ravel()  # column-major, as three.js reads it
    return buffer.tobytes()


def pack_transform(path: str, matrix: np.ndarray) -> bytes:
    """MessagePack of a ``set_transform`` command, as MeshCat packs it, without umsgpack.

    Equal (once unpacked) to ``umsgpack.packb(SetTransform(matrix, path).lower())``, about ten
    times faster, which matters at tens of transforms per frame.
    """
    return _transform_header(path) + _matrix_bytes(np.asarray(matrix, dtype=float))


_DOUBLE = np.dtype([("marker", "u1"), ("value", ">f8")])
_MATRIX_BUFFER = np.zeros(16, dtype=_DOUBLE)
_MATRIX_BUFFER["marker"] = 0xCB  # msgpack float 64
_TRANSFORM_HEADERS: dict[str, bytes] = {}
_FRAME_PREFIXES: dict[str, bytes] = {}


# -- the standalone page ---------------------------------------------------------------------


def _viewer_bundle() -> str:
    import meshcat

    path = Path(meshcat.__file__).parent / "viewer" / "dist" / "main.min.js"
    return path.read_text(encoding="utf-8")


def page(blobs: list[bytes], title: str = "MeshCat", overlay: str = "") -> str:
    """A standalone HTML page: MeshCat's viewer inlined plus commands decoded in order.

    Args:
        blobs: MessagePack commands.
        title: Page title.
        overlay: HTML shown over the view.

    Returns:
        The page.

    """
    bundle = _viewer_bundle().replace("</script", "<\\/script")
    commands = ",\n".join(f'"{base64.b64encode(b).decode("ascii")}"' for b in blobs)
    return f"""<!DOCTYPE html>
<html>
<head>
<meta charset="utf-8">
<title>{html.escape(title)}</title>
<style>
body {{ margin: 0; }}
#meshcat-pane {{ width: 100vw; height: 100vh; overflow: hidden; }}
#va-overlay {{ position: absolute; left: 8px; bottom: 8px; font: 12px sans-serif;
  background: rgba(255, 255, 255, 0.85); padding: 6px 10px; border-radius: 4px;
  max-width: 45vw; }}
#va-overlay .sw {{ display: inline-block; width: 12px; height: 12px; margin-right: 6px;
  vertical-align: middle; border: 1px solid #444; }}
</style>
</head>
<body>
<div id="meshcat-pane"></div>
{overlay}
<script>
{bundle}
</script>
<script>
var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
var commands = [
{commands}
];
for (var i = 0; i < commands.length; i++) {{
  var text = atob(commands[i]);
  var bytes = new Uint8Array(text.length);
  for (var k = 0; k < text.length; k++) {{ bytes[k] = text.charCodeAt(k); }}
  viewer.handle_command_bytearray(bytes);
}}
</script>
</body>
</html>
"""
