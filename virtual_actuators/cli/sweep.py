"""``sweep``: a walk over a grid of speeds, terrains and seeds, in parallel."""

from __future__ import annotations

import argparse


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
    from .commands import blame, writing

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
    with writing("--out", args.out):
        print(f"results: {write_results(results, args.out)}")
    if args.plot:
        with writing("--plot", args.plot):
            print(f"success map: {plot_success_map(results, args.plot)}")
    errors = [r for r in results if r.error]
    for result in errors[:5]:
        print(f"error at speed {result.speed} on {result.terrain}: {result.error}")
    return 1 if any(r.fell for r in results) else 0
