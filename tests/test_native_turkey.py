"""The turkey's native tick (the compiled core's ``NativeTurkey``) against the Python gait.

Oracle: the Python `TurkeyWalker` itself, run tick by tick on the same states. The native tick
does the same floating-point operations in the same order, so every channel of a walk's log, the
machine's history and the gait's memory agree bit for bit, including the start-up ticks where
the double support's request is scaled on its yield axis and the state changes.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from oracles import assert_same_walk

import virtual_actuators as va
from virtual_actuators.exceptions import InvalidInputError
from virtual_actuators.gaits.registry import WALKS, run_walk
from virtual_actuators.gaits.turkey.native import NativeTick
from virtual_actuators.models.loader import load_robot
from virtual_actuators.native import CORE
from virtual_actuators.simulation.simulator import Simulator

pytestmark = pytest.mark.skipif(CORE is None, reason="the compiled core is not built")

WALK = WALKS["turkey-walk"]


def _python(simulator, gait) -> None:  # an on_tick callback: the runner keeps the Python tick
    pass


@pytest.fixture(scope="module")
def walks():
    """A 2.5 s turkey walk with the native tick, and the same walk in Python."""
    native = run_walk("turkey-walk", duration=2.5, progress=False)
    python = run_walk("turkey-walk", duration=2.5, progress=False, on_tick=_python)
    return native, python


def test_walk_log_is_the_python_walks_bit_for_bit(walks):
    native, python = walks
    assert_same_walk(native, python)
    assert len(native.gait.machine.history) >= 5  # double support and both single supports


def test_gait_memory_after_the_walk_is_the_python_gaits(walks):
    native, python = walks
    assert native.gait.memory() == python.gait.memory()
    assert native.gait.state == python.gait.state
    for side in ("left", "right"):
        np.testing.assert_array_equal(
            native.gait.swing[side].velocity_setpoint, python.gait.swing[side].velocity_setpoint
        )


def _started_gait():
    robot = load_robot(WALK.robot)
    gait = WALK.make_gait(robot, None)
    simulator = Simulator(robot)
    simulator.reset(gait.initial_configuration())
    gait.compute(simulator.q, simulator.v, 0.0)  # the machine starts in Python
    return robot, gait, simulator


def test_ticks_match_the_python_gait_tick_by_tick_with_the_yield_scaling():
    """Both gaits on the same states: the native efforts are the Python ones, every tick."""
    robot, gait, simulator = _started_gait()
    reference = WALK.make_gait(robot, None)
    reference.compute(simulator.q, simulator.v, 0.0)
    native = NativeTick.of(gait)
    assert native is not None
    for tick in range(1, 400):  # the start-up: the double support's request scaled on x
        q, v, now = simulator.q, simulator.v, tick * 1e-3
        output, expected = native.compute(q, v, now), reference.compute(q, v, now)
        np.testing.assert_array_equal(output.tau, expected.tau)
        assert output.active == expected.active
        for name, wrench in output.wrenches.items():
            np.testing.assert_array_equal(wrench, expected.wrenches[name])
        simulator.step(output.tau)
    assert native.deferred == 0
    native.sync()
    assert gait.memory() == reference.memory()


def test_a_non_finite_state_gets_the_python_ticks_typed_error():
    _, gait, simulator = _started_gait()
    native = NativeTick.of(gait)
    q = simulator.q
    q[0] = math.nan
    with pytest.raises(InvalidInputError):
        native.compute(q, simulator.v, 0.001)
    assert native.deferred == 1


def test_no_native_tick_for_a_qp_double_support_or_an_unstarted_machine():
    robot = load_robot(WALK.robot)
    gait = WALK.make_gait(robot, None)
    assert NativeTick.of(gait) is None  # its machine starts on its first (Python) tick
    parameters = WALK.parameters(distribution="qp")
    qp_gait = WALK.make_gait(robot, None, parameters)
    simulator = Simulator(robot)
    simulator.reset(qp_gait.initial_configuration())
    qp_gait.compute(simulator.q, simulator.v, 0.0)
    assert NativeTick.of(qp_gait) is None
    assert WALKS["flamingo-slopes"].native is None


def test_repr_names_the_attachments():
    _, gait, _ = _started_gait()
    text = repr(NativeTick.of(gait))
    assert "double" in text and "deferred=0" in text


def test_a_tick_from_a_second_thread_at_once_raises_a_typed_error():
    import threading

    _, gait, simulator = _started_gait()
    native = NativeTick.of(gait)
    inside, release = threading.Event(), threading.Event()
    original = native.core

    class Slow:  # the core's tick, held open until the other thread has tried
        def __getattr__(self, name):
            return getattr(original, name)

        def tick(self, *args):
            inside.set()
            release.wait(5.0)
            return original.tick(*args)

    native.core = Slow()
    worker = threading.Thread(target=native.compute, args=(simulator.q, simulator.v, 0.001))
    worker.start()
    assert inside.wait(5.0)
    try:
        with pytest.raises(va.ConcurrentUseError, match="another thread"):
            native.compute(simulator.q, simulator.v, 0.001)
    finally:
        release.set()
        worker.join()
    native.core = original
    assert native.compute(simulator.q, simulator.v, 0.002).tau.shape == (robot_nv(gait),)


def robot_nv(gait) -> int:
    return gait.robot.model.nv


def test_a_falling_walk_is_the_python_walks_bit_for_bit():
    """Too fast (1.5 m/s, forced): the turkey falls; the native run falls at the same tick."""
    options = {"duration": 2.0, "progress": False, "speed": 1.5, "force_speed": True}
    native = run_walk("turkey-walk", **options)
    python = run_walk("turkey-walk", on_tick=_python, **options)
    assert native.metrics.fell and native.metrics.fall_time_s == python.metrics.fall_time_s
    assert_same_walk(native, python)
