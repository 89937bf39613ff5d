"""Worst-case ticks for ``bench_realtime.py`` figure 7: the tail of the tick-time distribution.

Two durations per tick, both in microseconds, from ``perf_counter_ns``:

* **controller**: the controller's compute between reading the state and writing the efforts.
  In a walk (``run_walk``), the gait's outermost ``compute(q, v, t, contacts)`` call (its
  compiled machine's tick; the ticks are taken at the end of each ``Simulator.step``); in a
  ``va.run`` loop, from the end of ``read_state`` to the start of ``write_effort`` (the loop's
  checks of the reading and of the efforts included). This is what a controller on hardware
  pays. Its thread CPU time (``thread_time_ns``, same interval) is reported too: unlike the
  wall-clock time it leaves out the time the thread was not running (preempted by other
  processes on a busy machine), so a tick whose wall time is far above its CPU time waited for
  the CPU. Reading that clock costs ~0.6 us per tick inside the interval.
* **loop**: one whole iteration of the loop. In a walk, from the end of one iteration's physics
  step to the end of the next (the first from the gait's first ``compute``): the contact
  switches, the gait, MuJoCo's step, the stance forces, the fall test and the recording. In a
  ``va.run`` loop, from one ``read_state`` call to the next (the last to the end of its
  ``write_effort``): read, checks, compute, MuJoCo's step, the loop's bookkeeping.

Beside them, MuJoCo's own ``Simulator.step`` (one control period of physics) in the same ticks:
the baseline of the same run.

**Ticks of 1 ms or more** (controller CPU or wall time) are listed with what happened inside the
controller's interval: Python garbage collections (generation, pause), QP solves whose active set
changed (DAQP from cold, and the ProxQP iterations of a fallback), the gait's state change, the
first tick. Every walk and loop with such ticks is then **replayed** (the same run again, up to
its last such tick: the simulation and the controller are deterministic, so tick ``i`` does the
same work): a tick whose replay takes under 1 ms of CPU was the machine's (the thread was
preempted, or its virtual CPU stolen: the thread's CPU clock counts that too on a VM), one that
takes 1 ms again is the code's, and so is one with a garbage collection or a ProxQP fallback in
it (a collection falls elsewhere in another run). ``controller_cpu_replayed`` is the controller's
CPU time with the replay in place of the machine's ticks: what a quiet machine gives.
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

    def __init__(
        self,
        targets: list[tuple[type, str]],
        cpu: bool = False,
        events: TickEvents | None = None,
        after: Callable[[], None] | None = None,
    ) -> None:
        self.targets, self.cpu, self.last, self.last_cpu, self.depth = targets, cpu, 0, 0, 0
        self.events = events  # told when the outermost call starts and ends
        self.after = after  # called after each outermost call
        self.caller: object = None  # the object of the latest outermost call
        self.first_start: int | None = None  # the first outermost call's start [ns]
        self._saved: list[tuple[type, str, object]] = []

    def _wrap(self, function: Callable[..., Any]) -> Callable[..., Any]:
        clock = time.perf_counter_ns
        cpu = time.thread_time_ns if self.cpu else int

        def wrapped(*args: Any, **kwargs: Any) -> Any:
            self.depth += 1
            if self.depth == 1 and self.events is not None:
                self.events.inside = True
            start, start_cpu = clock(), cpu()
            if self.depth == 1:
                self.caller = args[0] if args else None
            if self.first_start is None:
                self.first_start = start
            try:
                return function(*args, **kwargs)
            finally:
                self.depth -= 1
                if self.depth == 0:
                    self.last_cpu = cpu() - start_cpu
                    self.last = clock() - start
                    if self.events is not None:
                        self.events.inside = False
                    if self.after is not None:
                        self.after()

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


#: A tick at or above this is listed with what happened in it [us].
SLOW_US = 1000.0


class TickEvents:
    """What happened inside the controller's interval of each tick (:attr:`inside` set by the
    caller): garbage collections and QP solves whose active set changed (DAQP from cold, and
    ProxQP's iterations when it ran: the fallback). :meth:`end_tick` keeps a tick's record when
    its CPU or wall time reached :data:`SLOW_US`."""

    def __init__(self) -> None:
        self.inside, self.happened, self.slow = False, [], []
        self._gc_start, self._saved = 0, None
        self.collections_inside, self.longest_inside_us = 0, 0.0  # every tick's

    def _collection(self, phase: str, info: dict[str, int]) -> None:
        if not self.inside:
            return
        if phase == "start":
            self._gc_start = time.perf_counter_ns()
        else:
            pause = (time.perf_counter_ns() - self._gc_start) / 1e3
            self.collections_inside += 1
            self.longest_inside_us = max(self.longest_inside_us, pause)
            self.happened.append(f"GC gen {info['generation']} {pause:.0f} us")

    def _wrap_stages(self) -> None:
        from virtual_actuators.distribution.qp.stages import ProxStages

        original = ProxStages.solve
        self._saved = (ProxStages, original)

        def solve(stages: Any, path: str, rows: Any, miss: Any, weights: Any, budget: Any):
            if not self.inside:  # a warm-up's solve, say
                return original(stages, path, rows, miss, weights, budget)
            left, start = budget.left, time.perf_counter_ns()
            try:
                return original(stages, path, rows, miss, weights, budget)
            finally:
                used, took = left - budget.left, (time.perf_counter_ns() - start) / 1e3
                what = f"ProxQP fallback, {used} iterations" if used else "DAQP from cold"
                self.happened.append(f"QP active set changed ({what}, {took:.0f} us)")

        ProxStages.solve = solve

    def __enter__(self) -> TickEvents:
        gc.callbacks.append(self._collection)
        self._wrap_stages()
        return self

    def __exit__(self, *exc: object) -> None:
        gc.callbacks.remove(self._collection)
        cls, original = self._saved
        cls.solve = original

    def summary(self) -> dict[str, Any]:
        """Collections inside the controller's interval: count and longest pause [us]."""
        return {"inside_ticks": self.collections_inside,
                "longest_inside_us": self.longest_inside_us}  # fmt: skip

    def end_tick(self, tick: int, cpu_us: float, wall_us: float, state: str | None = None,
                 before: str | None = None) -> None:  # fmt: skip
        """Close tick ``tick`` (its controller's CPU and wall time, the gait state after it
        and before it)."""
        if cpu_us >= SLOW_US or wall_us >= SLOW_US:
            what = list(self.happened)
            if tick == 0:
                what.insert(0, "first tick")
            if state != before:
                what.append(f"state {before} -> {state}")
            self.slow.append({"tick": tick, "cpu_us": cpu_us, "wall_us": wall_us, "what": what})
        self.happened.clear()


#: What a slow tick recorded that is the code's cost even when its replay is fast (a garbage
#: collection falls on other ticks in another run: the heap differs; a ProxQP fallback).
CODE_EVENTS = ("GC gen", "ProxQP fallback")


def verdict(tick: dict[str, Any]) -> str:
    """``"code"``: CPU >= 1 ms and its replay too, or a collection or a ProxQP fallback in it;
    ``"machine"``: CPU >= 1 ms but not in the replay; ``"waited for the CPU"``: wall only."""
    if tick["cpu_us"] < SLOW_US:
        return "waited for the CPU"
    if not tick["replay_cpu_us"] < SLOW_US or any(
        event in what for what in tick["what"] for event in CODE_EVENTS
    ):
        return "code"
    return "machine"


def replayed(run: dict[str, Any], slow: list[dict[str, Any]], again: Callable[[int], Any]) -> None:
    """Replay a run up to its last slow tick (``again(ticks)`` returns the replay's controller
    CPU times [us]); each slow tick gets ``replay_cpu_us`` and a :func:`verdict`, and the run
    gets ``controller_cpu_replayed`` (the replay in place of the machine's ticks, see the
    module's text) and ``slow_ticks``."""
    cpu = np.asarray(run.pop("_cpu_us"), dtype=float)
    if slow:
        replay = np.asarray(again(max(t["tick"] for t in slow) + 1), dtype=float)
        for tick in slow:
            i = tick["tick"]
            tick["replay_cpu_us"] = float(replay[i]) if i < replay.size else float("nan")
            tick["verdict"] = verdict(tick)
            if tick["verdict"] != "code" and tick["replay_cpu_us"] < cpu[i]:
                cpu[i] = tick["replay_cpu_us"]
    run["controller_cpu_replayed"] = tail(cpu)
    run["slow_ticks"] = slow


def slow_summary(run: dict[str, Any]) -> str:
    """``N ticks >= 1 ms: ...`` grouped by verdict, the code's listed with what they were."""
    slow = run["slow_ticks"]
    if not slow:
        return "no tick >= 1 ms"
    groups: dict[str, list[dict[str, Any]]] = {}
    for tick in slow:
        groups.setdefault(tick["verdict"], []).append(tick)
    parts = []
    for tick in groups.get("code", []):
        what = "; ".join(tick["what"]) or "nothing recorded"
        parts.append(f"tick {tick['tick']} {tick['cpu_us']:.0f} us CPU (replay "
                     f"{tick['replay_cpu_us']:.0f}): {what}")  # fmt: skip
    machine = groups.get("machine", [])
    if machine:
        replays = max(t["replay_cpu_us"] for t in machine)
        noted = sorted({w for t in machine for w in t["what"] if w != "first tick"})
        parts.append(f"{len(machine)} the machine's (CPU >= 1 ms, replay <= {replays:.0f} us"
                     + (f"; seen in them: {', '.join(noted)[:160]}" if noted else "") + ")")
    waited = groups.get("waited for the CPU", [])
    if waited:
        parts.append(f"{len(waited)} waited for the CPU (wall >= 1 ms, CPU < 1 ms)")
    code = len(groups.get("code", []))
    return f"{len(slow)} ticks >= 1 ms, {code} of them the code's: " + "; ".join(parts)


def _classes_defining(base: type, name: str) -> list[tuple[type, str]]:
    """``(class, name)`` for ``base`` and every subclass that defines ``name`` itself."""
    found, todo = [], [base]
    while todo:
        cls = todo.pop()
        todo.extend(cls.__subclasses__())
        if name in cls.__dict__ and (cls, name) not in found:
            found.append((cls, name))
    return found


def _state_of(gait: object) -> str | None:
    """A gait's state name (None for a controller without a state machine)."""
    from virtual_actuators.control.plan.compiled import CompiledMachine

    try:
        if isinstance(gait, CompiledMachine):  # the walk's loop calls it directly
            return gait.machine.state.name
        return str(gait.state)
    except Exception:  # no machine
        return None


def _walk_once(name: str, seconds: float, options: dict, events: TickEvents | None) -> dict:
    """One timed run of a walk: per-tick arrays [ns] and the result."""
    from virtual_actuators.demos import run_walk
    from virtual_actuators.gaits import Gait
    from virtual_actuators.simulation import Simulator

    controller, cpu, physics, ends = [], [], [], []
    clock = time.perf_counter_ns
    from virtual_actuators.control.plan.compiled import CompiledMachine

    # the gaits' compute, and the compiled machine's (a walk's loop calls it directly)
    targets = [*_classes_defining(Gait, "compute"), (CompiledMachine, "compute")]
    gait_probe = _Outermost(targets, cpu=True, events=events)

    def on_tick() -> None:  # after every physics step
        ends.append(clock())
        controller.append(gait_probe.last)
        cpu.append(gait_probe.last_cpu)
        physics.append(step_probe.last)
        if events is not None:
            state = _state_of(gait_probe.caller)
            events.end_tick(len(cpu) - 1, cpu[-1] / 1e3, controller[-1] / 1e3, state,
                            state if before[0] is None else before[0])  # fmt: skip
            before[0] = state

    step_probe = _Outermost([(Simulator, "step")], after=on_tick)
    before = [None]

    with gait_probe, step_probe:
        result = run_walk(name, duration=seconds, progress=False, **options)
    return {"result": result, "controller": controller, "cpu": cpu, "physics": physics,
            "ends": ends, "first_start": gait_probe.first_start or 0}  # fmt: skip


def walk_ticks(name: str, seconds: float, **options: Any) -> dict[str, Any]:
    """``run_walk(name, duration=seconds, **options)`` with its ticks timed (controller, loop,
    MuJoCo step); returns their :func:`tail`, the run's facts and its slow ticks (replayed)."""
    from virtual_actuators.demos import run_walk

    run_walk(name, duration=min(seconds, 0.3), progress=False, **options)  # imports, caches
    with _GarbageCollections() as collections, TickEvents() as events:
        once = _walk_once(name, seconds, options, events)
    result, ends = once["result"], once["ends"]
    # the first iteration starts at the gait's first compute (its reading of q, v and the
    # contact switches just before is left out)
    loop = np.diff(np.asarray([once["first_start"], *ends], dtype=float)) / 1e3
    period = float(result.simulator.time) / max(len(ends), 1)
    run = {
        "ticks": len(ends),
        "simulated_s": float(result.simulator.time),
        "fell": bool(result.metrics.fell),
        "controller": tail(np.asarray(once["controller"], dtype=float) / 1e3),
        "controller_cpu": tail(np.asarray(once["cpu"], dtype=float) / 1e3),
        "loop": tail(loop),
        "mujoco_step": tail(np.asarray(once["physics"], dtype=float) / 1e3),
        "gc": collections.summary() | events.summary(),
        "_cpu_us": np.asarray(once["cpu"], dtype=float) / 1e3,
    }

    def again(ticks: int) -> np.ndarray:
        replay = _walk_once(name, (ticks + 0.5) * period, options, None)
        return np.asarray(replay["cpu"], dtype=float) / 1e3

    replayed(run, events.slow, again)
    return run


def run_loop_ticks(
    controller: Any, simulator: Any, q0: np.ndarray, ticks: int, robot: Any = None,
    events: TickEvents | None = None,
) -> dict[str, Any]:  # fmt: skip
    """``va.run(controller, ...)`` for ``ticks`` ticks on ``MujocoHardware(simulator)`` (reset
    to ``q0``, ``realtime=False``, 1 kHz), each tick timed (controller, loop, MuJoCo step)."""
    import virtual_actuators as va
    from virtual_actuators.simulation import MujocoHardware

    simulator.reset(q0)
    hardware = MujocoHardware(simulator)
    clock, cpu = time.perf_counter_ns, time.thread_time_ns
    starts, read_done, write_start, write_done, cpu_read, cpu_write = [], [], [], [], [], []
    before = [_state_of(controller)]

    def read_state() -> tuple[np.ndarray, np.ndarray, float]:
        starts.append(clock())
        state = hardware.read_state()
        cpu_read.append(cpu())
        read_done.append(clock())
        if events is not None:
            events.inside = True
        return state

    def write_effort(tau: np.ndarray) -> None:
        write_start.append(clock())
        cpu_write.append(cpu())
        if events is not None and events.inside:
            events.inside = False
            tick, state = len(cpu_write) - 1, _state_of(controller)
            events.end_tick(tick, (cpu_write[-1] - cpu_read[tick]) / 1e3,
                            (write_start[-1] - read_done[tick]) / 1e3, state, before[0])
            before[0] = state
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
        "_cpu_us": (cpu_end - cpu_start) / 1e3,
    }


def _replayed_loop(
    build: Callable[[], tuple], ticks: int, replay: bool
) -> dict[str, Any]:
    """A ``va.run`` loop of figure 7 built by ``build() -> (controller, simulator, q0, robot)``,
    its slow ticks replayed (a new build, the same ticks) when ``replay``."""
    controller, simulator, q0, robot = build()
    if not replay:
        return run_loop_ticks(controller, simulator, q0, ticks, robot)
    with TickEvents() as events:
        run = run_loop_ticks(controller, simulator, q0, ticks, robot, events)
    run["gc"] |= events.summary()
    replayed(run, events.slow, lambda n: _replayed_loop(build, n, False)["_cpu_us"])
    return run


def _ur5() -> tuple:
    from bench_arm_tracking import ToolTracker, start_pose

    import virtual_actuators as va
    from virtual_actuators.simulation import Simulator

    robot = va.load_robot("ur5")
    q0 = start_pose(robot)
    tracker = ToolTracker(robot, "tool0", q0, turn=True)
    tracker.controller.warm_up(q0)  # kernels loaded before the first tick
    return tracker, Simulator(robot), q0, robot


def ur5_tracking(ticks: int, replay: bool = True) -> dict[str, Any]:
    """The UR5's tool tracking a moving target (``bench_arm_tracking``'s 6-axis impedance with
    gravity compensation, the ``turn`` case) under ``va.run``."""
    return _replayed_loop(_ur5, ticks, replay)


def _go2() -> tuple:
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
    return gait, simulator, q0, None


def go2_standing(ticks: int, replay: bool = True) -> dict[str, Any]:
    """go2 standing on its four feet (the ``balance`` walk's :class:`Balancer`, no push) under
    ``va.run``."""
    return _replayed_loop(_go2, ticks, replay)


#: The ``va.run`` loops of figure 7: title -> runner(ticks).
RUN_LOOPS: dict[str, Callable[[int], dict[str, Any]]] = {
    "va.run UR5 tool tracking": ur5_tracking,
    "va.run go2 standing": go2_standing,
}
