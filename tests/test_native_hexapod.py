"""The hexapod's native tick (the compiled core's ``NativeHexapod``) against the Python gait.

Oracle: the Python `HexapodWalker` itself, run tick by tick on the same states. The native tick
does the same floating-point operations in the same order (the body's components, the QP on the
last certified active set, the swing legs, the tripod kernel), so every channel of a walk's log,
the machine's history and the gait's memory agree bit for bit; the ticks it hands on (a tripod's
entry, a QP whose active set changes) run in Python between two synchronisations.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from oracles import assert_same_walk

from virtual_actuators.core import CORE
from virtual_actuators.exceptions import InvalidInputError
from virtual_actuators.gaits.hexapod.native import NativeTick, read_memory
from virtual_actuators.gaits.hexapod.parameters import HexapodParameters
from virtual_actuators.gaits.hexapod.walk import hexapod_robot
from virtual_actuators.gaits.hexapod.walker import HexapodWalker
from virtual_actuators.gaits.registry import WALKS, run_walk
from virtual_actuators.models.loader import load_robot
from virtual_actuators.simulation.simulator import Simulator

pytestmark = pytest.mark.skipif(
    CORE is None or not hasattr(CORE, "NativeHexapod"), reason="the compiled core is not built"
)

WALK = WALKS["hexapod-walk"]


def _python(simulator, gait) -> None:  # an on_tick callback: the runner keeps the Python tick
    pass


@pytest.fixture(scope="module")
def walks():
    """A 3 s turning hexapod walk with the native tick, and the same walk in Python."""
    options = {"duration": 3.0, "progress": False, "yaw_rate": 0.2}
    native = run_walk("hexapod-walk", **options)
    python = run_walk("hexapod-walk", on_tick=_python, **options)
    return native, python


def test_walk_log_is_the_python_walks_bit_for_bit(walks):
    native, python = walks
    assert_same_walk(native, python)
    assert len(native.gait.machine.history) >= 9  # both tripods' stances, several times


def test_gait_memory_after_the_walk_is_the_python_gaits(walks):
    native, python = walks
    for mine, theirs in zip(read_memory(native.gait), read_memory(python.gait), strict=True):
        np.testing.assert_array_equal(mine, theirs)


def _started_gait(robot=None, **parameters):
    robot = robot or load_robot("hexapod")
    gait = HexapodWalker(robot, HexapodParameters(**parameters))
    simulator = Simulator(robot)
    simulator.reset(gait.initial_configuration())
    gait.compute(simulator.q, simulator.v, 0.0)  # the machine starts in Python
    return robot, gait, simulator


def _switches(gait, simulator) -> dict[str, bool]:
    touching = simulator.touching_frames()
    return {foot: foot in touching for foot in gait.contact_frames}


def test_ticks_match_the_python_gait_tick_by_tick():
    """Both gaits on the same states and commands: the same efforts and wrenches, every tick."""
    robot, gait, simulator = _started_gait()
    reference = HexapodWalker(robot)
    reference.compute(simulator.q, simulator.v, 0.0)
    native = NativeTick.of(gait)
    assert native is not None
    ticks, cold = 1500, 700
    for tick in range(1, ticks):
        q, v, now = simulator.q, simulator.v, tick * simulator.control_period
        if tick == cold:  # the QPs start cold: their next solves run DAQP, in Python
            before = native.deferred
            native.sync()  # the gait's Python objects up to the core's memory, then changed
            for walker in (gait, reference):
                for name in ("support_a", "support_b", "support_all"):
                    walker.controller.attachments[name].actuator.qp.reset()
            native.load()  # the core takes up the gait's Python objects as they are now
        command = (0.4 * min(1.0, now), 0.05 * math.sin(now))  # an accelerating, wavy command
        for walker in (gait, reference):
            walker.set_command(command, 0.3 * math.cos(2.0 * now))
        contacts = _switches(gait, simulator)
        output = native.compute(q, v, now, contacts)
        expected = reference.compute(q, v, now, contacts)
        np.testing.assert_array_equal(output.tau, expected.tau, err_msg=f"tick {tick}")
        assert output.active == expected.active
        for name, wrench in output.wrenches.items():
            np.testing.assert_array_equal(wrench, expected.wrenches[name])
        simulator.step(output.tau, ignore_unactuated=True)
        if tick == cold:
            assert native.deferred == before + 1
    assert gait.machine.history == reference.machine.history
    assert len(gait.machine.history) >= 6
    assert native.deferred < ticks // 10  # most ticks are the core's
    native.sync()
    for mine, theirs in zip(read_memory(gait), read_memory(reference), strict=True):
        np.testing.assert_array_equal(mine, theirs)


def test_a_non_finite_state_gets_the_python_ticks_typed_error():
    _, gait, simulator = _started_gait()
    native = NativeTick.of(gait)
    q = simulator.q
    q[0] = math.nan
    with pytest.raises(InvalidInputError):
        native.compute(q, simulator.v, 0.001)
    assert native.deferred == 1
    output = native.compute(simulator.q, simulator.v, 0.001)  # the core's again
    assert native.deferred == 1 and np.all(np.isfinite(output.tau))


def test_ticks_handed_on_after_the_bodys_qp_are_the_python_ticks():
    """A swing leg whose wrench overflows: the core hands the tick on after the body's QP
    certified its answer; the Python ticks decide, from the state the core left."""
    robot, gait, simulator = _started_gait()
    reference = HexapodWalker(robot)
    reference.compute(simulator.q, simulator.v, 0.0)
    native = NativeTick.of(gait)
    period, tick = simulator.control_period, 0
    while tick < 400 or not gait.state.startswith("tripod"):
        tick += 1
        contacts = _switches(gait, simulator)
        output = native.compute(simulator.q, simulator.v, tick * period, contacts)
        reference.compute(simulator.q, simulator.v, tick * period, contacts)
        simulator.step(output.tau, ignore_unactuated=True)
    native.sync()
    for walker in (gait, reference):  # 3e308 N in all: not finite
        walker.swing[2 if gait.support == "a" else 1].force = np.full(3, 1e308)
    native.load()
    deferred, start = native.deferred, tick + 1
    for later in range(start, start + 20):
        contacts = _switches(gait, simulator)
        output = native.compute(simulator.q, simulator.v, later * period, contacts)
        expected = reference.compute(simulator.q, simulator.v, later * period, contacts)
        np.testing.assert_array_equal(output.tau, expected.tau)
        simulator.step(output.tau, ignore_unactuated=True)
    assert native.deferred > deferred


def test_no_native_tick_for_a_partitioned_body_a_pendulum_or_an_unstarted_machine():
    assert NativeTick.of(HexapodWalker(load_robot("hexapod"))) is None  # first tick: Python's
    assert NativeTick.of(_started_gait(distribution="partitioned")[1]) is None
    assert NativeTick.of(_started_gait(hexapod_robot(pendulum=True))[1]) is None


def test_repr_names_the_attachments():
    _, gait, _ = _started_gait()
    text = repr(NativeTick.of(gait))
    assert "support_all" in text and "deferred=0" in text
