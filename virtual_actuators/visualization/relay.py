"""Relay process of `LiveWindow`: stdin to a MeshCat server, never waiting for it.

Run as ``python relay.py ZMQ_URL`` (it imports only the standard library and pyzmq). It reads
batches from stdin, each a ``>I`` length then commands of three ``>I``-length-prefixed frames
(type, path, MessagePack data), sends them on a DEALER socket without waiting for replies, and
writes the running count of replies as ``>Q`` to stdout. It exits at the end of stdin.
"""

from __future__ import annotations

import os
import struct
import sys


def _read_exact(fd: int, size: int) -> bytes | None:
    chunks, remaining = [], size
    while remaining:
        chunk = os.read(fd, remaining)
        if not chunk:
            return None
        chunks.append(chunk)
        remaining -= len(chunk)
    return b"".join(chunks)


def _commands(batch: bytes):
    offset, end = 0, len(batch)
    while offset < end:
        frames = []
        for _ in range(3):
            (size,) = struct.unpack_from(">I", batch, offset)
            offset += 4
            frames.append(batch[offset : offset + size])
            offset += size
        yield frames


def main(argv: list[str]) -> int:
    """Relay until stdin ends."""
    import zmq

    socket = zmq.Context.instance().socket(zmq.DEALER)
    socket.setsockopt(zmq.LINGER, 0)
    socket.setsockopt(zmq.SNDHWM, 0)
    socket.setsockopt(zmq.RCVHWM, 0)
    socket.connect(argv[0])
    stdin, stdout = sys.stdin.fileno(), sys.stdout.fileno()
    poller = zmq.Poller()
    poller.register(stdin, zmq.POLLIN)
    poller.register(socket, zmq.POLLIN)
    answered = 0
    open_input = True
    pending = 0
    while open_input or pending:
        events = dict(poller.poll(1000))
        if socket in events:
            while True:
                try:
                    socket.recv_multipart(zmq.NOBLOCK)
                except zmq.Again:
                    break
                answered += 1
                pending -= 1
            os.write(stdout, struct.pack(">Q", answered))
        if open_input and stdin in events:
            header = _read_exact(stdin, 4)
            batch = None if header is None else _read_exact(stdin, struct.unpack(">I", header)[0])
            if batch is None:
                open_input = False
                poller.unregister(stdin)
                continue
            for frames in _commands(batch):
                socket.send_multipart([b"", *frames])
                pending += 1
        if not open_input and not events:
            break  # the server stopped answering: give up
    socket.close()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
