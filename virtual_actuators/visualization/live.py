"""The live window: a MeshCat server fed through a relay process, and fast transform packing."""

from __future__ import annotations

import os
import struct
import subprocess
import sys
import time
from pathlib import Path

import meshcat.commands as mc
import numpy as np
import umsgpack

from ..exceptions import VirtualActuatorError
from .windows import SceneWindow, path_of

#: Seconds to wait for an existing server's answer, and the unanswered commands above which
#: the window is congested.
ANSWER_TIMEOUT = 5.0
MAX_BACKLOG = 600


class LiveWindow(SceneWindow):
    """A MeshCat server, fed through a relay process that never makes the caller wait.

    `commit` writes a frame's packed commands to the relay in one pipe write; with more than
    `MAX_BACKLOG` commands unanswered the window is `congested` and live frames are skipped.

    Args:
        zmq_url: ZMQ URL of a running MeshCat server (``meshcat-server`` prints it); None
            starts a server as a subprocess (it stops with this process).

    Raises:
        VirtualActuatorError: No server answers at ``zmq_url``, or the server or the relay
            cannot start.
    """

    live = True

    def __init__(self, zmq_url: str | None = None) -> None:
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
            web_url = self._ask(zmq_url, b"url", ANSWER_TIMEOUT).decode("utf-8")
        self.zmq_url, self.web_url = zmq_url, web_url
        self.sent = self.answered = 0
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
            self._deliver_transform(path_of(command), command.matrix)
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
            prefix = _LENGTH.pack(13) + b"set_transform" + _LENGTH.pack(len(encoded)) + encoded
            prefix = _FRAME_PREFIXES[path] = prefix + _LENGTH.pack(size) + header
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
            message = "The MeshCat relay process stopped; create a new viewer."
            raise VirtualActuatorError(message) from error

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
        """Whether the server lags by more than `MAX_BACKLOG` commands."""
        return self.backlog > MAX_BACKLOG

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
    header = umsgpack.packb({"type": "set_transform", "path": path, "matrix": []})[:-1]
    return header + b"\xdc\x00\x10"  # an array of 16


def _matrix_bytes(matrix: np.ndarray) -> bytes:
    buffer = _MATRIX_BUFFER
    buffer["value"] = matrix.T.ravel()  # column-major, as three.js reads it
    return buffer.tobytes()


_DOUBLE = np.dtype([("marker", "u1"), ("value", ">f8")])
_MATRIX_BUFFER = np.zeros(16, dtype=_DOUBLE)
_MATRIX_BUFFER["marker"] = 0xCB  # msgpack float 64
_FRAME_PREFIXES: dict[str, bytes] = {}
