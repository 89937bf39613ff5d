"""Command line: ``python -m virtual_actuators demo`` and friends."""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import sys
import time
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .examples import Example
    from .robots.robot import Robot


def _joint_table(robot, tau: np.ndarray, limp: Sequence[str] = ()) -> str:
    model = robot.model
    lines = [f"{'joint':<16}{'effort [N m]':>14}"]
    for j in range(1, model.njoints):
        joint = model.joints[j]
        if joint.shortname() == "JointModelFreeFlyer":
            continue
        for k in range(joint.nv):
            name = model.names[j] + (f"[{k}]" if joint.nv > 1 else "")
            note = "  (limp)" if model.names[j] in limp else ""
            lines.append(f"{name:<16}{tau[joint.idx_v + k]:>14.4f}{note}")
    return "\n".join(lines)


def _print_solution(title: str, robot, body, q, wrench, sol) -> None:
    print(f"\n== {title}")
    sizes = body.sizes()
    print(
        f"n={sizes['n']} p={sizes['p']} natural constraints={sizes['l_total']} "
        f"free entries={sizes['d_total']} redundancy r={sizes['r']} design={sizes['design']}"
    )
    print(f"method: {sol.method}   residual: {sol.residual:.2e}")
    for key in ("MFS", "RFS", "CFS"):
        labels = ", ".join(f"{r}.{a}" for r, a in sol.sets[key])
        print(f"{key} ({len(sol.sets[key])}): {labels}")
    print("\nforces on the body, per chain [N, N m]:")
    print(sol.table())
    print("\njoint efforts:")
    print(_joint_table(robot, sol.tau))


def stand_robot(name: str = "solo12") -> Robot:
    """Load the quadruped of ``demo stand`` and check that it has the frames the demo needs.

    Args:
        name: A robot name or URDF path for :func:`~virtual_actuators.load_robot`.

    Returns:
        The :class:`~virtual_actuators.Robot`.

    Raises:
        RobotNotFoundError: If no robot has this name or path.
        RobotDescriptionError: If its URDF cannot be loaded.
        FrameNotFoundError: If the robot lacks ``base_link`` or one of the frames ``FL_FOOT``,
            ``FR_FOOT``, ``HL_FOOT``, ``HR_FOOT`` (it is not a quadruped like solo12).
    """
    import virtual_actuators as va

    robot = va.load_robot(name)
    needed = ("base_link", *STAND_FEET)
    missing = [frame for frame in needed if not robot.model.existFrame(frame)]
    if missing:
        raise va.FrameNotFoundError(
            f"robot {name!r} has no frame {', '.join(missing)}: the stand demo needs a "
            f"quadruped with the frames {', '.join(needed)}, such as 'solo12' or 'solo'."
        )
    return robot


def demo_stand(
    robot: str | os.PathLike[str] | Robot = "solo12",
    repeat: int = 2000,
    args: argparse.Namespace | None = None,
) -> None:
    """Load a quadruped, declare a body actuator on its four feet, print the distribution.

    With ``args.viz`` / ``args.record``, also show it in MeshCat / write it as HTML.

    Args:
        robot: A robot loaded by :func:`stand_robot`, or a name or path to load with it.
        repeat: Solves per timing.
        args: The parsed command line (for the viewer options), or None.

    Raises:
        RobotNotFoundError: If ``robot`` is a name that no robot has.
        RobotDescriptionError: If its URDF cannot be loaded.
        FrameNotFoundError: If it is not a quadruped with the frames of :func:`stand_robot`.
    """
    import virtual_actuators as va

    if isinstance(robot, (str, os.PathLike)):
        robot = stand_robot(os.fspath(robot))
    q = robot.neutral()
    feet = list(STAND_FEET)
    mass = sum(inertia.mass for inertia in robot.model.inertias)
    weight = mass * 9.81
    print(f"{robot}  mass {mass:.2f} kg, standing pose from its SRDF")
    body = va.ParallelVirtualActuator(
        robot, action="base_link", reactions=feet, reference="base_link", contact="point"
    )
    wrench = np.array([2.0, 0.0, weight, 0.1, -0.2, 0.05])
    sol = body.solve(q, wrench)
    _print_solution(
        "body actuator, no design constraint (minimum-norm distribution)",
        robot,
        body,
        q,
        wrench,
        sol,
    )
    # all x forces equal, y forces equal front and hind, diagonal z sums equal: r = 6
    design = [
        va.Equal((feet[0], "x"), (feet[1], "x")),
        va.Equal((feet[0], "x"), (feet[2], "x")),
        va.Equal((feet[0], "x"), (feet[3], "x")),
        va.Equal((feet[0], "y"), (feet[1], "y")),
        va.Equal((feet[2], "y"), (feet[3], "y")),
        va.Linear({(feet[0], "z"): 1, (feet[3], "z"): 1, (feet[1], "z"): -1, (feet[2], "z"): -1}),
    ]
    square = va.ParallelVirtualActuator(
        robot, action="base_link", reactions=feet, reference="base_link", design=design
    )
    sol2 = square.solve(q, wrench)
    _print_solution(
        "with six design constraints (square, partitioned)", robot, square, q, wrench, sol2
    )
    for name, actuator in (("minimum-norm", body), ("partitioned", square)):
        start = time.perf_counter()
        for _ in range(repeat):
            actuator.solve(q, wrench)
        elapsed = (time.perf_counter() - start) / repeat * 1e6
        print(f"\nsolve time ({name}): {elapsed:.1f} us per call (median of one run)")
    if args is not None:
        _show_static(args, robot, q, sol2, square, wrench)


def _wants_viewer(args: argparse.Namespace) -> bool:
    return bool(getattr(args, "viz", False) or getattr(args, "record", None))


def _nice_scale(force: float, length: float) -> float:
    """Arrow scale [m/N] drawing ``force`` about ``length`` long, at a round N per metre."""
    per_metre = max(force, 1e-9) / max(length, 1e-3)
    exponent = 10.0 ** np.floor(np.log10(per_metre))
    step = next(m for m in (1.0, 2.0, 5.0, 10.0) if m * exponent >= per_metre)
    return 1.0 / (step * exponent)


def _robot_extent(robot, q: np.ndarray) -> float:
    import pinocchio as pin

    data = pin.Data(robot.model)
    pin.framesForwardKinematics(robot.model, data, q)
    points = np.array([f.translation for f in data.oMf])
    return max(0.3, float(np.linalg.norm(points.max(axis=0) - points.min(axis=0))))


def _make_viewer(args: argparse.Namespace, robot, **options):
    """A live viewer (``--viz``) or an offline one for ``--record`` only, or None."""
    if not _wants_viewer(args):
        return None
    from .viz import OfflineWindow, Viewer

    window = None if args.viz else OfflineWindow()
    return Viewer(robot, window=window, **options)


def _pause(message: str) -> None:
    """Wait for Enter when a person is at the terminal; return at once in scripts."""
    if sys.stdin is not None and sys.stdin.isatty():
        try:
            input(message)
        except EOFError:
            pass


def _finish_viewer(args: argparse.Namespace, viewer) -> None:
    if args.record:
        print(f"recording: {viewer.save_html(args.record)}")
    if args.viz:
        viewer.flush()
        print(f"viewer: {viewer.url}")
        _pause("Press Enter to stop the viewer. ")
    viewer.close()


def _show_static(args: argparse.Namespace, robot, q, solution, actuator, wrench) -> None:
    """Show one configuration with an actuator's distribution (``--viz`` / ``--record``)."""
    if not _wants_viewer(args):
        return
    force = float(
        np.linalg.norm(
            solution.forces[
                :, [i for i, a in enumerate(solution.axes) if a in ("x", "y", "z")]
            ].sum(axis=0)
        )
    )
    extent = _robot_extent(robot, q)
    viewer = _make_viewer(args, robot, force_scale=_nice_scale(force, 0.6 * extent))
    viewer.show(q, solution, actuator=actuator)
    _finish_viewer(args, viewer)


def demo_walk(args: argparse.Namespace) -> int:
    """Run one of the seeds' walks in MuJoCo, print its metrics, write JSON and a plot."""
    from .demos import WALKS, run_walk
    from .experiments.metrics import write_json
    from .experiments.plots import plot_walk
    from .robots.loader import load_robot

    viewer = on_tick = None
    if _wants_viewer(args):
        viewer = _make_viewer(args, load_robot(WALKS[args.name].robot), force_scale=1 / 250)
        if args.record:
            viewer.start_recording(fps=30.0)
        if args.viz:
            _pause("Open the viewer, then press Enter to start. ")
        on_tick = viewer.tick_callback(realtime=args.realtime)
    result = run_walk(
        args.name,
        duration=args.duration,
        speed=args.speed,
        terrain=args.terrain,
        progress=not args.quiet,
        on_tick=on_tick,
    )
    metrics = result.metrics
    print(metrics.summary())
    if args.json:
        print(f"metrics: {write_json(metrics, args.json)}")
    if args.plot:
        title = f"{args.name}: {result.log.metadata['robot']} on {result.log.metadata['terrain']}"
        heights = result.log.terrain_points[:, 1]
        layout = "time" if np.ptp(heights) == 0.0 else "terrain"  # Fig. 9 vs Fig. 15
        path = plot_walk(result.log, args.plot, title=title, metrics=metrics, layout=layout)
        print(f"plot: {path}")
    if viewer is not None:
        _finish_viewer(args, viewer)
    return 1 if metrics.fell else 0


DEMOS = ("turkey-walk", "flamingo-slopes", "stand")
WALK_DEMOS = ("turkey-walk", "flamingo-slopes")

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

#: The seeds' worked examples (``virtual_actuators.examples.EXAMPLES``, imported only when run).
EXAMPLE_NAMES = ("hexapod-tripod", "millipede", "single-leg", "double-support")


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


def example_view(args: argparse.Namespace, example: Example) -> None:
    """Show an example's configuration and solution (``--viz`` / ``--record``).

    The example's robot, actuator, configuration and solution are drawn as they are.
    """
    if not _wants_viewer(args):
        return
    solution = example.solution
    _show_static(args, example.robot, example.q, solution, example.actuator, solution.requested)


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


def walking_speed(text: str) -> float:
    """``--speed``: a desired speed in (0, 1.5] m/s.

    Raises:
        argparse.ArgumentTypeError: Otherwise.
    """
    value = _number(text, "speed")
    if not 0.0 < value <= 1.5:
        raise argparse.ArgumentTypeError(f"speed must be in (0, 1.5] m/s, got {text!r}")
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
    from .exceptions import VirtualActuatorError
    from .simulation.terrain import Terrain

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
    from .exceptions import suggestion
    from .robots.loader import list_robots

    names = list_robots()
    path = Path(text).expanduser()
    if text in names or path.is_file() or path.is_dir():
        return text
    raise argparse.ArgumentTypeError(
        f"no robot named {text!r} and no such URDF file. {suggestion(text, names, 'robots')}"
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


class _OptionError(Exception):
    """A command-line value that turned out unusable at run time (reported as a usage error)."""


@contextlib.contextmanager
def _blame(option: str) -> Iterator[None]:
    """Turn a library error raised in the block into an :class:`_OptionError` naming ``option``.

    Raises:
        _OptionError: If the block raises a :class:`~virtual_actuators.VirtualActuatorError`.
    """
    from .exceptions import VirtualActuatorError

    try:
        yield
    except VirtualActuatorError as error:
        raise _OptionError(f"argument {option}: {error}") from error


def build_parser() -> tuple[argparse.ArgumentParser, dict[str, argparse.ArgumentParser]]:
    """The parser of ``python -m virtual_actuators`` and its subcommands' parsers by name.

    Every option has an argparse ``type`` that checks its value (so a bad one is a usage error);
    the types import nothing heavy until their option is given.

    Returns:
        The top-level parser and ``{"demo": ..., "robots": ..., "example": ...}``.
    """
    parser = argparse.ArgumentParser(prog="python -m virtual_actuators", description=__doc__)
    sub = parser.add_subparsers(dest="command")
    demo = sub.add_parser(
        "demo",
        help="run a demo (default: Spring Turkey walking in MuJoCo)",
        description="turkey-walk: Spring Turkey on level ground (VMC section 5); "
        "flamingo-slopes: Spring Flamingo blind over unknown slopes (VMC section 6); "
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


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``python -m virtual_actuators``.

    Every option is checked by its argparse type: a bad value prints the usage line and the
    reason, with exit code 2. An option that the chosen demo does not use is a usage error too.
    Errors of the library raised at run time (a :class:`~virtual_actuators.VirtualActuatorError`,
    caused by the values given) are reported the same way, naming the option when it is known;
    any other exception is a bug and propagates.

    Args:
        argv: The arguments (default: ``sys.argv[1:]``); none, or options first, means
            ``demo`` (with those options).

    Returns:
        The exit code: 0, or 1 when a walk ends with the robot fallen.

    Raises:
        SystemExit: With code 2 (and argparse's usage message on stderr) for a bad argument, or
            with code 0 for ``--help``.
    """
    parser, subparsers = build_parser()
    arguments = list(sys.argv[1:] if argv is None else argv)
    if not arguments or (arguments[0].startswith("-") and arguments[0] not in ("-h", "--help")):
        arguments.insert(0, "demo")  # the default command, with its options
    args = parser.parse_args(arguments)
    command_parser = subparsers.get(args.command, parser)
    if args.command == "demo":
        _check_demo_options(args, command_parser)
    from .exceptions import VirtualActuatorError

    try:
        return _run(args)
    except _OptionError as error:  # a value that only failed when used: a usage error, exit 2
        command_parser.error(str(error))
    except VirtualActuatorError as error:  # caused by the arguments: a usage error, exit 2
        command_parser.error(str(error))
    return 2  # (error() exits)


def _check_demo_options(args: argparse.Namespace, parser: argparse.ArgumentParser) -> None:
    """Refuse options that the chosen demo would ignore (a usage error, exit 2)."""
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


def _run(args: argparse.Namespace) -> int:
    if args.command == "demo":
        if args.name == "stand":
            with _blame("--robot"):
                robot = stand_robot(args.robot or "solo12")
            demo_stand(robot, args=args)
            return 0
        return demo_walk(args)
    if args.command == "example":
        from .examples import EXAMPLES

        example_view(args, EXAMPLES[args.name]())
    elif args.command == "robots":
        import virtual_actuators as va

        print("\n".join(va.list_robots()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
