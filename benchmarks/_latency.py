"""Worst-case ticks for ``bench_realtime.py`` figure 7: the tail of the tick-time distribution.

Two durations per tick, both in microseconds, from ``perf_counter_ns``:

* **controller**: the controller's compute between reading the state and writing the efforts.
  In a walk (``run_walk``), the gait's outermost ``compute(q, v, t, contacts)`` call; in a
  ``va.run`` loop, from the end of ``read_state`` to the start of ``write_effort`` (the loop's
  checks of the reading and of the efforts included). This is what a controller on hardware
  pays. Its thread CPU time (``thread_time_ns``, same interval) is reported too: unlike the
  wall-clock time it leaves out the time the thread was not running (preempted by other
  processes on a busy machine), so a tick whose wall time is far above its CPU time waited
  for the CPU. Reading that clock costs ~0.6 us per tick inside the interval.
* **loop**: one whole iteration of the loop. In a walk, from the end of one iteration's physics
  step to the end of the next (the first from the gait's first ``compute``): the contact
  switches, the gait, MuJoCo's step, the stance forces, the fall test and the recording. In a
  ``va.run`` loop, from one ``read_state`` call to the next (the last to the end of its
  ``write_effort``): read, checks, compute, MuJoCo's step, the loop's bookkeeping.

Beside them, MuJoCo's own ``Simulator.step`` (one control period of physics) in the same ticks:
the baseline of the same run.
"""

from __future__ import annotations

import gc
import time
from collections.abc import Callable
from typing import Any

import numpy as np

#: Percentiles reported for each duration.
TAIL = {"p50": 50.0, "p99": 99.0, "p99.9": 99.9}


def tail(samples_us: Any) -> dict[str, float]:
    """p50, p99, p99.9, max, the tick of the max (0: the first), the max of the ticks after the
    first, how many took 1 ms or more, and the count of tick durations [us]."""
    values = np.asarray(samples_us, dtype=float)
    if values.size == 0:
        empty = dict.fromkeys([*TAIL, "max", "max_after_first"], float("nan"))
        return {**empty, "max_at": -1, "over_1ms": 0, "n": 0}
    out = {key: float(np.percentile(values, q)) for key, q in TAIL.items()}
    worst = int(np.argmax(values))
    out |= {"max": float(values[worst]), "max_at": worst}
    out["max_after_first"] = float(values[1:].max()) if values.size > 1 else float("nan")
    return {**out, "over_1ms": int(np.sum(values >= 1e3)), "n": int(values.size)}


def tail_text(stats: dict[str, float]) -> str:
    """``p50 / p99 / p99.9 / max us``."""
    return " / ".join(f"{stats[k]:.0f}" for k in (*TAIL, "max")) + " us"


class _Outermost:
    """Times the outermost call of some methods (a subclass's ``compute`` calling its base's
    counts once); ``last`` holds the latest duration [ns], ``last_cpu`` its thread CPU time
    [ns] (with ``cpu``), ``first_start`` when the first call started."""

    def __init__(self, targets: list[tuple[type, str]], cpu: bool = False) -> None:
        self.targets, self.cpu, self.last, self.last_cpu, self.depth = targets, cpu, 0, 0, 0
        self.first_start: int | None = None  # the first outermost call's start [ns]
        self._saved: list[tuple[type, str, object]] = []

    def _wrap(self, function: Callable[..., Any]) -> Callable[..., Any]:
        clock = time.perf_counter_ns
        cpu = time.thread_time_ns if self.cpu else int

        def wrapped(*args: Any, **kwargs: Any) -> Any:
            self.depth += 1
            start, start_cpu = clock(), cpu()
            if self.first_start is None:
                self.first_start = start
            try:
                return function(*args, **kwargs)
            finally:
                self.depth -= 1
                if self.depth == 0:
                    self.last_cpu = cpu() - start_cpu
                    self.last = clock() - start

        return wrapped

    def __enter__(self) -> _Outermost:
        for cls, name in self.targets:
            original = cls.__dict__[name]
            self._saved.append((cls, name, original))
            setattr(cls, name, self._wrap(original))
        return self

    def __exit__(self, *exc: object) -> None:
        for cls, name, original in reversed(self._saved):
            setattr(cls, name, original)
        self._saved.clear()


class _GarbageCollections:
    """Python's garbage collections while the block runs: count per generation and the longest
    pause [us] (``gc.callbacks``), to tell a collection from the code in a long tick."""

    def __init__(self) -> None:
        self.counts, self.longest_us, self._start = [0, 0, 0], 0.0, 0

    def _callback(self, phase: str, info: dict[str, int]) -> None:
        if phase == "start":
            self._start = time.perf_counter_ns()
            return
        self.counts[info["generation"]] += 1
        self.longest_us = max(self.longest_us, (time.perf_counter_ns() - self._start) / 1e3)

    def __enter__(self) -> _GarbageCollections:
        gc.callbacks.append(self._callback)
        return self

    def __exit__(self, *exc: object) -> None:
        gc.callbacks.remove(self._callback)

    def summary(self) -> dict[str, Any]:
        """``{"collections": [gen 0, gen 1, gen 2], "longest_pause_us": ...}``."""
        return {"collections": list(self.counts), "longest_pause_us": self.longest_us}


def _classes_defining(base: type, name: str) -> list[tuple[type, str]]:
    """``(class, name)`` for ``base`` and every subclass that defines ``name`` itself."""
    found, todo = [], [base]
    while todo:
        cls = todo.pop()
        todo.extend(cls.__subclasses__())
        if name in cls.__dict__ and (cls, name) not in found:
            found.append((cls, name))
    return found


def walk_ticks(name: str, seconds: float, **options: Any) -> dict[str, Any]:
    """``run_walk(name, duration=seconds, **options)`` with its ticks timed (controller, loop,
    MuJoCo step); returns their :func:`tail` and the run's facts."""
    from virtual_actuators.demos import run_walk
    from virtual_actuators.gaits import Gait
    from virtual_actuators.simulation import Simulator

    controller, cpu, physics, ends = [], [], [], []
    clock = time.perf_counter_ns
    gait_probe = _Outermost(_classes_defining(Gait, "compute"), cpu=True)
    step_probe = _Outermost([(Simulator, "step")])

    def on_tick(simulator: object, gait: object) -> None:  # after every physics step
        ends.append(clock())
        controller.append(gait_probe.last)
        cpu.append(gait_probe.last_cpu)
        physics.append(step_probe.last)

    run_walk(name, duration=min(seconds, 0.3), progress=False, **options)  # imports, caches
    with gait_probe, step_probe, _GarbageCollections() as collections:
        result = run_walk(name, duration=seconds, progress=False, on_tick=on_tick, **options)
    # the first iteration starts at the gait's first compute (its reading of q, v and the
    # contact switches just before is left out)
    loop = np.diff(np.asarray([gait_probe.first_start or 0, *ends], dtype=float)) / 1e3
    return {
        "ticks": len(ends),
        "simulated_s": float(result.simulator.time),
        "fell": bool(result.metrics.fell),
        "controller": tail(np.asarray(controller, dtype=float) / 1e3),
        "controller_cpu": tail(np.asarray(cpu, dtype=float) / 1e3),
        "loop": tail(loop),
        "mujoco_step": tail(np.asarray(physics, dtype=float) / 1e3),
        "gc": collections.summary(),
    }


def run_loop_ticks(
    controller: Any, simulator: Any, q0: np.ndarray, ticks: int, robot: Any = None
) -> dict[str, Any]:
    """``va.run(controller, ...)`` for ``ticks`` ticks on ``MujocoHardware(simulator)`` (reset
    to ``q0``, ``realtime=False``, 1 kHz), each tick timed (controller, loop, MuJoCo step)."""
    import virtual_actuators as va
    from virtual_actuators.simulation import MujocoHardware

    simulator.reset(q0)
    hardware = MujocoHardware(simulator)
    clock, cpu = time.perf_counter_ns, time.thread_time_ns
    starts, read_done, write_start, write_done, cpu_read, cpu_write = [], [], [], [], [], []

    def read_state() -> tuple[np.ndarray, np.ndarray, float]:
        starts.append(clock())
        state = hardware.read_state()
        cpu_read.append(cpu())
        read_done.append(clock())
        return state

    def write_effort(tau: np.ndarray) -> None:
        write_start.append(clock())
        cpu_write.append(cpu())
        hardware.write_effort(tau)
        write_done.append(clock())

    with _GarbageCollections() as collections:
        stats = va.run(
            controller, read_state, write_effort, rate_hz=1000.0, realtime=False,
            should_stop=lambda: len(starts) >= ticks, robot=robot,
        )  # fmt: skip
    n = len(starts)  # the loop's final zero effort is one more write, not a tick
    start, read, write, done, cpu_start, cpu_end = (
        np.asarray(a[:n], dtype=float)
        for a in (starts, read_done, write_start, write_done, cpu_read, cpu_write)
    )
    return {
        "ticks": n,
        "failed_ticks": stats.failed_ticks,
        "overruns_of_1ms": stats.overruns,
        "controller": tail((write - read) / 1e3),
        "controller_cpu": tail((cpu_end - cpu_start) / 1e3),
        "loop": tail(np.diff(np.append(start, done[-1:])) / 1e3),  # start to start
        "mujoco_step": tail((done - write) / 1e3),
        "run_stats_tick_times": tail(np.asarray(stats.tick_times) * 1e6),
        "gc": collections.summary(),
    }


def ur5_tracking(ticks: int) -> dict[str, Any]:
    """The UR5's tool tracking a moving target (``bench_arm_tracking``'s 6-axis impedance with
    gravity compensation, the ``turn`` case) under ``va.run``."""
    from bench_arm_tracking import ToolTracker, start_pose

    import virtual_actuators as va
    from virtual_actuators.simulation import Simulator

    robot = va.load_robot("ur5")
    q0 = start_pose(robot)
    tracker = ToolTracker(robot, "tool0", q0, turn=True)
    tracker.controller.warm_up(q0)  # kernels loaded before the first tick
    return run_loop_ticks(tracker, Simulator(robot), q0, ticks, robot=robot)


def go2_standing(ticks: int) -> dict[str, Any]:
    """go2 standing on its four feet (the ``balance`` walk's :class:`Balancer`, no push) under
    ``va.run``."""
    import virtual_actuators as va
    from virtual_actuators.gaits.balance import Balancer
    from virtual_actuators.simulation import Simulator

    robot = va.load_robot("go2")
    gait = Balancer(robot)
    simulator = Simulator(robot)
    q0 = gait.initial_configuration()
    q0[:2] = 0.0
    q0 = simulator.on_ground(q0)
    gait.start(q0)
    gait.controller.warm_up(q0)
    return run_loop_ticks(gait, simulator, q0, ticks)


#: The ``va.run`` loops of figure 7: title -> runner(ticks).
RUN_LOOPS: dict[str, Callable[[int], dict[str, Any]]] = {
    "va.run UR5 tool tracking": ur5_tracking,
    "va.run go2 standing": go2_standing,
}
