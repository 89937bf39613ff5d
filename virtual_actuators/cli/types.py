"""Argument types of the command line: a bad value is a usage error (exit 2), never a traceback.

Heavy modules (MuJoCo, the robot catalog) are imported only when their option is given; output
files are tried before the run, not after it.
"""

from __future__ import annotations

import argparse
import math
import os
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

from ..demos.sweep import MAX_SEEDS

if TYPE_CHECKING:
    from ..gaits.push import Push

#: Bounds of ``--duration`` [s]: a few 1 ms control ticks; every tick is logged in memory.
MIN_DURATION = 0.01
MAX_DURATION = 600.0

#: ``--terrain`` points must lie within this many metres of the origin (x and z).
MAX_TERRAIN_EXTENT = 1000.0

#: Bounds of ``--yaw-rate`` [rad/s] and ``--amplitude`` / ``--wavelength`` [m].
MAX_YAW_RATE = 3.0
MAX_AMPLITUDE = 2.0
MAX_WAVELENGTH = 50.0

#: The bound of ``--speed`` [m/s], which ``--force-speed`` does not lift: ``gaits.base.MAX_SPEED``
#: (named here so that parsing imports no simulation; tests/test_sweep checks the two agree).
MAX_SPEED = 1.5

#: Most processes of ``sweep --workers`` (each holds MuJoCo and a robot: about 150 MiB).
MAX_WORKERS = 256


def _number(text: str, what: str) -> float:
    """A finite float from ``text`` (``what`` names it in messages), or a usage error."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{what} must be a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"{what} must be a finite number, got {text!r}")
    return value


def positive_seconds(text: str) -> float:
    """``--duration``: a finite number of seconds in [`MIN_DURATION`, `MAX_DURATION`].

    Raises:
        argparse.ArgumentTypeError: Otherwise.
    """
    value = _number(text, "duration")
    if value <= 0.0:
        raise argparse.ArgumentTypeError(f"duration must be > 0 s, got {text!r}")
    if not MIN_DURATION <= value <= MAX_DURATION:
        raise argparse.ArgumentTypeError(
            f"duration must be between {MIN_DURATION:g} s (a run needs a few 1 ms control "
            f"ticks) and {MAX_DURATION:g} s (the whole run is logged in memory), got {text!r}"
        )
    return value


def _in_range(text: str, what: str, low: float, high: float, unit: str, open_low: bool = False):
    """A finite number in ``[low, high]`` (``(low, high]`` with ``open_low``), or a usage error."""
    value = _number(text, what)
    if not ((low < value if open_low else low <= value) and value <= high):
        bracket = "(" if open_low else "["
        raise argparse.ArgumentTypeError(
            f"{what} must be in {bracket}{low:g}, {high:g}] {unit}, got {text!r}"
        )
    return value


def walking_speed(text: str) -> float:
    """``--speed``: a desired speed in (0, `MAX_SPEED`] m/s.

    Raises:
        argparse.ArgumentTypeError: Otherwise (beyond `MAX_SPEED`, saying why).
    """
    if _number(text, "speed") > MAX_SPEED:
        raise argparse.ArgumentTypeError(
            f"speed must be in (0, {MAX_SPEED:g}] m/s, got {text!r}: {MAX_SPEED:g} m/s bounds "
            "every walk's desired speed, and --force-speed does not lift it (it lifts only a "
            "walk's supported range): no walk here walks faster (the fastest, go2's trot, was "
            f"measured up to {MAX_SPEED:g} m/s)"
        )
    return _in_range(text, "speed", 0.0, MAX_SPEED, "m/s", open_low=True)


#: ``--direction`` relative to the heading [deg], ``--yaw-rate`` [rad/s] and the sine path's
#: ``--amplitude`` and ``--wavelength`` [m].
direction_degrees = partial(_in_range, what="direction", low=-360.0, high=360.0, unit="degrees")
yaw_rate = partial(_in_range, what="yaw rate", low=-MAX_YAW_RATE, high=MAX_YAW_RATE, unit="rad/s")
amplitude = partial(_in_range, what="amplitude", low=0.0, high=MAX_AMPLITUDE, unit="m")
wavelength = partial(
    _in_range, what="wavelength", low=0.0, high=MAX_WAVELENGTH, unit="m", open_low=True
)


def time_window(text: str) -> tuple[float | None, float | None]:
    """``--window``: ``T0:T1`` seconds, either side may be empty (``:5``, ``10:``).

    Raises:
        argparse.ArgumentTypeError: Not two numbers (or empty) around one colon, or T0 >= T1.
    """
    parts = text.split(":")
    if len(parts) != 2:
        raise argparse.ArgumentTypeError(f"window must be T0:T1 in seconds, got {text!r}")
    start, stop = (_number(p, "window") if p.strip() else None for p in parts)
    if start is not None and stop is not None and start >= stop:
        raise argparse.ArgumentTypeError(f"window start must be before its end, got {text!r}")
    return start, stop


def _whole(text: str, what: str, low: int, high: int | None = None, why: str = "") -> int:
    """A whole number from ``low`` to ``high`` (``why`` says why), or a usage error."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{what} must be a whole number, got {text!r}") from None
    if value < low:
        raise argparse.ArgumentTypeError(f"{what} must be >= {low}, got {text!r}")
    if high is not None and value > high:
        raise argparse.ArgumentTypeError(f"{what} must be at most {high} ({why}), got {text!r}")
    return value


#: ``--seed`` (a non-negative integer), ``sweep --seeds`` (starts per cell, 1 to `MAX_SEEDS`)
#: and ``sweep --workers`` (the process pool's size, 1 to `MAX_WORKERS`).
seed = partial(_whole, what="seed", low=0)
seed_count = partial(
    _whole, what="seeds", low=1, high=MAX_SEEDS, why="every walk of the grid is queued at once"
)
worker_count = partial(
    _whole, what="workers", low=1, high=MAX_WORKERS, why="each worker is a process with MuJoCo"
)


def terrain_spec(text: str) -> str:
    """``--terrain``: a spec `Terrain.parse` accepts, within `MAX_TERRAIN_EXTENT` m of the origin.

    Raises:
        argparse.ArgumentTypeError: If the spec does not parse (with the parser's reason) or a
            point lies too far away.
    """
    from ..exceptions import VirtualActuatorError

    try:  # without MuJoCo, the import's MissingDependencyError names the extra to install
        from ..simulation.terrain import Terrain

        terrain = Terrain.parse(text)
    except VirtualActuatorError as error:
        raise argparse.ArgumentTypeError(str(error)) from None
    far = [
        point for point in terrain.points if max(abs(point[0]), abs(point[1])) > MAX_TERRAIN_EXTENT
    ]
    if far:
        x, z = (float(value) for value in far[0])
        raise argparse.ArgumentTypeError(
            f"terrain point ({x:g}, {z:g}) in {text!r} is too far away: x and z must be within "
            f"+-{MAX_TERRAIN_EXTENT:g} m"
        )
    return text


def robot_name(text: str) -> str:
    """``--robot``: a name ``load_robot`` knows, or an existing URDF file or robot folder.

    Raises:
        argparse.ArgumentTypeError: An empty name, or otherwise (with the closest names).
    """
    from ..models.catalog import list_robots, shown_name, suggest_robots

    if not text.strip():
        raise argparse.ArgumentTypeError(
            f"expected a robot name or a URDF path, got {text!r} (leave --robot out for solo12)"
        )
    names = list_robots(include_aliases=True)
    if text in names or _existing_path(text):
        return text
    raise argparse.ArgumentTypeError(
        f"no robot named {shown_name(text)} and no such URDF file. {suggest_robots(text)}"
    )


def push_spec(text: str) -> Push:
    """``--push N@T[:DEG]``: N newtons from T >= 0 seconds along DEG degrees (0 = +x, N < 0 back).

    Raises:
        argparse.ArgumentTypeError: Otherwise.
    """
    from ..exceptions import InvalidInputError
    from ..gaits.push import Push

    try:
        return Push.parse(text)
    except InvalidInputError:
        raise argparse.ArgumentTypeError(
            f"expected N@T[:DEG], newtons at T >= 0 seconds along DEG degrees (e.g. 250@1.0:90; "
            f"-10@1 pushes 10 N along -x), got {text!r}"
        ) from None


def frame_list(text: str) -> tuple[str, ...]:
    """``--feet``: two or more comma-separated frame names (checked when the robot loads).

    Raises:
        argparse.ArgumentTypeError: Fewer than two names, or an empty one.
    """
    names = tuple(name.strip() for name in text.split(","))
    if len(names) < 2 or not all(names):
        raise argparse.ArgumentTypeError(
            f"expected two or more frame names separated by commas, got {text!r}"
        )
    return names


def value_range(text: str) -> list[float]:
    """``sweep --speed``: ``START:STOP:STEP`` (stop included) or ``a,b,c`` (or ``0.5``).

    Raises:
        argparse.ArgumentTypeError: Not numbers, a step <= 0, more than 1000 values, or a value
            that is not a `walking_speed`.
    """
    try:
        if ":" in text:
            start, stop, step = (float(part) for part in text.split(":"))
            if not (step > 0 and math.isfinite(start) and math.isfinite(stop)):
                raise ValueError("step must be > 0")
            if stop < start:
                raise ValueError("stop is below start")
            span = (stop - start) / step
            if not math.isfinite(span) or span > 1000:
                raise ValueError("more than 1000 values")
            count = math.floor(span + 1e-9) + 1
            values = [round(start + k * step, 10) for k in range(max(count, 0))]
        else:
            values = [float(part) for part in text.split(",")]
    except ValueError as error:
        raise argparse.ArgumentTypeError(
            f"expected START:STOP:STEP or comma-separated numbers, got {text!r} ({error})."
        ) from None
    if not values or not all(math.isfinite(v) for v in values):
        raise argparse.ArgumentTypeError(f"no finite values in {text!r}.")
    for value in values:
        walking_speed(repr(value))
    return values


def terrain_list(text: str) -> list[str]:
    """``sweep --terrain``: comma-separated built-in terrains (``profile-one,rolling``).

    Raises:
        argparse.ArgumentTypeError: An unknown terrain.
    """
    names = [name.strip() for name in text.split(",")]
    for name in names:
        terrain_spec(name)
    return names


def _existing_path(text: str) -> bool:
    """Whether ``text`` names an existing file or folder (False for anything unusable)."""
    try:
        path = Path(text).expanduser()
        return path.is_file() or path.is_dir()
    except (OSError, RuntimeError, ValueError):  # ~nosuchuser, a name too long, a NUL byte
        return False


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
    """An empty write to ``path``, appended (never truncated); a file it created is removed."""
    existed = path.exists()
    flags = os.O_WRONLY | os.O_APPEND | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0)
    descriptor = os.open(path, flags | (0 if existed else os.O_CREAT), 0o666)
    try:
        os.write(descriptor, b"")
    finally:
        os.close(descriptor)
        if not existed:  # through a dangling symbolic link, the file created is its target
            Path(os.path.realpath(path)).unlink(missing_ok=True)
