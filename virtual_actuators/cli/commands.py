"""What the command line runs: the demos, the worked examples, the viewer around them."""

from __future__ import annotations

import argparse
import contextlib
from collections.abc import Iterator
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ..examples import Example

from .views import finish_viewer, make_viewer, pause, show_static, wants_viewer


def demo_walk(args: argparse.Namespace) -> int:
    """Run one of the seeds' walks in MuJoCo, print its metrics, write JSON and a plot."""
    from ..demos import WALKS, run_walk
    from ..experiments.metrics import write_json
    from ..experiments.plots import plot_walk
    from ..models.loader import load_robot

    viewer = on_tick = None
    if wants_viewer(args):
        viewer = make_viewer(args, load_robot(WALKS[args.name].robot), force_scale=1 / 250)
        if args.record:
            viewer.start_recording(fps=30.0)
        if args.viz:
            pause("Open the viewer, then press Enter to start. ")
        on_tick = viewer.tick_callback(realtime=args.realtime)
    result = run_walk(
        args.name,
        duration=args.duration,
        speed=args.speed,
        terrain=args.terrain,
        progress=not args.quiet,
        on_tick=on_tick,
        seed=args.seed,
        distribution=args.distribution,
    )
    metrics = result.metrics
    print(metrics.summary())
    if args.json:
        with writing("--json", args.json):
            print(f"metrics: {write_json(metrics, args.json)}")
    if args.plot:
        title = f"{args.name}: {result.log.metadata['robot']} on {result.log.metadata['terrain']}"
        heights = result.log.terrain_points[:, 1]
        layout = "time" if np.ptp(heights) == 0.0 else "terrain"  # Fig. 9 vs Fig. 15
        with writing("--plot", args.plot):
            path = plot_walk(
                result.log,
                args.plot,
                title=title,
                metrics=metrics,
                layout=layout,
                window=args.window,
            )
        print(f"plot: {path}")
    if viewer is not None:
        finish_viewer(args, viewer)
    return 1 if metrics.fell else 0


def demo_hexapod(args: argparse.Namespace) -> int:
    """Walk the 1996 hexapod in MuJoCo, print its figures, write JSON and a plot."""
    import math

    from ..demos.hexapod_walk import HexapodWalkConfig, run_hexapod_walk
    from ..experiments.hexapod_plots import plot_hexapod
    from ..experiments.metrics import write_json

    defaults = HexapodWalkConfig()
    speed = args.speed
    if speed is None:
        speed = 0.2 if (args.pendulum or args.track) else defaults.speed
    config = HexapodWalkConfig(
        speed=speed,
        direction=math.radians(args.direction or 0.0),
        yaw_rate=args.yaw_rate or 0.0,
        path=args.path or "line",
        amplitude=defaults.amplitude if args.amplitude is None else args.amplitude,
        wavelength=defaults.wavelength if args.wavelength is None else args.wavelength,
        pendulum=args.pendulum,
        track=args.track,
        terrain=args.terrain or "flat",
        duration=args.duration or defaults.duration,
        seed=args.seed,
        distribution=args.distribution or defaults.distribution,
    )
    viewer = on_tick = None
    if wants_viewer(args):
        from ..demos.hexapod_walk import hexapod_robot

        viewer = make_viewer(args, hexapod_robot(config.pendulum), force_scale=1 / 100)
        if args.record:
            viewer.start_recording(fps=30.0)
        if args.viz:
            pause("Open the viewer, then press Enter to start. ")
        on_tick = viewer.tick_callback(realtime=args.realtime)
    result = run_hexapod_walk(config, progress=not args.quiet, on_tick=on_tick)
    print(result.metrics.summary())
    if args.json:
        with writing("--json", args.json):
            print(f"trace: {write_json(result.to_json(), args.json)}")
    if args.plot:
        with writing("--plot", args.plot):
            path = plot_hexapod(result.log, args.plot, summary=result.metrics.summary())
        print(f"plot: {path}")
    if viewer is not None:
        finish_viewer(args, viewer)
    return 1 if result.metrics.fell else 0


def example_view(args: argparse.Namespace, example: Example) -> None:
    """Show an example's configuration and solution (``--viz`` / ``--record``).

    The example's robot, actuator, configuration and solution are drawn as they are.
    """
    if not wants_viewer(args):
        return
    solution = example.solution
    show_static(args, example.robot, example.q, solution, example.actuator, solution.requested)


class OptionError(Exception):
    """A command-line value that turned out unusable at run time (reported as a usage error)."""


@contextlib.contextmanager
def blame(option: str) -> Iterator[None]:
    """Turn a library error raised in the block into an :class:`OptionError` naming ``option``.

    Raises:
        OptionError: If the block raises a :class:`~virtual_actuators.VirtualActuatorError`.
    """
    from ..exceptions import VirtualActuatorError

    try:
        yield
    except VirtualActuatorError as error:
        raise OptionError(f"argument {option}: {error}") from error


@contextlib.contextmanager
def writing(option: str, path: str) -> Iterator[None]:
    """Turn an :class:`OSError` raised while writing ``path`` into an :class:`OptionError`.

    Every output is tried before the run (:func:`~virtual_actuators.cli.types.output_path`);
    this reports one that still fails at the end (the disk filled up) on one line, never as a
    traceback whose exit code 1 would read as "the robot fell".

    Raises:
        OptionError: If the block raises an :class:`OSError` (names ``option``, the path and the
            reason).
    """
    try:
        yield
    except OSError as error:
        reason = error.strerror or str(error)
        raise OptionError(f"argument {option}: cannot write {path!r}: {reason}") from error


def run(args: argparse.Namespace) -> int:
    """Run the parsed command; returns the exit code (1: a walk ended with the robot fallen).

    Raises:
        OptionError: A value that only failed when used (names its option).
        VirtualActuatorError: A library error caused by the arguments.

    """
    if args.command == "demo":
        if args.name == "stand":
            from .stand import demo_stand, stand_robot

            with blame("--feet" if args.feet else "--robot"):
                loaded = stand_robot("solo12" if args.robot is None else args.robot, args.feet)
            demo_stand(loaded, args=args)
            return 0
        if args.name == "hexapod-walk":
            return demo_hexapod(args)
        return demo_walk(args)
    if args.command == "example":
        from ..examples import EXAMPLES

        example_view(args, EXAMPLES[args.name]())
    elif args.command == "sweep":
        from .sweep import sweep_command

        return sweep_command(args)
    elif args.command == "robots":
        from ..models.directory import describe_robots, robot_table

        print(robot_table(describe_robots()))
    return 0
