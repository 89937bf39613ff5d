"""Argument types of the command line's output files, each tried before the run, not after it.

A bad path is a usage error (exit 2), never a traceback after a long run.
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path


def output_path(text: str) -> str:
    """An output file that can be written now, opened as the run will at its end.

    Raises:
        argparse.ArgumentTypeError: If the path is empty or a folder, its folder does not
            exist, or it cannot be created, opened for writing or written (``/dev/full``, a
            file under ``/proc``, a read-only file system, permission denied).
    """
    try:
        path = Path(text)
        if not text.strip():
            raise argparse.ArgumentTypeError("expected a file path, got an empty string")
        if path.is_dir():
            raise argparse.ArgumentTypeError(f"{text!r} is a folder; give a file path in it")
        if not path.parent.is_dir():
            raise argparse.ArgumentTypeError(
                f"{text!r} is not a file path in an existing folder "
                f"(no folder {str(path.parent)!r})"
            )
        if not os.access(path if path.exists() else path.parent, os.W_OK):
            raise argparse.ArgumentTypeError(f"{text!r} cannot be written (permission denied)")
    except (OSError, RuntimeError, ValueError) as error:  # a name too long, a NUL byte...
        raise argparse.ArgumentTypeError(
            f"{text[:80]!r} is not a usable file path ({error})"
        ) from None
    try:
        _try_writing(path)
    except OSError as error:
        reason = error.strerror or str(error)
        raise argparse.ArgumentTypeError(f"{text[:80]!r} cannot be written ({reason})") from None
    return text


def figure_path(text: str) -> str:
    """``sweep --plot``: an `output_path` whose suffix is an image format matplotlib writes.

    Raises:
        argparse.ArgumentTypeError: An unknown suffix (matplotlib picks the format by it), a
            path that `output_path` refuses, or matplotlib is not installed (the message
            names its extra).
    """
    from ..exceptions import MissingDependencyError, import_optional

    try:
        import_optional("matplotlib", "plots", "The plot")
    except MissingDependencyError as error:
        raise argparse.ArgumentTypeError(str(error)) from None
    from matplotlib.backend_bases import FigureCanvasBase

    formats = sorted(FigureCanvasBase.get_supported_filetypes())
    suffix = Path(text).suffix.lower().removeprefix(".")
    if suffix not in formats:
        raise argparse.ArgumentTypeError(
            f"{text[:80]!r}: its suffix names the image format, one of "
            f"{', '.join('.' + name for name in formats)}"
        )
    return output_path(text)


def _try_writing(path: Path) -> None:
    """Give ``path`` an empty write, as the run will at its end, and leave it as it was.

    An existing file is opened for appending (never truncated); a new one is removed again.

    Raises:
        OSError: If the file cannot be created, opened for writing or written.
    """
    existed = path.exists()
    flags = os.O_WRONLY | os.O_APPEND | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0)
    descriptor = os.open(path, flags | (0 if existed else os.O_CREAT), 0o666)
    try:
        os.write(descriptor, b"")
    finally:
        os.close(descriptor)
        if not existed:  # through a dangling symbolic link, the file created is its target
            Path(os.path.realpath(path)).unlink(missing_ok=True)
