"""What the command line runs: the demos, the worked examples, the viewer around them."""

from __future__ import annotations

import argparse
import contextlib
import sys
from collections.abc import Iterator, Sequence
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ...examples import Example


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


def print_solution(title: str, robot, body, q, wrench, sol) -> None:
    """Print a parallel actuator's sizes, partition, per-chain forces and joint efforts."""
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
    from ..viz import OfflineWindow, Viewer

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


def show_static(args: argparse.Namespace, robot, q, solution, actuator, wrench) -> None:
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
    from ..demos import WALKS, run_walk
    from ..experiments.metrics import write_json
    from ..experiments.plots import plot_walk
    from ..robots.loader import load_robot

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
        seed=args.seed,
        distribution=args.distribution,
    )
    metrics = result.metrics
    print(metrics.summary())
    if args.json:
        print(f"metrics: {write_json(metrics, args.json)}")
    if args.plot:
        title = f"{args.name}: {result.log.metadata['robot']} on {result.log.metadata['terrain']}"
        heights = result.log.terrain_points[:, 1]
        layout = "time" if np.ptp(heights) == 0.0 else "terrain"  # Fig. 9 vs Fig. 15
        path = plot_walk(
            result.log, args.plot, title=title, metrics=metrics, layout=layout, window=args.window
        )
        print(f"plot: {path}")
    if viewer is not None:
        _finish_viewer(args, viewer)
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
    if _wants_viewer(args):
        from ..demos.hexapod_walk import hexapod_robot

        viewer = _make_viewer(args, hexapod_robot(config.pendulum), force_scale=1 / 100)
        if args.record:
            viewer.start_recording(fps=30.0)
        if args.viz:
            _pause("Open the viewer, then press Enter to start. ")
        on_tick = viewer.tick_callback(realtime=args.realtime)
    result = run_hexapod_walk(config, progress=not args.quiet, on_tick=on_tick)
    print(result.metrics.summary())
    if args.json:
        print(f"trace: {write_json(result.to_json(), args.json)}")
    if args.plot:
        print(f"plot: {plot_hexapod(result.log, args.plot, summary=result.metrics.summary())}")
    if viewer is not None:
        _finish_viewer(args, viewer)
    return 1 if result.metrics.fell else 0


def example_view(args: argparse.Namespace, example: Example) -> None:
    """Show an example's configuration and solution (``--viz`` / ``--record``).

    The example's robot, actuator, configuration and solution are drawn as they are.
    """
    if not _wants_viewer(args):
        return
    solution = example.solution
    show_static(args, example.robot, example.q, solution, example.actuator, solution.requested)


class OptionError(Exception):
    """A command-line value that turned out unusable at run time (reported as a usage error)."""


@contextlib.contextmanager
def _blame(option: str) -> Iterator[None]:
    """Turn a library error raised in the block into an :class:`OptionError` naming ``option``.

    Raises:
        OptionError: If the block raises a :class:`~virtual_actuators.VirtualActuatorError`.
    """
    from ..exceptions import VirtualActuatorError

    try:
        yield
    except VirtualActuatorError as error:
        raise OptionError(f"argument {option}: {error}") from error


def run(args: argparse.Namespace) -> int:
    """Run the parsed command; returns the exit code (1: a walk ended with the robot fallen).

    Raises:
        OptionError: A value that only failed when used (names its option).
        VirtualActuatorError: A library error caused by the arguments.

    """
    if args.command == "demo":
        if args.name == "stand":
            from .stand import demo_stand, stand_robot

            with _blame("--feet" if args.feet else "--robot"):
                loaded = stand_robot(args.robot or "solo12", args.feet)
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
        from ..robots.directory import describe_robots, robot_table

        print(robot_table(describe_robots()))
    return 0
