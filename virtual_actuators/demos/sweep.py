"""Parameter sweeps of the walks: every (speed, terrain, seed) walk of a grid, in parallel.

Engines: ``"process"`` (a process pool), ``"dask"`` (``DASK_SCHEDULER_ADDRESS``, else a local
cluster) and ``"ray"`` (``RAY_ADDRESS`` when set); results go to a table and a success map.
"""

from __future__ import annotations

import csv
import json
import os
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..exceptions import InvalidInputError, import_optional

if TYPE_CHECKING:
    from matplotlib.figure import Figure

ENGINES = ("process", "dask", "ray")
#: Most seeds per (speed, terrain) cell, and most walks in one sweep (all queued at once).
MAX_SEEDS = 1000
MAX_WALKS = 100_000


@dataclass(frozen=True)
class SweepCase:
    """One walk of a sweep."""

    walk: str
    speed: float  # [m/s]
    terrain: str
    seed: int
    duration: float | None = None  # [s], None: the walk's default


@dataclass(frozen=True)
class SweepResult:
    """What one walk of a sweep gave (``error`` is set, and the rest NaN, if it raised)."""

    walk: str
    speed: float
    terrain: str
    seed: int
    fell: bool
    fall_time: float
    distance: float  # [m]
    mean_speed: float  # [m/s]
    steps: int
    realtime_factor: float
    error: str = ""


def grid(
    walk: str,
    speeds: Sequence[float],
    terrains: Sequence[str],
    seeds: int,
    duration: float | None = None,
) -> list[SweepCase]:
    """Every (speed, terrain, seed) case, seeds ``0 .. seeds - 1``.

    Raises:
        InvalidInputError: Unknown walk, ``seeds`` not an int from 1 to `MAX_SEEDS`, or
            more than `MAX_WALKS` cases in all.
    """
    from ..gaits.registry import WALKS  # MuJoCo: not needed to parse a sweep's options

    if walk not in WALKS:
        raise InvalidInputError(f"Unknown walk {walk!r}; sweeps run {sorted(WALKS)}.")
    if isinstance(seeds, bool) or not isinstance(seeds, int) or not 1 <= seeds <= MAX_SEEDS:
        raise InvalidInputError(f"seeds must be an int from 1 to {MAX_SEEDS}, got {seeds!r}.")
    count = len(speeds) * len(terrains) * seeds
    if count > MAX_WALKS:
        raise InvalidInputError(
            f"A sweep of {len(speeds)} speeds x {len(terrains)} terrains x {seeds} seeds = "
            f"{count} walks is more than {MAX_WALKS}: fewer speeds, terrains or seeds."
        )
    return [
        SweepCase(walk, float(speed), terrain, seed, duration)
        for speed in speeds
        for terrain in terrains
        for seed in range(seeds)
    ]


def run_case(case: SweepCase) -> SweepResult:
    """Run one walk (in a worker); a library error is recorded, not raised."""
    from ..exceptions import VirtualActuatorError

    cell = (case.walk, case.speed, case.terrain, case.seed)
    options = dict(duration=case.duration, speed=case.speed, terrain=case.terrain, seed=case.seed)
    try:  # force_speed: a sweep maps where the walk holds, inside its range or not
        from ..gaits import registry  # MuJoCo, imported in the worker

        result = registry.run_walk(case.walk, progress=False, force_speed=True, **options)
    except Exception as error:  # recorded in the table: one broken walk never loses the sweep
        typed = isinstance(error, VirtualActuatorError)
        message = str(error) if typed else f"{type(error).__name__}: {error}"
        nan = float("nan")
        return SweepResult(*cell, True, nan, nan, nan, 0, nan, message)
    figures = result.figures()
    factor = float(result.simulator.time / max(result.wall_time, 1e-9))
    distances = figures.fall_time, figures.distance, figures.mean_speed
    return SweepResult(*cell, figures.fell, *distances, figures.steps, factor)


def run_sweep(
    cases: Sequence[SweepCase],
    engine: str = "process",
    workers: int | None = None,
    on_result: Callable[[SweepResult], None] | None = None,
) -> list[SweepResult]:
    """Run the cases in parallel; results come back in the order of ``cases``.

    Args:
        cases: From `grid`.
        engine: ``"process"``, ``"dask"`` or ``"ray"``.
        workers: Parallel workers for ``"process"`` (None: the CPU count).
        on_result: Called as each result arrives (a progress bar).

    Raises:
        InvalidInputError: Unknown engine, or ``workers`` < 1.
        MissingDependencyError: Dask or Ray is not installed.
    """
    if engine not in ENGINES:
        raise InvalidInputError(f"engine must be one of {ENGINES}, got {engine!r}.")
    whole = isinstance(workers, int) and not isinstance(workers, bool)
    if workers is not None and not (whole and workers >= 1):
        raise InvalidInputError(f"workers must be an int >= 1, got {workers!r}.")
    engines = {"process": _run_processes, "dask": _run_dask, "ray": _run_ray}
    results: dict[int, SweepResult] = {}
    for i, result in engines[engine](cases, workers):
        results[i] = result
        if on_result is not None:
            on_result(result)
    return [results[i] for i in range(len(cases))]


def _run_processes(cases, workers) -> Iterator[tuple[int, SweepResult]]:
    """``(index, result)`` of each case as it arrives from a process pool."""
    from concurrent.futures import ProcessPoolExecutor, as_completed

    count = workers or os.cpu_count() or 1
    pool = ProcessPoolExecutor(max_workers=min(count, max(len(cases), 1)))
    try:
        futures = {pool.submit(run_case, case): i for i, case in enumerate(cases)}
        for future in as_completed(futures):
            yield futures[future], future.result()
    except BaseException:  # Ctrl-C or a crashed worker: drop the queued walks at once
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    pool.shutdown()


def _run_dask(cases, workers) -> Iterator[tuple[int, SweepResult]]:
    """As `_run_processes`, on ``DASK_SCHEDULER_ADDRESS`` or a local cluster."""
    for package in ("dask", "distributed"):
        import_optional(package, "dask", "engine='dask' (dask.distributed)")
    from dask.distributed import Client, LocalCluster, as_completed

    address = os.environ.get("DASK_SCHEDULER_ADDRESS")
    cluster = None if address else LocalCluster(processes=True, threads_per_worker=1)
    try:
        with Client(address or cluster) as client:
            futures = client.map(run_case, cases, pure=False)
            index = {future.key: i for i, future in enumerate(futures)}
            for future in as_completed(futures):
                yield index[future.key], future.result()
    finally:
        if cluster is not None:
            cluster.close()


def _run_ray(cases, workers) -> Iterator[tuple[int, SweepResult]]:
    """As `_run_processes`, on Ray (``RAY_ADDRESS`` when set)."""
    ray = import_optional("ray", "ray", "engine='ray'")
    started = not ray.is_initialized()
    ray.init(ignore_reinit_error=True, include_dashboard=False)
    try:
        remote = ray.remote(run_case)
        pending = {remote.remote(case): i for i, case in enumerate(cases)}
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1)
            for reference in ready:
                yield pending.pop(reference), ray.get(reference)
    finally:
        if started:
            ray.shutdown()


def write_results(results: Iterable[SweepResult], path: str | Path) -> Path:
    """Write the table as CSV (``.csv``) or JSON (any other suffix); returns the path."""
    path = Path(path)
    rows = [asdict(result) for result in results]
    if path.suffix.lower() == ".csv":
        with path.open("w", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=list(SweepResult.__dataclass_fields__))
            writer.writeheader()
            writer.writerows(rows)
    else:
        clean = [
            {k: (None if isinstance(v, float) and v != v else v) for k, v in row.items()}
            for row in rows
        ]
        path.write_text(json.dumps({"results": clean}, indent=1))
    return path


def success_map(results: Sequence[SweepResult]) -> tuple[list[float], list[str], np.ndarray]:
    """``(speeds, terrains, rate)``: the fraction of seeds that did not fall, per cell."""
    speeds = sorted({r.speed for r in results})
    terrains = list(dict.fromkeys(r.terrain for r in results))
    rate = np.full((len(terrains), len(speeds)), np.nan)
    for i, terrain in enumerate(terrains):
        for j, speed in enumerate(speeds):
            cell = [r for r in results if r.terrain == terrain and r.speed == speed]
            if cell:
                rate[i, j] = sum(not r.fell for r in cell) / len(cell)
    return speeds, terrains, rate


def plot_success_map(results: Sequence[SweepResult], path: str | Path) -> Path:
    """Draw `success_map` as a heat map (speed across, terrain down) into ``path`` (by suffix).

    Raises:
        MissingDependencyError: matplotlib is not installed (the extra ``plots``).
    """
    figure = draw_success_map(results)
    figure.savefig(path, dpi=figure.dpi)
    return Path(path)


def draw_success_map(results: Sequence[SweepResult], dpi: float = 120) -> Figure:
    """The heat map `plot_success_map` saves: a matplotlib figure (no pyplot).

    Raises:
        MissingDependencyError: matplotlib is not installed (the extra ``plots``).
    """
    import_optional("matplotlib", "plots", "The success map")
    from matplotlib.ticker import PercentFormatter

    from ..experiments.plot_panels import new_figure, set_heading

    speeds, terrains, rate = success_map(results)
    walk = results[0].walk if results else ""
    seeds = len({r.seed for r in results})
    longest = max((len(t) for t in terrains), default=0)
    width = max(5.0, 2.4 + 0.08 * longest + 0.7 * len(speeds))
    figure = new_figure(width, 1.9 + 0.6 * len(terrains), dpi)
    axes = figure.add_subplot()
    image = axes.imshow(rate, vmin=0.0, vmax=1.0, cmap="RdYlGn", aspect="auto")
    axes.set_xticks(range(len(speeds)), [f"{s:g}" for s in speeds])
    axes.set_yticks(range(len(terrains)), terrains)
    axes.set_xlabel("desired speed [m/s]")
    axes.set_ylabel("terrain")
    for i, j in zip(*np.nonzero(np.isfinite(rate)), strict=True):  # cells that ran, row by row
        axes.text(j, i, f"{rate[i, j]:.0%}", ha="center", va="center", fontsize=8)
    bar = figure.colorbar(image, ax=axes, fraction=0.05, format=PercentFormatter(1.0))
    bar.set_label("walks that did not fall", fontsize=8)
    per_cell = f"{seeds} seed per cell" if seeds == 1 else f"{seeds} seeds per cell"
    set_heading(figure, f"{walk}: walks that did not fall, of {per_cell}", 10)
    return figure
