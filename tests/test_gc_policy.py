"""The control loops' garbage-collection policy: no collection inside a tick, the collector
restored afterwards, garbage still collected, no tracked objects piling up tick after tick."""

from __future__ import annotations

import gc
import weakref

import numpy as np
import pytest

import virtual_actuators as va
from virtual_actuators.control.gc_policy import GC_POLICIES, LoopCollector

PENDULUM = va.load_robot("double_pendulum")  # nq = nv = 2


class Cycle:
    """A reference cycle: only the garbage collector frees it."""

    def __init__(self) -> None:
        self.me = self


class CycleMaker:
    """A controller that leaves garbage cycles behind every tick and watches the collector."""

    robot = PENDULUM

    def __init__(self, per_tick: int = 50) -> None:
        self.per_tick, self.inside, self.ticks = per_tick, False, 0
        self.made: weakref.WeakSet = weakref.WeakSet()
        self.collections_inside = 0
        self.states: set[tuple[bool, bool]] = set()  # (collector enabled, anything frozen)

    def on_collection(self, phase: str, info: dict) -> None:
        if phase == "start" and self.inside:
            self.collections_inside += 1

    def compute(self, q, v, time):
        self.inside = True
        self.states.add((gc.isenabled(), gc.get_freeze_count() > 0))
        for _ in range(self.per_tick):
            self.made.add(Cycle())
        self.ticks += 1
        self.inside = False
        return np.zeros(2)


def _run(controller, ticks: int, **options) -> va.RunStats:
    reading = (np.zeros(2), np.zeros(2))
    clock = iter(range(10**9))
    gc.callbacks.append(controller.on_collection)
    try:
        return va.run(
            controller, lambda: (*reading, 1e-3 * next(clock)), lambda tau: None,
            realtime=False, should_stop=lambda: controller.ticks >= ticks, **options,
        )  # fmt: skip
    finally:
        gc.callbacks.remove(controller.on_collection)


def test_no_collection_inside_a_tick_and_the_garbage_is_still_collected():
    enabled, frozen = gc.isenabled(), gc.get_freeze_count()
    quiet = CycleMaker()
    _run(quiet, 400)  # 20,000 cycles: many times CPython's young threshold (700)
    assert quiet.collections_inside == 0
    assert quiet.states == {(False, True)}  # automatic collector off, the set-up frozen
    assert len(quiet.made) < quiet.per_tick * 400 / 4  # collected between ticks
    assert (gc.isenabled(), gc.get_freeze_count()) == (enabled, frozen)  # restored
    # the same controller with CPython's own policy: collections land inside ticks
    loud = CycleMaker()
    _run(loud, 400, gc_policy="python")
    if enabled:
        assert loud.collections_inside > 0
        assert loud.states == {(True, frozen > 0)}


def test_the_collector_is_restored_when_the_loop_is_interrupted():
    class Interrupted(CycleMaker):
        def compute(self, q, v, time):
            if self.ticks == 3:
                raise KeyboardInterrupt
            return super().compute(q, v, time)

    enabled, frozen = gc.isenabled(), gc.get_freeze_count()
    with pytest.raises(KeyboardInterrupt):
        _run(Interrupted(), 10)
    assert (gc.isenabled(), gc.get_freeze_count()) == (enabled, frozen)


def test_a_controller_tick_leaves_no_tracked_objects_behind():
    # a real controller: a joint spring-damper on the double pendulum
    controller = va.Controller(PENDULUM)
    controller.add("hold", va.Posture(PENDULUM.joint_names, 20.0, 2.0, np.zeros(2)))
    counts: dict[int, int] = {}
    ticks = [0]

    def should_stop() -> bool:
        ticks[0] += 1
        if ticks[0] in (200, 400):
            gc.collect()
            counts[ticks[0]] = len(gc.get_objects())
        return ticks[0] >= 400

    rng = np.random.default_rng(1)
    readings = [(rng.normal(size=2), rng.normal(size=2)) for _ in range(8)]
    stamp = iter(range(10**9))

    def read_state():
        k = next(stamp)
        return (*readings[k % 8], 1e-3 * k)

    va.run(controller, read_state, lambda tau: None, realtime=False, should_stop=should_stop)
    assert counts[400] == counts[200]


def test_bad_policy():
    with pytest.raises(va.InvalidInputError, match="gc_policy"):
        _run(CycleMaker(), 1, gc_policy="never")
    with pytest.raises(va.InvalidInputError, match="gc_policy"):
        LoopCollector("off")
    assert "between-ticks" in GC_POLICIES


def test_a_walk_runs_with_the_collector_paused_and_restores_it():
    from virtual_actuators.demos import run_walk

    enabled, frozen = gc.isenabled(), gc.get_freeze_count()
    seen = set()
    run_walk(
        "turkey-walk", duration=0.05, progress=False,
        on_tick=lambda simulator, gait: seen.add((gc.isenabled(), gc.get_freeze_count() > 0)),
    )  # fmt: skip
    assert seen == {(False, True)}
    assert (gc.isenabled(), gc.get_freeze_count()) == (enabled, frozen)
