"""What the command line prints and shows: solution tables and the viewer around a demo."""

from __future__ import annotations

import argparse
import contextlib
import os
import sys

import numpy as np

from .options import wants_viewer
from .usage_errors import writing


def _joint_table(robot, tau: np.ndarray) -> str:
    """Each joint's effort, a row per degree of freedom, the names' column fitting the longest."""
    model = robot.model
    rows = []
    for j in range(1, model.njoints):
        joint = model.joints[j]
        if joint.shortname() == "JointModelFreeFlyer":
            continue
        for k in range(joint.nv):
            name = model.names[j] + (f"[{k}]" if joint.nv > 1 else "")
            rows.append((name, tau[joint.idx_v + k]))
    width = max([len("joint"), *(len(name) for name, _ in rows)]) + 2
    lines = [f"{'joint':<{width}}{'effort [N m]':>14}"]
    lines += [f"{name:<{width}}{effort:>z14.4f}" for name, effort in rows]
    return "\n".join(lines)


def print_solution(title: str, robot, body, sol) -> None:
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


def _nice_scale(force: float, length: float) -> float:
    """Arrow scale [m/N] drawing ``force`` about ``length`` long, at a round N per metre."""
    per_metre = max(force, 1e-9) / max(length, 1e-3)
    exponent = 10.0 ** np.floor(np.log10(per_metre))
    step = next(m for m in (1.0, 2.0, 5.0, 10.0) if m * exponent >= per_metre)
    return 1.0 / (step * exponent)


def make_viewer(args: argparse.Namespace, robot, **options):
    """A live viewer (``--viz``) or an offline one for ``--record`` only (callers ask first)."""
    from ..viz import OfflineWindow, Viewer

    window = None if args.viz else OfflineWindow()
    return Viewer(robot, window=window, **options)


def pause(message: str) -> bool:
    """Wait for Enter when a person is at the terminal (True); return at once in scripts."""
    if sys.stdin is None or not sys.stdin.isatty():
        return False
    with contextlib.suppress(EOFError):
        input(message)
    return True


def finish_viewer(args: argparse.Namespace, viewer) -> None:
    """Write the recording (``--record``), keep a live view serving until stopped (`serve`), close.

    Raises:
        OptionError: The recording cannot be written (the viewer is closed all the same).
    """
    try:
        if args.record:
            with writing("--record", args.record):
                print(f"recording: {viewer.save_html(args.record)}")
        if args.viz:
            viewer.flush()
            serve()
    finally:
        viewer.close()


def serve() -> None:
    """Keep the live viewer serving: until Enter or Ctrl-C at a terminal, else SIGINT or SIGTERM."""
    import signal
    import time

    def stop(number, frame) -> None:
        raise KeyboardInterrupt

    try:  # SIGTERM too closes the viewer's server (it runs in a session of its own)
        previous = signal.signal(signal.SIGTERM, stop)
    except ValueError:  # not the main thread: only Ctrl-C
        previous = None
    try:
        if not pause("viewer: serving (URL above); press Enter (or Ctrl-C) to stop it. "):
            print(
                f"viewer: serving (URL above) until interrupted (Ctrl-C, or kill {os.getpid()}); "
                "no terminal to press Enter in",
                flush=True,
            )
            while True:
                time.sleep(3600.0)
    except KeyboardInterrupt:
        pass
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
    print("viewer: stopped")


def show_static(args: argparse.Namespace, robot, q, solution, actuator) -> None:
    """Show one configuration with an actuator's distribution (``--viz`` / ``--record``)."""
    if not wants_viewer(args):
        return
    linear = [i for i, a in enumerate(solution.axes) if a in ("x", "y", "z")]
    force = float(np.linalg.norm(solution.forces[:, linear].sum(axis=0)))
    import pinocchio as pin

    data = pin.Data(robot.model)
    pin.framesForwardKinematics(robot.model, data, q)
    points = np.array([f.translation for f in data.oMf])
    extent = max(0.3, float(np.linalg.norm(points.max(axis=0) - points.min(axis=0))))
    viewer = make_viewer(args, robot, force_scale=_nice_scale(force, 0.6 * extent))
    viewer.show(q, solution, actuator=actuator)
    finish_viewer(args, viewer)
