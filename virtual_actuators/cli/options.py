"""The command line's options: names, bounds, argparse types and the parser.

Every option has an argparse ``type`` that checks its value, so a bad one is a usage error (exit
code 2, the usage line and the reason), never a traceback; the types import nothing heavy until
their option is given.
"""

from __future__ import annotations

import argparse
import math
import os
from pathlib import Path

DEMOS = ("turkey-walk", "flamingo-slopes", "hexapod-walk", "stand")
WALK_DEMOS = ("turkey-walk", "flamingo-slopes", "hexapod-walk")

#: The frames that ``demo stand`` puts its body actuator on.
STAND_FEET = ("FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT")

#: Bounds of ``--duration`` [s]: a run needs a few 1 ms control ticks, and its log holds every
#: tick in memory (and the simulation runs at about real time).
MIN_DURATION = 0.01
MAX_DURATION = 600.0

#: ``--terrain`` points must lie within this many metres of the origin (x and z).
MAX_TERRAIN_EXTENT = 1000.0

#: Options of ``demo`` that only the walks use (argparse destination, option).
WALK_OPTIONS = (
    ("duration", "--duration"),
    ("speed", "--speed"),
    ("terrain", "--terrain"),
    ("json", "--json"),
    ("plot", "--plot"),
    ("realtime", "--realtime"),
)

#: Options of ``demo`` that only ``hexapod-walk`` uses (argparse destination, option).
HEXAPOD_OPTIONS = (
    ("direction", "--direction"),
    ("yaw_rate", "--yaw-rate"),
    ("path", "--path"),
    ("amplitude", "--amplitude"),
    ("wavelength", "--wavelength"),
    ("pendulum", "--pendulum"),
    ("track", "--track"),
    ("seed", "--seed"),
    ("distribution", "--distribution"),
)

#: Bounds of ``--yaw-rate`` [rad/s] and ``--amplitude`` / ``--wavelength`` [m].
MAX_YAW_RATE = 3.0
MAX_AMPLITUDE = 2.0
MAX_WAVELENGTH = 50.0

#: What ``python -m virtual_actuators --help`` says first.
DESCRIPTION = "Command line: ``python -m virtual_actuators demo`` and friends."

#: The seeds' worked examples (``virtual_actuators.examples.EXAMPLES``, imported only when run).
EXAMPLE_NAMES = ("hexapod-tripod", "millipede", "single-leg", "double-support")


# -- argument types: a bad value is a usage error (exit 2), never a traceback ---------------------


def _number(text: str, what: str) -> float:
    """A finite float from ``text``.

    Raises:
        argparse.ArgumentTypeError: If ``text`` is not a number, or is NaN or infinite.
    """
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{what} must be a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"{what} must be a finite number, got {text!r}")
    return value


def positive_seconds(text: str) -> float:
    """``--duration``: a finite number of seconds in [:data:`MIN_DURATION`, :data:`MAX_DURATION`].

    Raises:
        argparse.ArgumentTypeError: Otherwise (argparse turns it into a usage error).
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
    """A finite number in ``[low, high]`` (``(low, high]`` with ``open_low``), or a usage error.

    Raises:
        argparse.ArgumentTypeError: Otherwise.
    """
    value = _number(text, what)
    if not ((low < value if open_low else low <= value) and value <= high):
        bracket = "(" if open_low else "["
        raise argparse.ArgumentTypeError(
            f"{what} must be in {bracket}{low:g}, {high:g}] {unit}, got {text!r}"
        )
    return value


def walking_speed(text: str) -> float:
    """``--speed``: a desired speed in (0, 1.5] m/s.

    Raises:
        argparse.ArgumentTypeError: Otherwise.
    """
    return _in_range(text, "speed", 0.0, 1.5, "m/s", open_low=True)


def direction_degrees(text: str) -> float:
    """``--direction``: the travel direction relative to the heading, in degrees (-360 to 360).

    Raises:
        argparse.ArgumentTypeError: Otherwise.
    """
    return _in_range(text, "direction", -360.0, 360.0, "degrees")


def yaw_rate(text: str) -> float:
    """``--yaw-rate``: rad/s within +-:data:`MAX_YAW_RATE`.

    Raises:
        argparse.ArgumentTypeError: Otherwise.
    """
    return _in_range(text, "yaw rate", -MAX_YAW_RATE, MAX_YAW_RATE, "rad/s")


def amplitude(text: str) -> float:
    """``--amplitude``: the sine's amplitude in [0, :data:`MAX_AMPLITUDE`] m.

    Raises:
        argparse.ArgumentTypeError: Otherwise.
    """
    return _in_range(text, "amplitude", 0.0, MAX_AMPLITUDE, "m")


def wavelength(text: str) -> float:
    """``--wavelength``: the sine's wavelength in (0, :data:`MAX_WAVELENGTH`] m.

    Raises:
        argparse.ArgumentTypeError: Otherwise.
    """
    return _in_range(text, "wavelength", 0.0, MAX_WAVELENGTH, "m", open_low=True)


def seed(text: str) -> int:
    """``--seed``: a non-negative integer.

    Raises:
        argparse.ArgumentTypeError: Otherwise.
    """
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"seed must be an integer, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"seed must be >= 0, got {text!r}")
    return value


def terrain_spec(text: str) -> str:
    """``--terrain``: a spec :meth:`Terrain.parse` accepts (checked now, parsed again later).

    Its points must also lie within :data:`MAX_TERRAIN_EXTENT` metres of the origin. The terrain
    module is imported here, only when the option is given (it brings in MuJoCo, which the
    walks need anyway).

    Raises:
        argparse.ArgumentTypeError: If the spec does not parse (with the parser's reason) or a
            point lies too far away.
    """
    from ..exceptions import VirtualActuatorError
    from ..simulation.terrain import Terrain

    try:
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

    Whether the robot suits the demo (stand needs a quadruped) is checked when it is loaded.

    Raises:
        argparse.ArgumentTypeError: Otherwise (with the closest names).
    """
    from ..robots.catalog import list_robots, suggest_robots

    names = list_robots(include_aliases=True)
    path = Path(text).expanduser()
    if text in names or path.is_file() or path.is_dir():
        return text
    raise argparse.ArgumentTypeError(
        f"no robot named {text!r} and no such URDF file. {suggest_robots(text)}"
    )


def output_path(text: str) -> str:
    """An output file in an existing, writable folder (checked before a run, not after it).

    Raises:
        argparse.ArgumentTypeError: If the path is empty or a folder, its folder does not
            exist, or it cannot be written.
    """
    path = Path(text)
    if not text.strip():
        raise argparse.ArgumentTypeError("expected a file path, got an empty string")
    if path.is_dir():
        raise argparse.ArgumentTypeError(f"{text!r} is a folder; give a file path in it")
    if not path.parent.is_dir():
        raise argparse.ArgumentTypeError(
            f"{text!r} is not a file path in an existing folder (no folder {str(path.parent)!r})"
        )
    if not os.access(path if path.exists() else path.parent, os.W_OK):
        raise argparse.ArgumentTypeError(f"{text!r} cannot be written (permission denied)")
    return text


def _viewer_arguments(parser: argparse.ArgumentParser, walks: bool = False) -> None:
    parser.add_argument(
        "--viz",
        action="store_true",
        help="show it live in MeshCat (prints the URL"
        + ("; walks update at 30 Hz wall clock)" if walks else ")"),
    )
    parser.add_argument(
        "--record",
        type=output_path,
        default=None,
        metavar="PATH.html",
        help="write a standalone HTML page (a MeshCat animation of the whole run for walks, "
        "30 frames per simulated second)",
    )
    if walks:
        parser.add_argument(
            "--realtime",
            action="store_true",
            help="with --viz, slow the simulation down to wall-clock time",
        )


def _hexapod_arguments(demo: argparse.ArgumentParser) -> None:
    hexapod = "hexapod-walk: "
    demo.add_argument(
        "--direction",
        type=direction_degrees,
        default=None,
        metavar="DEG",
        help=hexapod + "travel direction relative to the heading, degrees (90: crab left)",
    )
    demo.add_argument(
        "--yaw-rate",
        type=yaw_rate,
        default=None,
        metavar="RAD/S",
        help=hexapod + "yaw rate; the velocity is fixed in the body frame, so the body traces "
        "a circle of radius speed / yaw rate",
    )
    demo.add_argument(
        "--path",
        choices=("line", "sine"),
        default=None,
        help=hexapod + "line (default) or sine: y = A sin(2 pi x / L) from the start, "
        "holding the initial heading",
    )
    demo.add_argument(
        "--amplitude", type=amplitude, default=None, metavar="M", help=hexapod + "sine A, m"
    )
    demo.add_argument(
        "--wavelength", type=wavelength, default=None, metavar="M", help=hexapod + "sine L, m"
    )
    demo.add_argument(
        "--pendulum",
        action="store_true",
        help=hexapod + "balance a 0.30 m, 0.18 kg pendulum on the back with an LQR",
    )
    demo.add_argument(
        "--track",
        action="store_true",
        help=hexapod + "face an object circling the start while walking",
    )
    demo.add_argument(
        "--seed", type=seed, default=None, help=hexapod + "random initial disturbance"
    )
    demo.add_argument(
        "--distribution",
        choices=("qp", "partitioned"),
        default=None,
        help=hexapod + "how the body wrench is split over the support feet (default qp)",
    )


def build_parser() -> tuple[argparse.ArgumentParser, dict[str, argparse.ArgumentParser]]:
    """The parser of ``python -m virtual_actuators`` and its subcommands' parsers by name.

    Every option has an argparse ``type`` that checks its value (so a bad one is a usage error);
    the types import nothing heavy until their option is given.

    Returns:
        The top-level parser and ``{"demo": ..., "robots": ..., "example": ...}``.
    """
    parser = argparse.ArgumentParser(prog="python -m virtual_actuators", description=DESCRIPTION)
    sub = parser.add_subparsers(dest="command")
    demo = sub.add_parser(
        "demo",
        help="run a demo (default: Spring Turkey walking in MuJoCo)",
        description="turkey-walk: Spring Turkey on level ground (VMC section 5); "
        "flamingo-slopes: Spring Flamingo blind over unknown slopes (VMC section 6); "
        "hexapod-walk: the 1996 hexapod's tripod gait on commanded paths, with a pendulum or "
        "tracking an object (VAC section 4); "
        "stand: a quadruped's body actuator and its force distribution.",
    )
    demo.add_argument("name", nargs="?", default="turkey-walk", choices=DEMOS)
    demo.add_argument(
        "--duration",
        type=positive_seconds,
        default=None,
        help=f"walks: simulated seconds, {MIN_DURATION:g} to {MAX_DURATION:g}",
    )
    demo.add_argument(
        "--speed", type=walking_speed, default=None, help="walks: desired speed, (0, 1.5] m/s"
    )
    demo.add_argument(
        "--terrain",
        type=terrain_spec,
        default=None,
        help="walks: 'flat', 'flat:HEIGHT', a built-in profile (profile-one, profile-two, "
        "rolling) or points 'x:z,x:z,...' in metres with increasing x",
    )
    demo.add_argument(
        "--json",
        type=output_path,
        default=None,
        metavar="PATH",
        help="walks: write the metrics as JSON",
    )
    demo.add_argument(
        "--plot",
        type=output_path,
        default=None,
        metavar="PATH",
        help="walks: save a PNG of the run",
    )
    _hexapod_arguments(demo)
    demo.add_argument("--quiet", action="store_true", help="no progress bar")
    demo.add_argument(
        "--robot",
        type=robot_name,
        default=None,
        help="stand: a quadruped with base_link and FL/FR/HL/HR_FOOT frames (default: solo12)",
    )
    _viewer_arguments(demo, walks=True)
    robots = sub.add_parser("robots", help="list the robots load_robot accepts by name")
    example = sub.add_parser("example", help="run one of the seeds' worked examples")
    example.add_argument("name", choices=EXAMPLE_NAMES)
    _viewer_arguments(example)
    return parser, {"demo": demo, "robots": robots, "example": example}


def check_demo_options(args: argparse.Namespace, parser: argparse.ArgumentParser) -> None:
    """Refuse options that the chosen demo would ignore (a usage error, exit 2)."""
    if args.name != "hexapod-walk":
        for dest, option in HEXAPOD_OPTIONS:
            if getattr(args, dest) not in (None, False):
                parser.error(f"argument {option}: only hexapod-walk uses it, not {args.name}")
    elif args.path != "sine" and (args.amplitude is not None or args.wavelength is not None):
        parser.error("argument --amplitude/--wavelength: only --path sine uses them")
    if args.name == "stand":
        for dest, option in WALK_OPTIONS:
            if getattr(args, dest) not in (None, False):
                parser.error(
                    f"argument {option}: only the walks ({', '.join(WALK_DEMOS)}) use it, not stand"
                )
    elif args.robot is not None:
        parser.error(
            f"argument --robot: only the stand demo uses it; {args.name} has its own robot"
        )
