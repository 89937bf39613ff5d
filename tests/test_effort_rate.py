"""The controller's optional effort rate limit (control.effort_limits): a safety net for motors."""

from __future__ import annotations

import numpy as np
import pytest

import virtual_actuators as va
from virtual_actuators.control.effort_limits import LimitFraction

PERIOD = 1e-3  # [s]


@pytest.fixture(scope="module")
def ur5():
    return va.load_robot("ur5")


def _tool_spring(robot, **options):
    """A stiff tool spring whose set point the test moves: a step in every effort."""
    controller = va.Controller(robot, **options)
    tool = va.VirtualActuator(robot, "tool0", "world", "world", ("x", "y", "z"))
    spring = va.SpringDamper(("x", "y", "z"), 4000.0, 0.0)
    controller.add("tool", tool, [spring])
    return controller, spring


def test_each_tick_moves_at_most_the_rate_times_the_period(ur5):
    rate = 5000.0  # [N m/s]: 5 N m a tick, against a step of up to 67 N m
    controller, spring = _tool_spring(ur5, effort_rate_limit=rate)
    q, v = np.array([0.3, -1.2, 1.4, -0.8, 1.1, 0.2]), np.zeros(6)
    spring.setpoint = controller.attachments["tool"].sensor.position(q)
    first = controller.compute(q, v, 0.0)
    assert not first.rate_limited.any()  # the first tick is free
    spring.setpoint = spring.setpoint + np.array([0.02, -0.01, 0.03])  # a step of ~100 N
    previous = first.tau
    for tick in range(1, 30):
        output = controller.compute(q, v, tick * PERIOD)
        change = np.abs(output.tau - previous)
        assert (change <= rate * PERIOD * (1 + 1e-12)).all()
        held = change > rate * PERIOD * (1 - 1e-9)
        assert np.array_equal(output.rate_limited, held)
        previous = output.tau
    assert output.rate_limited_joints == []  # caught up: the request is met again
    assert np.allclose(output.tau, output.tau_requested)
    assert "rate_limited" not in repr(output)


def test_a_fraction_of_the_limit_follows_the_limits_and_a_dict_names_joints(ur5):
    controller, spring = _tool_spring(ur5, effort_rate_limit=LimitFraction(10.0))
    q, v = np.array([0.3, -1.2, 1.4, -0.8, 1.1, 0.2]), np.zeros(6)
    controller.effort_limits = np.full(6, 50.0)  # the rates follow: 500 N m/s
    spring.setpoint = controller.attachments["tool"].sensor.position(q)
    start = controller.compute(q, v, 0.0).tau
    spring.setpoint = spring.setpoint + 0.05
    output = controller.compute(q, v, 2 * PERIOD)
    assert np.abs(output.tau - start).max() == pytest.approx(500.0 * 2 * PERIOD)
    controller.effort_rate_limit = {"shoulder_lift_joint": 1.0}
    controller.reset_effort_rate(start, 2 * PERIOD)
    output = controller.compute(q, v, 3 * PERIOD)
    assert output.rate_limited_joints == ["shoulder_lift_joint"]
    assert abs(output.tau[1] - start[1]) == pytest.approx(1e-3)


def test_a_new_run_is_free_and_the_same_time_repeats(ur5):
    controller, spring = _tool_spring(ur5, effort_rate_limit=100.0)
    q, v = np.array([0.3, -1.2, 1.4, -0.8, 1.1, 0.2]), np.zeros(6)
    spring.setpoint = controller.attachments["tool"].sensor.position(q)
    controller.compute(q, v, 5.0)
    spring.setpoint = spring.setpoint + 0.05
    again = controller.compute(q, v, 5.0)  # no time: no change
    assert again.rate_limited.any() and np.allclose(again.tau, 0.0, atol=1e-9)
    restart = controller.compute(q, v, 0.0)  # time went back: a new run
    assert not restart.rate_limited.any()
    controller.reset_effort_rate()  # free again
    assert not controller.compute(q, v, 0.1).rate_limited.any()


@pytest.mark.parametrize(
    "value, match",
    [
        (0.0, "effort_rate_limit"),
        (-1.0, "effort_rate_limit"),
        (float("nan"), "effort_rate_limit"),
        ([1.0, 2.0], "shape"),
        ("fast", "effort_rate_limit"),
        ({"shoulder_lift_joint": -2.0}, "shoulder_lift_joint"),
    ],
)
def test_bad_rate_limits_name_the_argument(ur5, value, match):
    with pytest.raises(va.InvalidInputError, match=match):
        va.Controller(ur5, effort_rate_limit=value)


def test_unknown_joints_and_missing_limits_are_typed_errors(ur5):
    with pytest.raises(va.JointNotFoundError, match="shoulder_lift_joint"):
        va.Controller(ur5, effort_rate_limit={"shoulder_lift": 1.0})
    with pytest.raises(va.InvalidInputError, match="per_second"):
        LimitFraction(0.0)
    with pytest.raises(va.InvalidInputError, match="no effort_rate_limit"):
        va.Controller(ur5).reset_effort_rate()
    controller = va.Controller(ur5, effort_rate_limit=1.0)
    with pytest.raises(va.InvalidInputError, match="6 finite numbers"):
        controller.reset_effort_rate(np.zeros(5))
    with pytest.raises(va.InvalidInputError, match="time"):
        controller.reset_effort_rate(np.zeros(6), float("inf"))


class _Recorder:
    """Sets the limit after the first tick, then records every tick's change of effort."""

    def __init__(self, fraction: LimitFraction) -> None:
        self.fraction, self.last, self.changes = fraction, None, []

    def __call__(self, simulator, gait) -> None:
        controller, tau = gait.controller, gait.last.tau.copy()
        if self.last is None:
            controller.effort_rate_limit = self.fraction
            controller.reset_effort_rate(tau, simulator.time - PERIOD)
        else:
            self.changes.append(np.abs(tau - self.last) / controller.effort_limits)
        self.last = tau


@pytest.mark.slow
def test_a_walk_under_a_rate_limit_keeps_it_on_every_tick():
    pytest.importorskip("mujoco")
    from virtual_actuators.gaits.registry import run_walk

    recorder = _Recorder(LimitFraction(40.0))  # [1/s]: the full effort in 25 ms at least
    result = run_walk("legged", robot="go2", duration=1.5, progress=False, on_tick=recorder)
    assert not result.metrics.fell
    changes = np.array(recorder.changes)[:, np.isfinite(result.gait.controller.effort_limits)]
    assert len(changes) > 1400
    assert changes.max() <= 40.0 * PERIOD * (1 + 1e-9)


def test_a_compiled_gait_keeps_the_rate_limit():
    from virtual_actuators.gaits.turkey.walker import TurkeyWalker

    gait = TurkeyWalker(va.load_robot("spring_turkey"))
    q, v = gait.initial_configuration(), np.zeros(gait.robot.model.nv)
    first = gait.compute(q, v, 0.0).tau.copy()
    if gait.compiled is None:
        pytest.skip("no compiled core")
    gait.controller.effort_rate_limit = 1.0  # [N m/s]: 1 mN m per tick
    gait.controller.reset_effort_rate(first, 0.0)
    moving = v.copy()
    moving[1] = -0.3  # the body falls at 0.3 m/s: the granny walker's damper pushes at once
    output = gait.compute(q, moving, PERIOD)
    assert output.rate_limited.any()
    assert np.abs(output.tau - first).max() <= 1.0 * PERIOD * (1 + 1e-9)
