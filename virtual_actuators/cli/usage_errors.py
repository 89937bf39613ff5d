"""The command line's usage errors (exit 2), and closed output pipes.

Options that the demo would ignore, or whose package is missing, are refused before anything
runs; a value that fails only when used is an `OptionError`. A closed pipe (``demo ... --json
run.json | head -1``) says nothing about the run: its files are written and its exit code kept,
and what is left to print is discarded, without a traceback.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
from collections.abc import Iterator
from typing import TextIO

from .options import STAND_OPTIONS, WALK_DEMOS, WALK_OPTIONS, WALK_OWN_OPTIONS, wants_viewer


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


def check_demo_options(args: argparse.Namespace, parser: argparse.ArgumentParser) -> None:
    """Refuse options that the chosen demo would ignore (a usage error, exit 2)."""
    if args.name == "stand":
        for dest, option in WALK_OPTIONS + WALK_OWN_OPTIONS:
            if dest not in STAND_OPTIONS and getattr(args, dest) not in (None, False):
                parser.error(
                    f"argument {option}: only the walks ({', '.join(WALK_DEMOS)}) use it, not stand"
                )
        for dest in ("duration", "json"):
            if getattr(args, dest) is not None and not args.estimator:
                parser.error(
                    f"argument --{dest}: stand runs a closed loop only with --estimator; give it"
                )
    else:
        _check_walk_options(args, parser)
    if args.name == "balance" and args.speed is not None:
        parser.error("argument --speed: balance does not use it")
    if args.window is not None and args.plot is None:
        parser.error("argument --window: it selects what --plot draws; give --plot PATH too")
    if args.realtime and not args.viz:
        parser.error(
            "argument --realtime: it paces the live viewer to wall-clock time; give --viz too "
            "(a run without it goes as fast as it can)"
        )


def _check_walk_options(args: argparse.Namespace, parser: argparse.ArgumentParser) -> None:
    """Refuse a walk's options that it does not take, or that do not fit its range or run."""
    from ..exceptions import MissingDependencyError

    try:  # the walk registry brings MuJoCo: a usage error naming the extra without it
        from ..gaits.registry import WALKS as walks
    except MissingDependencyError as error:
        parser.error(str(error))
    walk = walks[args.name]
    for dest, option in WALK_OWN_OPTIONS:
        if dest not in walk.options and getattr(args, dest) not in (None, False):
            users = [name for name, other in walks.items() if dest in other.options]
            if dest in STAND_OPTIONS:
                parser.error(
                    f"argument {option}: only the stand demo and {', '.join(users)} use it, "
                    f"not {args.name}"
                )
            parser.error(f"argument {option}: only {', '.join(users)} uses it, not {args.name}")
    _check_speed(args, parser, walk)
    if "path" in walk.options and args.path != "sine":
        if args.amplitude is not None or args.wavelength is not None:
            parser.error("argument --amplitude/--wavelength: only --path sine uses them")
    if args.window is not None and not walk.plot_window:
        windowed = " and ".join(name for name, other in walks.items() if other.plot_window)
        parser.error(f"argument --window: the plots of {windowed} take it, not {args.name}")
    if args.window is not None:
        _check_window(args, parser, walk.duration)


def _check_window(args: argparse.Namespace, parser: argparse.ArgumentParser, default: float):
    """Refuse a ``--window`` that holds no simulated second of the run (before it runs)."""
    duration = default if args.duration is None else args.duration
    start, stop = args.window
    run = f"the run lasts {duration:g} s" + (
        f" ({args.name}'s default; --duration sets it)" if args.duration is None else ""
    )
    if start is not None and start >= duration:
        parser.error(f"argument --window: it starts at {start:g} s, but {run}")
    if stop is not None and stop <= 0.0:
        parser.error(f"argument --window: it ends at {stop:g} s, before the run starts at 0 s")


def _check_speed(args: argparse.Namespace, parser: argparse.ArgumentParser, walk) -> None:
    """Refuse a ``--speed`` outside the walk's supported range, unless ``--force-speed``."""
    if args.force_speed and args.speed is None:
        parser.error("argument --force-speed: it lets a --speed outside the range run; give one")
    if args.speed is None or args.force_speed:
        return
    options = {
        name: getattr(args, name)
        for name in walk.options
        if name in ("robot", "gait", "pendulum", "track") and getattr(args, name) is not None
    }
    from ..exceptions import InvalidInputError

    try:
        walk.check_speed(args.speed, forced_by="--force-speed", **options)
    except InvalidInputError as error:
        parser.error(f"argument --speed: {error}")


def _needed_packages(args: argparse.Namespace) -> list[tuple[str, str, str]]:
    """``(module, its extra, what needs it)`` of each optional package the command imports."""
    walks = args.command == "sweep" or (args.command == "demo" and args.name != "stand")
    needs = []
    if walks:
        needs.append(("mujoco", "sim", "MuJoCo simulation (the walks and sweeps)"))
        if not args.quiet:
            needs.append(("tqdm", "sim", "The progress bar (--quiet runs without it)"))
    if getattr(args, "plot", None):
        needs.append(("matplotlib", "plots", "The plot (--plot)"))
    if wants_viewer(args):
        needs.append(("meshcat", "viz", "The MeshCat viewer (--viz, --record)"))
    engine = getattr(args, "engine", None)
    if engine == "dask":
        engine_dask = "The Dask engine (--engine dask)"
        needs += [(name, "dask", engine_dask) for name in ("dask", "distributed")]
    elif engine == "ray":
        needs.append(("ray", "ray", "The Ray engine (--engine ray)"))
    return needs


def check_installed(args: argparse.Namespace, parser: argparse.ArgumentParser) -> None:
    """Import every optional package the command needs, or fail with a usage error.

    Raises:
        SystemExit: With code 2 and a message naming the missing package, its extra and the
            command that installs it (`import_optional`).
    """
    from ..exceptions import MissingDependencyError, import_optional

    for need in _needed_packages(args):
        try:
            import_optional(*need)
        except MissingDependencyError as error:
            parser.error(str(error))
