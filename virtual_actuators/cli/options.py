"""The command line's options: names, argparse types (each checks its value) and the parser."""

from __future__ import annotations

import argparse
import re
from collections.abc import Iterable

from .types import (
    MAX_DURATION,
    MIN_DURATION,
    amplitude,
    direction_degrees,
    figure_path,
    frame_list,
    output_path,
    positive_seconds,
    push_spec,
    robot_name,
    seed,
    seed_count,
    terrain_list,
    terrain_spec,
    time_window,
    value_range,
    walking_speed,
    wavelength,
    worker_count,
    yaw_rate,
)

#: The walks (``virtual_actuators.gaits.registry.WALKS``, named here so that ``--help`` imports
#: no simulation; tests/test_cli_usage checks the two agree).
WALK_DEMOS = ("turkey-walk", "flamingo-slopes", "hexapod-walk", "legged", "balance")
DEMOS = (*WALK_DEMOS, "stand")


def _options(destinations: str) -> tuple[tuple[str, str], ...]:
    """``(argparse destination, option)`` of each space-separated destination."""
    return tuple((dest, "--" + dest.replace("_", "-")) for dest in destinations.split())


#: Options of ``demo`` that only the walks use (argparse destination, option).
WALK_OPTIONS = _options(
    "duration speed force_speed terrain json plot realtime seed distribution window"
)

#: Options of ``demo`` that only some walks use: a walk takes those in its ``Walk.options``.
WALK_OWN_OPTIONS = _options(
    "direction yaw_rate path amplitude wavelength pendulum track robot feet gait push estimator"
)

#: Options of ``demo stand`` (also walk options of ``legged``); ``duration`` and ``json`` with
#: ``estimator`` only (the closed loop standing on the estimate).
STAND_OPTIONS = ("robot", "feet", "estimator", "duration", "json")


#: What ``python -m virtual_actuators --help`` says first.
DESCRIPTION = (
    "Virtual actuators on any URDF robot: walks and a standing robot (demo), the papers' "
    "worked examples (example), the robots by name (robots), walks over a grid (sweep)."
)

#: The seeds' worked examples (``virtual_actuators.examples.EXAMPLES``, imported only when run).
EXAMPLE_NAMES = ("hexapod-tripod", "millipede", "single-leg", "double-support")


def _viewer_arguments(parser: argparse.ArgumentParser, walks: bool = False) -> None:
    parser.add_argument(
        "--viz",
        action="store_true",
        help="show it live in MeshCat: prints the URL"
        + (", updates at 30 Hz wall clock" if walks else "")
        + ", then serves until Enter (at a terminal) or Ctrl-C",
    )
    parser.add_argument(
        "--record",
        type=output_path,
        metavar="PATH.html",
        help="write a standalone HTML page (a MeshCat animation of the whole run for walks, "
        "30 frames per simulated second)",
    )
    if walks:
        parser.add_argument(
            "--realtime",
            action="store_true",
            help="with --viz (only): slow the walk down to wall-clock time",
        )


def _hexapod_arguments(demo: argparse.ArgumentParser) -> None:
    demo.add_argument(
        "--direction",
        type=direction_degrees,
        metavar="DEG",
        help="hexapod-walk, legged: travel direction relative to the heading, degrees (90: crab "
        "left)",
    )
    demo.add_argument(
        "--yaw-rate",
        type=yaw_rate,
        metavar="RAD/S",
        help="hexapod-walk, legged: yaw rate; the velocity is fixed in the body frame, so the "
        "body traces a circle of radius speed / yaw rate",
    )
    demo.add_argument(
        "--gait",
        choices=("trot", "pace", "walk", "tripod"),
        help="legged: the pattern (default trot; tripod for six legs)",
    )
    demo.add_argument(
        "--push",
        type=push_spec,
        metavar="N@T[:DEG]",
        help="legged, balance: push the base with N newtons for 0.1 s from T seconds along DEG "
        "degrees in the ground plane (0 = +x, default 0; N < 0 pushes the other way)",
    )
    demo.add_argument(
        "--path",
        choices=("line", "sine"),
        help="hexapod-walk, legged: line (default) or sine: y = A sin(2 pi x / L) from the "
        "start, holding the initial heading",
    )
    demo.add_argument("--amplitude", type=amplitude, metavar="M", help="--path sine: A, m")
    demo.add_argument("--wavelength", type=wavelength, metavar="M", help="--path sine: L, m")
    demo.add_argument(
        "--pendulum",
        action="store_true",
        help="hexapod-walk: balance a 0.30 m, 0.18 kg pendulum on the back with an LQR",
    )
    demo.add_argument(
        "--track",
        action="store_true",
        help="hexapod-walk, legged: face an object circling the start while walking",
    )
    demo.add_argument(
        "--seed",
        type=seed,
        help="walks: a random start (the start-up push; the hexapod's initial disturbance)",
    )
    demo.add_argument(
        "--distribution",
        choices=("qp", "partitioned"),
        help="walks: how the body wrench is split over the support feet (default: qp for the "
        "hexapod, partitioned for the bipeds)",
    )
    demo.add_argument(
        "--window",
        type=time_window,
        metavar="T0:T1",
        help="walks with --plot: plot only simulated seconds T0 to T1 (either may be empty; "
        "checked against --duration before the run)",
    )


def _robot_arguments(demo: argparse.ArgumentParser) -> None:
    demo.add_argument(
        "--robot",
        type=robot_name,
        help="stand, legged, balance: a legged robot by name or URDF path (default: solo12; "
        "balance: talos; feet from its SRDF, frame names or structure, see the robots command)",
    )
    demo.add_argument(
        "--feet",
        type=frame_list,
        metavar="FRAME,FRAME,...",
        help="stand, legged: the foot frames (when the robot's own cannot be found)",
    )


def wants_viewer(args: argparse.Namespace) -> bool:
    """Whether the command asked for a viewer (``--viz`` or ``--record``)."""
    return bool(getattr(args, "viz", False) or getattr(args, "record", None))


def build_parser() -> tuple[argparse.ArgumentParser, dict[str, argparse.ArgumentParser]]:
    """The parser of ``python -m virtual_actuators`` and its subcommands' parsers by name.

    Returns:
        The top-level parser and ``{"demo": ..., "robots": ..., "example": ...}``.
    """
    from .. import __version__

    parser = argparse.ArgumentParser(prog="python -m virtual_actuators", description=DESCRIPTION)
    parser.add_argument("--version", action="version", version=f"virtual_actuators {__version__}")
    sub = parser.add_subparsers(dest="command")
    demo = sub.add_parser(
        "demo",
        help="run a demo (default: Spring Turkey walking in MuJoCo)",
        description="turkey-walk: Spring Turkey on level ground (VMC section 5); "
        "flamingo-slopes: Spring Flamingo blind over unknown slopes (VMC section 6); "
        "hexapod-walk: the 1996 hexapod's tripod gait on commanded paths, with a pendulum or "
        "tracking an object (VAC section 4); "
        "legged: any legged robot (--robot NAME_OR_URDF) trotting, pacing or walking; "
        "stand: a quadruped's body actuator and its force distribution; "
        "balance: any legged robot standing on the contact QP, pushed (--robot, --push).",
    )
    demo.add_argument("name", nargs="?", default="turkey-walk", choices=DEMOS)
    demo.add_argument(
        "--duration",
        type=positive_seconds,
        help=f"walks: simulated seconds, {MIN_DURATION:g} to {MAX_DURATION:g}",
    )
    demo.add_argument(
        "--speed",
        type=walking_speed,
        help="walks: desired speed [m/s], within the walk's supported range (see docs/cli.md)",
    )
    demo.add_argument(
        "--force-speed",
        action="store_true",
        help="walks: run a --speed outside the walk's supported range instead of refusing it",
    )
    demo.add_argument(
        "--terrain",
        type=terrain_spec,
        help="walks: 'flat', 'flat:HEIGHT', a built-in profile (profile-one, profile-two, "
        "rolling) or points 'x:z,x:z,...' in metres with increasing x",
    )
    demo.add_argument(
        "--json", type=output_path, metavar="PATH", help="walks: write the metrics as JSON"
    )
    demo.add_argument(
        "--plot", type=output_path, metavar="PATH", help="walks: save a PNG of the run"
    )
    demo.add_argument(
        "--estimator",
        action="store_true",
        help="legged, balance, stand, hexapod-walk: the controller reads only the simulated "
        "sensors (MEMS IMU, encoders) through the state estimator; the truth only scores it",
    )
    _hexapod_arguments(demo)
    demo.add_argument("--quiet", action="store_true", help="no progress bar")
    _robot_arguments(demo)
    _viewer_arguments(demo, walks=True)
    robots = sub.add_parser(
        "robots", help="list the robots load_robot accepts by name (kind, DoF, feet, aliases)"
    )
    example = sub.add_parser("example", help="run one of the seeds' worked examples")
    example.add_argument("name", choices=EXAMPLE_NAMES)
    _viewer_arguments(example)
    sweep = _sweep_parser(sub)
    return parser, {"demo": demo, "robots": robots, "example": example, "sweep": sweep}


def _sweep_parser(sub) -> argparse.ArgumentParser:
    sweep = sub.add_parser(
        "sweep",
        help="run a walk over a grid of speeds, terrains and seeds, in parallel",
        description="Every (speed, terrain, seed) walk of the grid, on a process pool (or Dask / "
        "Ray with --engine, e.g. on a cluster); prints the success rate per cell, writes the "
        "results table (--out, or beside --plot) and a success map (--plot).",
    )
    sweep.add_argument("walk", choices=WALK_DEMOS)
    sweep.add_argument("--speed", type=value_range, metavar="A:B:STEP", help="desired speeds")
    sweep.add_argument("--terrain", type=terrain_list, metavar="T1,T2", help="terrains")
    sweep.add_argument("--seeds", type=seed_count, default=3, help="starts per cell (1 to 1000)")
    sweep.add_argument("--duration", type=positive_seconds, help="simulated seconds per walk")
    sweep.add_argument("--engine", choices=("process", "dask", "ray"), default="process")
    sweep.add_argument("--workers", type=worker_count, help="process pool size (1 to 256)")
    sweep.add_argument(
        "--out",
        type=output_path,
        metavar="PATH",
        help="write the results table, .csv or .json (default: beside --plot, else not written)",
    )
    sweep.add_argument("--plot", type=figure_path, metavar="PATH.png", help="success map")
    sweep.add_argument("--quiet", action="store_true", help="no progress bar")
    return sweep


#: A value that starts like a negative number (``-10@1``, ``-.5``), which argparse reads as an
#: option (no option starts so).
_MINUS_VALUE = re.compile(r"-[\d.]")


def attach_values(arguments: list[str], parsers: Iterable[argparse.ArgumentParser]) -> list[str]:
    """``--push -10@1`` as ``--push=-10@1``: the value of an option that takes one, minus and all.

    Args:
        arguments: The command line's words.
        parsers: The parsers whose options are looked up.

    Returns:
        The words, each such option joined to its value.
    """
    valued = {
        option
        for parser in parsers
        for action in parser._actions  # argparse's own list of the options
        if action.nargs is None and action.option_strings
        for option in action.option_strings
    }
    joined: list[str] = []
    for word in arguments:
        if joined and joined[-1] in valued and _MINUS_VALUE.match(word):
            joined[-1] = f"{joined[-1]}={word}"
        else:
            joined.append(word)
    return joined
