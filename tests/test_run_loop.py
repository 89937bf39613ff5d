"""va.run: the hardware loop on a MuJoCo arm, and its safety rules (stale, non-finite, errors)."""

from __future__ import annotations

import numpy as np
import pytest

import virtual_actuators as va
from virtual_actuators.control import run_loop
from virtual_actuators.simulation import MujocoHardware, Simulator


class ArmController:
    """UR5: a Cartesian spring-damper on the tool plus gravity compensation."""

    def __init__(self, robot: va.Robot, target: np.ndarray) -> None:
        self.robot = robot  # va.run writes this robot's (nv,) efforts
        self.controller = va.Controller(robot)
        tool = va.VirtualActuator(robot, "tool0", "world", "world", ("x", "y", "z"))
        self.spring = va.SpringDamper(("x", "y", "z"), 400.0, 40.0, setpoint=target)
        self.controller.add("tool", tool, [self.spring])
        self.gravity = va.GravityCompensation(robot)

    def compute(self, q, v, time):
        return self.controller.compute(q, v, time).tau + self.gravity.torques(q)


@pytest.mark.slow
def test_runs_an_arm_to_its_target_in_mujoco():
    robot = va.load_robot("ur5_robot")
    q0 = robot.q(shoulder_lift_joint=-1.0, elbow_joint=1.3, wrist_1_joint=-0.8)
    simulator = Simulator(robot)
    simulator.reset(q0)
    tool = va.VirtualActuator(robot, "tool0", "world", "world", ("x", "y", "z"))
    target = tool.position(q0) + np.array([0.05, -0.04, 0.03])  # [m]
    hardware = MujocoHardware(simulator)
    stats = va.run(
        ArmController(robot, target),
        hardware.read_state,
        hardware.write_effort,
        rate_hz=1000.0,
        realtime=False,
        should_stop=lambda: simulator.time >= 2.0 - 1e-9,
    )
    assert stats.ticks == 2000 and stats.zero_ticks == stats.failed_ticks == 0
    assert hardware.efforts_written == 2001  # and one zero effort at the end
    assert np.linalg.norm(tool.position(simulator.q) - target) < 1e-3  # [m] (0.3 mm measured)
    assert "ticks" in stats.summary()


def test_the_controller_is_warmed_up_before_the_first_reading_with_the_same_efforts(
    monkeypatch,
):
    """va.run warms up the va.Controller an object drives (``controller``) once, before its
    first reading; the efforts are the same bits as without the warm-up."""
    robot = va.load_robot("ur5_robot")
    q0 = robot.q(shoulder_lift_joint=-1.0, elbow_joint=1.3, wrist_1_joint=-0.8)
    tool = va.VirtualActuator(robot, "tool0", "world", "world", ("x", "y", "z"))
    target = tool.position(q0) + np.array([0.05, -0.04, 0.03])  # [m]
    events, efforts = [], {}
    warm_up = va.Controller.warm_up
    monkeypatch.setattr(va.Controller, "warm_up",
                        lambda self, q: (events.append("warm-up"), warm_up(self, q)))  # fmt: skip
    for warmed in (True, False):
        if not warmed:
            monkeypatch.setattr(run_loop, "warm_up_driven", lambda controller, robot: None)
        simulator = Simulator(robot)
        simulator.reset(q0)
        hardware, written = MujocoHardware(simulator), []

        def read_state(hardware=hardware):
            events.append("read")
            return hardware.read_state()

        def write_effort(tau, hardware=hardware, written=written):
            written.append(np.array(tau))
            hardware.write_effort(tau)

        va.run(ArmController(robot, target), read_state, write_effort, realtime=False,
               should_stop=lambda simulator=simulator: simulator.time >= 0.3 - 1e-9)  # fmt: skip
        efforts[warmed] = np.array(written)
    assert events[0] == "warm-up" and events.count("warm-up") == 1
    assert len(efforts[True]) == 301 and np.array_equal(efforts[True], efforts[False])


class Scripted:
    """read_state / write_effort that replay a script and record what was written."""

    def __init__(self, states):
        self.states, self.written, self.k = states, [], 0

    def read_state(self):
        state = self.states[min(self.k, len(self.states) - 1)]
        self.k += 1
        return state

    def write_effort(self, tau):
        self.written.append(np.array(tau))


PENDULUM = va.load_robot("double_pendulum")  # nq = nv = 2


class Constant:
    robot = PENDULUM

    def compute(self, q, v, time):
        return np.ones(len(v))


def test_zero_effort_on_stale_and_non_finite_readings_and_at_the_end():
    good = (np.zeros(2), np.zeros(2))
    states = [(*good, 0.0), (*good, 0.001), (np.array([np.nan, 0.0]), np.zeros(2), 0.002)]
    states += [(*good, 0.003)] * 30  # the stamp stops advancing: stale after 3 periods
    io = Scripted(states)
    # stop on the count of readings, not on the wall clock: on a loaded machine a 30 ms
    # duration can end before the stamp has been still for three periods
    stats = va.run(
        Constant(), io.read_state, io.write_effort, rate_hz=1000.0, should_stop=lambda: io.k >= 25
    )
    assert np.array_equal(io.written[0], np.ones(2))
    assert np.array_equal(io.written[2], np.zeros(2))  # NaN reading
    assert stats.reasons.get("non-finite") == 1
    assert stats.reasons.get("stale", 0) >= 1
    assert np.array_equal(io.written[-1], np.zeros(2))  # the loop ends on zero effort
    assert stats.ticks + 1 == len(io.written)


def test_a_failing_controller_sends_zero():
    class Failing:
        robot = PENDULUM

        def compute(self, q, v, time):
            raise va.SingularConfigurationError("straight knee")

    io = Scripted([(np.zeros(2), np.zeros(2), 0.001 * k) for k in range(100)])
    stats = va.run(Failing(), io.read_state, io.write_effort, rate_hz=2000.0, duration=0.01)
    assert stats.zero_ticks == stats.failed_ticks == stats.ticks > 0
    assert stats.reasons == {"controller error: SingularConfigurationError": stats.ticks}
    assert all(tau.shape == (2,) and not tau.any() for tau in io.written)


def test_bad_arguments():
    io = Scripted([(np.zeros(2), np.zeros(2), 0.0)])
    with pytest.raises(va.InvalidInputError, match="rate_hz"):
        va.run(Constant(), io.read_state, io.write_effort, rate_hz=0.0, duration=1.0)
    with pytest.raises(va.InvalidInputError, match="duration or a should_stop"):
        va.run(Constant(), io.read_state, io.write_effort)
    with pytest.raises(va.InvalidInputError, match="compute"):
        va.run(object(), io.read_state, io.write_effort, duration=1.0)
    with pytest.raises(va.InvalidInputError, match="write_effort"):
        va.run(Constant(), io.read_state, None, duration=1.0)


def test_any_controller_failure_sends_zero_and_the_end_is_zero_even_on_interrupt():
    class Flaky:
        robot = PENDULUM

        def __init__(self):
            self.calls = 0

        def compute(self, q, v, time):
            self.calls += 1
            if self.calls == 2:
                raise TypeError("a bug in the law")
            if self.calls == 4:
                return np.ones(5)  # wrong size
            if self.calls == 6:
                raise KeyboardInterrupt
            return np.ones(2)

    io = Scripted([(np.zeros(2), np.zeros(2), 0.001 * k) for k in range(100)])
    with pytest.raises(KeyboardInterrupt):
        va.run(Flaky(), io.read_state, io.write_effort, rate_hz=1000.0, duration=1.0)
    written = [tau.tolist() for tau in io.written]
    assert written[:5] == [[1, 1], [0, 0], [1, 1], [0, 0], [1, 1]]
    assert written[-1] == [0.0, 0.0]  # the interrupt still ends on zero effort


def test_a_nan_stamp_is_not_taken_as_the_clock():
    states = [(np.zeros(2), np.zeros(2), float("nan"))]
    states += [(np.zeros(2), np.zeros(2), 0.001 * k) for k in range(1, 40)]
    io = Scripted(states)
    stats = va.run(Constant(), io.read_state, io.write_effort, rate_hz=1000.0, duration=0.03)
    assert stats.reasons == {"non-finite": 1}
    assert stats.zero_ticks == 1
