"""What the command line runs: the demos, the worked examples, the viewer around them."""

from __future__ import annotations

import argparse
import contextlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..examples import Example

from .usage_errors import OptionError, blame, writing
from .views import finish_viewer, make_viewer, pause, show_static, wants_viewer


def demo_walk(args: argparse.Namespace) -> int:
    """Run one of the walks in MuJoCo, print its figures, write JSON and a plot."""
    from ..demos import WALKS, run_walk
    from ..exceptions import FrameNotFoundError, GaitPatternError
    from ..experiments.metrics import write_json
    from ..models.loader import load_robot

    walk = WALKS[args.name]
    options = walk_options(args, walk.options)
    if "robot" in walk.options:
        legged_robot(args, walk.robot)  # a robot that cannot walk: a usage error, before the run
    viewer = on_tick = None
    if wants_viewer(args):
        robot = (walk.viewer_robot or (lambda **_: load_robot(walk.robot)))(**options)
        viewer = make_viewer(args, robot, force_scale=walk.force_scale)
        if args.record:
            viewer.start_recording(fps=30.0)
        if args.viz:
            pause("Open the viewer, then press Enter to start. ")
        on_tick = viewer.tick_callback(realtime=args.realtime)
    feet = blame("--feet", only=FrameNotFoundError) if args.feet else contextlib.nullcontext()
    with feet, blame("--gait", only=GaitPatternError):
        result = run_walk(
            args.name,
            duration=args.duration,
            speed=args.speed,
            terrain=args.terrain,
            progress=not args.quiet,
            on_tick=on_tick,
            seed=args.seed,
            distribution=args.distribution,
            force_speed=args.force_speed,  # checked against the walk's range with the options
            **options,
        )
    metrics = result.metrics
    print(metrics.summary())
    if args.json:
        data = result.to_json()
        label = "trace" if "trace" in data else "metrics"
        with writing("--json", args.json):
            path = write_json(data, args.json)
        print(f"{label}: {path}")
    if args.plot:
        with writing("--plot", args.plot):
            path = walk.plot(result, args.plot, args.window)
        print(f"plot: {path}")
    if viewer is not None:
        finish_viewer(args, viewer)
    return 1 if metrics.fell else 0


def legged_robot(args: argparse.Namespace, default: str):
    """The legged robot of ``--robot`` (else ``default``), its body and feet (``--feet`` or found).

    Returns:
        ``(robot, body frame, foot frames)``.

    Raises:
        OptionError: ``--robot`` names no robot, a description that cannot be loaded, a robot
            with no feet or with a fixed base; or a frame of ``--feet`` is not in the robot.
    """
    from ..exceptions import RobotDescriptionError, RobotNotFoundError
    from .stand import stand_robot

    feet = getattr(args, "feet", None)
    described = (RobotNotFoundError, RobotDescriptionError)
    with blame("--feet" if feet else "--robot"), blame("--robot", only=described):
        loaded = stand_robot(default if args.robot is None else args.robot, feet)
    robot = loaded[0]
    if not robot.floating_base:
        raise OptionError(
            f"argument --robot: robot {robot.name!r} has a fixed base: {args.name} needs a "
            "legged robot, whose base floats (the robots command lists them)"
        )
    return loaded


def walk_options(args: argparse.Namespace, names: tuple[str, ...]) -> dict[str, object]:
    """The walk's own options that were given (``--direction`` in degrees becomes radians)."""
    import math

    options = {name: getattr(args, name) for name in names}
    options = {name: value for name, value in options.items() if value not in (None, False)}
    if "direction" in options:
        options["direction"] = math.radians(options["direction"])
    return options


def sweep_command(args: argparse.Namespace) -> int:
    """Run the grid, print a per-cell table, write the results (and the success map).

    Returns:
        0, or 1 when any walk fell.

    Raises:
        VirtualActuatorError: A bad grid, or a missing engine (Dask, Ray).
    """
    from ..demos import WALKS
    from ..demos.sweep import grid, plot_success_map, run_sweep, success_map, write_results
    from ..experiments.progress import Progress

    spec = WALKS[args.walk]
    speeds = args.speed or [0.4]
    terrains = args.terrain or [spec.terrain]
    with blame("--speed/--terrain/--seeds"):
        cases = grid(args.walk, speeds, terrains, args.seeds, duration=args.duration)
    print(
        f"{len(cases)} walks of {args.walk}: speeds {speeds}, terrains {terrains}, "
        f"{args.seeds} seeds, engine {args.engine}"
    )
    bar = None if args.quiet else Progress(len(cases), unit="walks", description=args.walk)
    done = []

    def arrived(result) -> None:
        done.append(result)
        if bar is not None:
            bar.set(len(done))

    try:
        results = run_sweep(cases, engine=args.engine, workers=args.workers, on_result=arrived)
    finally:
        if bar is not None:
            bar.close()
    speeds_, terrains_, rate = success_map(results)
    width = max(len(t) for t in terrains_)
    print(f"{'':{width}}  " + " ".join(f"{s:>6g}" for s in speeds_) + "   (speed [m/s])")
    for i, terrain in enumerate(terrains_):
        cells = " ".join(f"{value:>6.0%}" if value == value else "     -" for value in rate[i])
        print(f"{terrain:{width}}  {cells}")
    out, option = results_path(args)
    if out is None:
        print("results: not written (--out PATH.csv or PATH.json writes them)")
    else:
        with writing(option, out):
            path = write_results(results, out)
        print(f"results: {path}" + ("" if args.out else " (beside the plot; --out sets it)"))
    if args.plot:
        with writing("--plot", args.plot):
            path = plot_success_map(results, args.plot)
        print(f"success map: {path}")
    errors = [r for r in results if r.error]
    for result in errors[:5]:
        print(f"error at speed {result.speed} on {result.terrain}: {result.error}")
    return 1 if any(r.fell for r in results) else 0


def results_path(args: argparse.Namespace) -> tuple[str | None, str]:
    """Where ``sweep`` writes its results: ``--out``, else a ``.csv`` beside ``--plot``, else None.

    Returns:
        ``(path or None, "--out" or "--plot")``.
    """
    if args.out:
        return args.out, "--out"
    if args.plot:
        from pathlib import Path

        return str(Path(args.plot).with_suffix(".csv")), "--plot"
    return None, "--out"


def check_results_path(args: argparse.Namespace, parser: argparse.ArgumentParser) -> None:
    """Try the results table beside ``--plot`` now, as ``--out`` is tried when parsed.

    Raises:
        SystemExit: With code 2 when it cannot be written (names the path and the reason).
    """
    from .paths import output_path

    out, option = results_path(args)
    if out is not None and option == "--plot":
        try:
            output_path(out)
        except argparse.ArgumentTypeError as error:
            parser.error(f"argument --plot: the results table beside it: {error}")


def example_view(args: argparse.Namespace, example: Example) -> None:
    """Show an example's configuration and solution (``--viz`` / ``--record``)."""
    if not wants_viewer(args):
        return
    solution = example.solution
    show_static(args, example.robot, example.q, solution, example.actuator, solution.requested)


def run(args: argparse.Namespace) -> int:
    """Run the parsed command; returns the exit code (1: a walk ended with the robot fallen).

    Raises:
        OptionError: A value that only failed when used (names its option).
        VirtualActuatorError: A library error caused by the arguments.
    """
    if args.command == "demo":
        if args.name == "stand":
            from .stand import demo_stand

            demo_stand(legged_robot(args, "solo12"), args=args)
            return 0
        return demo_walk(args)
    if args.command == "example":
        from ..examples import EXAMPLES

        example_view(args, EXAMPLES[args.name]())
    elif args.command == "sweep":
        return sweep_command(args)
    elif args.command == "robots":
        from ..models.directory import describe_robots, robot_table

        print(robot_table(describe_robots()))
    return 0
