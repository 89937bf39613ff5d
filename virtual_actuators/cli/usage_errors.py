"""Command-line values that fail only when used (usage errors, exit 2), and closed output pipes.

A closed pipe (``demo ... --json run.json | head -1``) says nothing about the run: its files are
written and its exit code kept, and what is left to print is discarded, without a traceback.
"""

from __future__ import annotations

import contextlib
import os
import sys
from collections.abc import Iterator
from typing import TextIO

__all__ = ["OptionError", "blame", "tolerate_closed_pipes", "writing"]


class OptionError(Exception):
    """A command-line value that turned out unusable at run time (reported as a usage error)."""


@contextlib.contextmanager
def blame(
    option: str, only: type[Exception] | tuple[type[Exception], ...] | None = None
) -> Iterator[None]:
    """Turn a library error raised in the block into an `OptionError` naming ``option``.

    Args:
        option: The option that caused the error.
        only: The error types that ``option`` causes (None: any [`VirtualActuatorError`][]);
            others propagate unchanged.

    Raises:
        OptionError: If the block raises such an error.
    """
    from ..exceptions import VirtualActuatorError

    caught = VirtualActuatorError if only is None else only
    try:
        yield
    except caught as error:
        raise OptionError(f"argument {option}: {error}") from error


@contextlib.contextmanager
def writing(option: str, path: str) -> Iterator[None]:
    """Turn an `OSError` raised while writing ``path`` into an `OptionError` (not exit code 1).

    Raises:
        OptionError: If the block raises an `OSError` (names ``option``, the path and the
            reason).
    """
    try:
        yield
    except OSError as error:
        reason = error.strerror or str(error)
        raise OptionError(f"argument {option}: cannot write {path!r}: {reason}") from error


class _QuietPipe:
    """A text stream that discards its output once its reader has closed the pipe."""

    def __init__(self, stream: TextIO) -> None:
        self._stream = stream

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
        null = os.open(os.devnull, os.O_WRONLY)
        try:
            os.dup2(null, self._stream.fileno())
        finally:
            os.close(null)

    def __getattr__(self, name: str) -> object:
        return getattr(self._stream, name)


@contextlib.contextmanager
def tolerate_closed_pipes() -> Iterator[None]:
    """Within the block, ``sys.stdout`` and ``sys.stderr`` go quiet when their reader exits.

    Both are flushed at the end of the block, also when it raises (``SystemExit``).
    """
    saved = sys.stdout, sys.stderr
    quiet = [None if stream is None else _QuietPipe(stream) for stream in saved]
    sys.stdout, sys.stderr = (q or s for q, s in zip(quiet, saved, strict=True))
    try:
        yield
    finally:
        for stream in quiet:
            if stream is not None:
                stream.flush()
        sys.stdout, sys.stderr = saved
