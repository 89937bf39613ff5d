"""A controller's per-tick solve on the tick's snapshot against the general path, bit for bit.

A parallel attachment's distribution is answered by one call of the compiled core on the
snapshot's arrays, its [`Solution`][virtual_actuators.Solution] built straight from the buffer
(:class:`~virtual_actuators.distribution.partitioned.compiled.SnapshotSolve`). Every field must
equal what ``ParallelVirtualActuator.solve_checked`` returns for the same snapshot and request
(the dispatch over the backends, then ``Solution.from_tick``), and a controller's whole tick must
be the same with it and without it.
"""

from __future__ import annotations

import dataclasses
import threading

import numpy as np
import pytest
from oracles import random_configuration
from test_solve_fast_path import DECLARATIONS, _assert_same

import virtual_actuators as va
from virtual_actuators.control.tick import NO_LIMP
from virtual_actuators.core import CORE
from virtual_actuators.exceptions import VirtualActuatorError

pytestmark = pytest.mark.skipif(CORE is None, reason="virtual_actuators._core is not built")


def _plans(body: va.ParallelVirtualActuator):
    """The checked requests to try: no free axis, then each axis free in turn (when allowed)."""
    yield body.plan()
    for axis in body.axes:
        try:
            yield body.plan((axis,))
        except VirtualActuatorError:  # too many constraints for that free axis
            continue


def _snapshot(robot: va.Robot, rng: np.random.Generator) -> va.Snapshot:
    q = random_configuration(robot, rng, scale=0.4)
    snapshot = va.Snapshot(robot, q, rng.normal(size=robot.model.nv))
    snapshot.jacobian_world  # computed, as a controller's sensing leaves it  # noqa: B018
    return snapshot


@pytest.mark.parametrize("case", DECLARATIONS, ids=[c[0] for c in DECLARATIONS])
def test_the_snapshot_solve_gives_the_general_paths_bits(case):
    _, body = case
    rng = np.random.default_rng(5)
    decided = 0
    for plan in _plans(body):
        one_call = body.snapshot_solve(plan)
        assert one_call is not None, plan.free
        for k in range(20):
            snapshot = _snapshot(body.robot, rng)
            wrench = rng.normal(size=body.n) * rng.choice([1e-6, 1.0, 1e3, 1e200])
            tol = [1e-6, 0.0, 1e-3][k % 3]
            fast = one_call(snapshot, wrench, tol)
            try:
                general, missed = body.solve_checked(snapshot, wrench, plan, tol)
            except va.SingularConfigurationError:
                assert fast is None
                continue
            assert missed is (not general.admissible)
            if fast is not None:
                _assert_same(fast, general)
                decided += 1
    assert decided >= 20  # the one-call path ran, not only the general one


def test_a_snapshot_not_computed_yet_is_handed_on():
    body = DECLARATIONS[0][1]
    one_call = body.snapshot_solve(body.plan())
    snapshot = va.Snapshot(body.robot, body.robot.neutral(), np.zeros(body.robot.model.nv))
    wrench = np.array([2.0, 1.0, 25.0, 0.1, -0.2, 0.05])
    assert one_call(snapshot, wrench) is None
    assert not snapshot.computed  # the general path runs kinematics and solve in one call
    general = body.solve_checked(snapshot, wrench, body.plan())[0]
    snapshot.frame_table  # noqa: B018
    _assert_same(one_call(snapshot, wrench), general)


def test_only_the_compiled_partitioned_request_has_one():
    body = DECLARATIONS[0][1]
    assert body.snapshot_solve(body.plan(method="dense")) is None
    assert body.snapshot_solve(body.plan(method="qp")) is None
    assert body.snapshot_solve(body.plan(compiled=False)) is None
    assert "SnapshotSolve" in repr(body.snapshot_solve(body.plan()))


def test_threads_share_one_snapshot_solve():
    body = DECLARATIONS[0][1]
    one_call, plan = body.snapshot_solve(body.plan()), body.plan()
    rng = np.random.default_rng(3)
    cases = [(_snapshot(body.robot, rng), rng.normal(size=6) * 10.0) for _ in range(40)]
    expected = [body.solve_checked(s, w, plan)[0] for s, w in cases]
    errors = []

    def work() -> None:
        try:
            for _ in range(20):
                for (snapshot, wrench), general in zip(cases, expected, strict=True):
                    fast = one_call(snapshot, wrench)
                    if fast is not None:
                        _assert_same(fast, general)
        except AssertionError as error:  # reported by the main thread
            errors.append(error)

    threads = [threading.Thread(target=work) for _ in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert not errors


def _outputs_equal(a: va.ControlOutput, b: va.ControlOutput) -> None:
    for field in dataclasses.fields(va.ControlOutput):
        x, y = getattr(a, field.name), getattr(b, field.name)
        if field.name == "solutions":
            assert x.keys() == y.keys()
            for name in x:
                _assert_same(x[name], y[name])
        elif isinstance(y, np.ndarray):
            assert np.array_equal(x, y) and x.dtype == y.dtype, field.name
        elif isinstance(y, dict) and y and isinstance(next(iter(y.values())), np.ndarray):
            assert x.keys() == y.keys(), field.name
            assert all(np.array_equal(x[k], y[k]) for k in y), field.name
        else:
            assert x == y, field.name


@pytest.mark.parametrize("free", [(), ("rz",)])
def test_a_controller_tick_is_the_same_without_the_one_call_solve(free):
    robot = va.load_robot("solo12")
    body = va.ParallelVirtualActuator(
        robot, "base_link", ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"], "world"
    )
    controller = va.Controller(robot)
    height = va.SpringDamper(("z", "rx", "ry"), 300.0, 20.0, setpoint=(0.25, 0.0, 0.0))
    push = va.SpringDamper(("x", "y", "rz"), 50.0, 5.0)
    attachment = controller.add("body", body, [height, push], free=free)
    assert attachment.snapshot_solve is not None
    rng = np.random.default_rng(8)
    names, answered, one_call = ("body",), [], attachment.snapshot_solve

    def counting(snapshot, wrench):
        solution = one_call(snapshot, wrench)
        answered.append(solution is not None)
        return solution

    for _ in range(30):
        q = random_configuration(robot, rng, scale=0.3)
        v = rng.normal(size=robot.model.nv)
        attachment.snapshot_solve = counting
        fast = controller.compute_checked(va.Snapshot(robot, q, v), 0.1, names, NO_LIMP)
        attachment.snapshot_solve = None  # the general path: solve_checked
        try:
            general = controller.compute_checked(va.Snapshot(robot, q, v), 0.1, names, NO_LIMP)
        finally:
            attachment.snapshot_solve = one_call
        _outputs_equal(fast, general)
    assert sum(answered) >= 20  # the controller took the one-call solve


def _spring_body(robot: va.Robot):
    """solo12's body on its four feet with spring-dampers and a bunny (the one-call tick)."""
    body = va.ParallelVirtualActuator(
        robot, "base_link", ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"], "world"
    )
    return body, [
        va.SpringDamper(("y", "z", "rx"), 300.0, 20.0, setpoint=(0.0, 0.25, 0.0)),
        va.SpringDamper(("ry",), 30.0, 2.0, limit=1.0, name="level"),
        va.SpringDamper(("rz",), 20.0, 1.0, setpoint=0.2, name="heading"),
        va.DogtrackBunny(0.4, 60.0, stiffness=5.0, limit=25.0),
    ]


def test_the_fused_tick_is_the_spring_tick_then_the_snapshot_solve():
    """``_core.SpringSolve``: the spring tick's buffer and the distribution's, bit for bit."""
    robot = va.load_robot("solo12")
    body, components = _spring_body(robot)
    attachment = va.Controller(robot).add("body", body, components)
    spring = attachment.spring_tick
    assert spring.fused is not None and spring.solve is attachment.snapshot_solve
    rng = np.random.default_rng(2)
    solved = 0
    for k in range(40):
        snapshot = _snapshot(robot, rng)
        buffer, solution = spring.run_solve(components, snapshot, 0.05 * k)
        expected = spring.run_solve(components, snapshot, 0.05 * k, solve=False)[0]  # moved alike
        assert (buffer is None) == (expected is None)
        if buffer is None:
            assert solution is None
            continue
        assert np.array_equal(buffer, expected)
        general = body.solve_checked(snapshot, expected[spring.slices[2]], attachment.plan)[0]
        if solution is not None:
            _assert_same(solution, general)
            _assert_same(solution, attachment.snapshot_solve(snapshot, general.requested))
            solved += 1
    assert solved >= 30


def test_a_controller_tick_is_the_same_on_every_path():
    """The fused call, the spring tick then the one-call solve, and the general path agree."""
    robot = va.load_robot("solo12")
    outputs = []
    for path in ("fused", "spring tick, then the one-call solve", "general"):
        body, components = _spring_body(robot)
        controller = va.Controller(robot)
        attachment = controller.add("body", body, components)
        if path != "fused":
            attachment.spring_tick.fused = None
        if path == "general":
            attachment.spring_tick = attachment.snapshot_solve = None
        rng = np.random.default_rng(9)
        outputs.append(
            [
                controller.compute_checked(_snapshot(robot, rng), 0.02 * k, ("body",), NO_LIMP)
                for k in range(25)
            ]
        )
    for fused, other in zip(outputs[0], outputs[1], strict=True):
        _outputs_equal(fused, other)
    for fused, other in zip(outputs[0], outputs[2], strict=True):
        _outputs_equal(fused, other)
