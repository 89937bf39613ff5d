"""Standard output whose reader went away (``demo ... --json run.json | head -1``).

A closed pipe says nothing about the run: its files are written and its exit code kept, and what
is left to print is discarded, without a traceback.
"""

from __future__ import annotations

import contextlib
import os
import sys
from collections.abc import Iterator
from typing import TextIO


class QuietPipe:
    """A text stream that discards its output once its reader has closed the pipe.

    Args:
        stream: The stream to write to (``sys.stdout``).

    Attributes:
        closed_by_reader: Whether a write found the pipe closed.
    """

    def __init__(self, stream: TextIO) -> None:
        self._stream = stream
        self.closed_by_reader = False

    def write(self, text: str) -> int:
        """Write ``text``; nothing once the reader is gone. Returns ``len(text)``."""
        try:
            return self._stream.write(text)
        except BrokenPipeError:
            self._silence()
            return len(text)

    def flush(self) -> None:
        """Flush; nothing once the reader is gone."""
        try:
            self._stream.flush()
        except BrokenPipeError:
            self._silence()

    def _silence(self) -> None:
        """Point the stream's file descriptor at the null device (buffered text goes there)."""
        self.closed_by_reader = True
        null = os.open(os.devnull, os.O_WRONLY)
        try:
            os.dup2(null, self._stream.fileno())
        finally:
            os.close(null)

    def __getattr__(self, name: str) -> object:
        return getattr(self._stream, name)

    def __repr__(self) -> str:
        return f"QuietPipe({self._stream!r}, closed_by_reader={self.closed_by_reader})"


@contextlib.contextmanager
def tolerate_closed_pipes() -> Iterator[None]:
    """Within the block, ``sys.stdout`` and ``sys.stderr`` go quiet when their reader exits.

    Both are flushed at the end of the block, also when it raises (``SystemExit``).
    """
    saved = sys.stdout, sys.stderr
    quiet = [None if stream is None else QuietPipe(stream) for stream in saved]
    sys.stdout, sys.stderr = (q or s for q, s in zip(quiet, saved, strict=True))
    try:
        yield
    finally:
        for stream in quiet:
            if stream is not None:
                stream.flush()
        sys.stdout, sys.stderr = saved
