"""What the command line runs: the demos, the worked examples, the viewer around them.

``demo stand``: any legged robot standing, its body actuator and force distribution. Feet come
from `find_feet` or ``--feet``: three or more are point contacts, two (a biped) flat ones; the
robot stands in its `standing_pose`.
"""

from __future__ import annotations

import argparse
import contextlib
import itertools
import math
import time

import numpy as np

from .options import wants_viewer
from .usage_errors import OptionError, blame, writing
from .views import finish_viewer, make_viewer, pause, print_solution, show_static

#: Solves per timing of ``demo stand``.
STAND_SOLVES = 2000


def demo_walk(args: argparse.Namespace) -> int:
    """Run one of the walks in MuJoCo, print its figures, write JSON and a plot."""
    from ..demos import WALKS, run_walk
    from ..exceptions import FrameNotFoundError, GaitPatternError
    from ..experiments.metrics import write_json
    from ..models.loader import load_robot

    walk = WALKS[args.name]
    options = {name: getattr(args, name) for name in walk.options}  # the walk's own, if given
    options = {name: value for name, value in options.items() if value not in (None, False)}
    if "direction" in options:
        options["direction"] = math.radians(options["direction"])  # --direction is in degrees
    if "robot" in walk.options:
        _legged_robot(args, walk.robot)  # a robot that cannot walk: a usage error, before the run
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
    if result.estimation is not None:
        print(result.estimation.summary().summary())
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
        if result.estimation is not None:
            print(f"estimate plot: {path.with_name(path.stem + '-estimate.png')}")
    if viewer is not None:
        finish_viewer(args, viewer)
    return 1 if metrics.fell else 0


def _legged_robot(args: argparse.Namespace, default: str):
    """``(robot, body, feet)`` of ``--robot`` (else ``default``) and ``--feet``, or OptionError."""
    from ..exceptions import RobotDescriptionError, RobotNotFoundError
    from ..models.feet import body_frame, find_feet
    from ..models.loader import load_robot
    from ..vocabulary.axes import resolve_frame

    feet = args.feet
    described = (RobotNotFoundError, RobotDescriptionError)
    with blame("--feet" if feet else "--robot"), blame("--robot", only=described):
        robot = load_robot(default if args.robot is None else args.robot)
        if feet is None:
            found = find_feet(robot)
            body, feet = found.body, list(found.feet)
        else:
            for frame in feet:
                resolve_frame(robot.model, frame, "foot")
            body, feet = body_frame(robot.model, robot.floating_base), list(feet)
    if not robot.floating_base:
        raise OptionError(
            f"argument --robot: robot {robot.name!r} has a fixed base: {args.name} needs a "
            "legged robot, whose base floats (the robots command lists them)"
        )
    return robot, body, feet


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
    with bar or contextlib.nullcontext():
        done = itertools.count(1)
        arrived = None if bar is None else lambda _: bar.set(next(done))
        results = run_sweep(cases, engine=args.engine, workers=args.workers, on_result=arrived)
    speeds_, terrains_, rate = success_map(results)
    width = max(len(t) for t in terrains_)
    print(f"{'':{width}}  " + " ".join(f"{s:>6g}" for s in speeds_) + "   (speed [m/s])")
    for i, terrain in enumerate(terrains_):
        cells = " ".join(f"{value:>6.0%}" if value == value else "     -" for value in rate[i])
        print(f"{terrain:{width}}  {cells}")
    out, option = _results_path(args)
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


def _results_path(args: argparse.Namespace) -> tuple[str | None, str]:
    """``(path or None, option)`` of the results: ``--out``, else a ``.csv`` beside ``--plot``."""
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
    from .types import output_path

    out, option = _results_path(args)
    if out is not None and option == "--plot":
        try:
            output_path(out)
        except argparse.ArgumentTypeError as error:
            parser.error(f"argument --plot: the results table beside it: {error}")


def run(args: argparse.Namespace) -> int:
    """Run the parsed command; returns the exit code (1: a walk ended with the robot fallen).

    Raises:
        OptionError: A value that only failed when used (names its option).
        VirtualActuatorError: A library error caused by the arguments.
    """
    if args.command == "demo":
        if args.name == "stand":
            _demo_stand(args)
            return 0
        return demo_walk(args)
    if args.command == "example":
        from ..examples import EXAMPLES

        example = EXAMPLES[args.name]()
        show_static(args, example.robot, example.q, example.solution, example.actuator)
    elif args.command == "sweep":
        return sweep_command(args)
    elif args.command == "robots":
        from ..models.directory import describe_robots, robot_table

        print(robot_table(describe_robots()))
    return 0


def _demo_stand(args: argparse.Namespace) -> None:
    """Print the body actuator distribution of ``--robot`` (and show it with ``--viz``)."""
    import virtual_actuators as va
    from virtual_actuators.models.standing import standing_pose

    robot, body_frame, feet = _legged_robot(args, "solo12")
    q = standing_pose(robot, feet)  # _legged_robot refused a fixed base
    weight = robot.mass * 9.81  # [N]
    contact = "point" if len(feet) >= 3 else "flat"
    print(
        f"{robot}  mass {robot.mass:.2f} kg; body {body_frame!r} on {len(feet)} feet "
        f"({', '.join(feet)}), {contact} contacts"
    )
    body = va.ParallelVirtualActuator(
        robot, action=body_frame, reactions=feet, reference=body_frame, contact=contact
    )
    wrench = np.array([2.0, 0.0, weight, 0.1, -0.2, 0.05])  # [N, N m] in the body frame
    sol = body.solve(q, wrench)
    print_solution("body actuator (minimum-norm distribution)", robot, body, sol)
    shown, actuator = sol, body
    timed = [("minimum-norm", body)]
    if len(feet) == 4 and contact == "point":
        # all x forces equal, y forces equal front and hind, diagonal z sums equal: r = 6
        design = [va.Equal((feet[0], "x"), (foot, "x")) for foot in feet[1:]]
        design += [
            va.Equal((feet[0], "y"), (feet[1], "y")),
            va.Equal((feet[2], "y"), (feet[3], "y")),
        ]
        z = {(feet[0], "z"): 1, (feet[3], "z"): 1, (feet[1], "z"): -1, (feet[2], "z"): -1}
        design.append(va.Linear(z))
        square = va.ParallelVirtualActuator(
            robot, action=body_frame, reactions=feet, reference=body_frame, design=design
        )
        shown, actuator = square.solve(q, wrench), square
        print_solution("with six design constraints (square, partitioned)", robot, square, shown)
        timed.append(("partitioned", square))
    for name, timed_actuator in timed:
        start = time.perf_counter()
        for _ in range(STAND_SOLVES):
            timed_actuator.solve(q, wrench)
        elapsed = (time.perf_counter() - start) / STAND_SOLVES * 1e6
        print(f"\nsolve time ({name}): {elapsed:.1f} us per call (mean of one run)")
    if args.estimator:
        _stand_on_estimate(args, robot.name if args.robot is None else args.robot, feet)
    show_static(args, robot, q, shown, actuator)


def _stand_on_estimate(args: argparse.Namespace, robot: str, feet: tuple[str, ...]) -> None:
    """``demo stand --estimator``: the robot standing in MuJoCo on the estimate (no push)."""
    from ..demos import run_walk
    from ..experiments.metrics import write_json

    result = run_walk(
        "balance", duration=args.duration, progress=not args.quiet, robot=robot, estimator=True
    )
    print(f"\nstanding on the estimate: {result.metrics.summary()}")
    print(result.estimation.summary().summary())
    if args.json:
        with writing("--json", args.json):
            path = write_json(result.to_json(), args.json)
        print(f"trace: {path}")
