"""Command-line values that fail only when used, reported as usage errors (exit 2)."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

__all__ = ["OptionError", "blame", "writing"]


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
