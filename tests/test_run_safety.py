"""va.run's safety contract: efforts of the robot's size, readings checked against the robot,
a safe action on every failure, and always a final zero effort (issue 24, items 8, 9, 11, 14).

The drivers here are recording fakes of the user's hardware interface (``read_state`` /
``write_effort``); the robots and the closed-loop check are real (Pinocchio, MuJoCo).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import virtual_actuators as va
from virtual_actuators.control import run_loop
from virtual_actuators.control.safe_action import DEFAULT_DAMPING
from virtual_actuators.simulation import MujocoHardware, Simulator

PENDULUM = va.load_robot("double_pendulum")  # nq = nv = 2
SOLO = va.load_robot("solo12")  # nq = 19 (a unit quaternion), nv = 18


class Driver:
    """Replays readings (or raises the exceptions among them) and records every write."""

    def __init__(self, readings):
        self.readings, self.written, self.k = list(readings), [], 0

    def read_state(self):
        reading = self.readings[min(self.k, len(self.readings) - 1)]
        self.k += 1
        if isinstance(reading, BaseException):
            raise reading
        return reading

    def write_effort(self, tau):
        self.written.append(np.array(tau, copy=True))


class Law:
    """A control law of the robot: ``effort(k, q, v)`` on call k, or an exception to raise."""

    def __init__(self, robot, effort):
        self.robot, self.effort, self.calls = robot, effort, 0

    def compute(self, q, v, time):
        self.calls += 1
        result = self.effort(self.calls, q, v)
        if isinstance(result, BaseException):
            raise result
        return result


def good(k: int, robot=PENDULUM):
    q = robot.neutral()
    return q, np.full(robot.model.nv, 0.1), 0.001 * k


def run(law, driver, ticks: int, **options):
    """``ticks`` ticks back to back (stopped by a tick counter, not by the clock)."""
    count = iter(range(ticks + 1))
    options.setdefault("stale_after", 60.0)  # no reading is stale on a slow machine
    return va.run(
        law,
        driver.read_state,
        driver.write_effort,
        realtime=False,
        should_stop=lambda: next(count) == ticks,
        **options,
    )


def test_effort_size_comes_from_the_robot_not_the_first_reading():
    readings = [(np.zeros(3), np.zeros(3), 0.0)] + [good(k) for k in range(1, 5)]
    driver = Driver(readings)
    stats = run(Law(PENDULUM, lambda k, q, v: np.ones(2)), driver, 5)
    assert [tau.shape for tau in driver.written] == [(2,)] * 6
    assert stats.reasons == {"malformed reading": 1}
    assert not driver.written[0].any() and not driver.written[-1].any()
    assert all(np.array_equal(tau, np.ones(2)) for tau in driver.written[1:5])


@pytest.mark.parametrize(
    "first", [OSError("bus off"), None, (np.zeros(2), np.zeros(2)), "garbage", KeyboardInterrupt()]
)
def test_a_failing_first_reading_still_ends_on_zero_effort(first):
    driver = Driver([first] + [good(k) for k in range(1, 4)])
    law = Law(PENDULUM, lambda k, q, v: np.ones(2))
    if isinstance(first, KeyboardInterrupt):
        with pytest.raises(KeyboardInterrupt):
            run(law, driver, 3)
        assert len(driver.written) == 1  # nothing but the final zero
    else:
        stats = run(law, driver, 3)
        reason = "read error: OSError" if isinstance(first, OSError) else "malformed reading"
        assert stats.reasons == {reason: 1}
        assert len(driver.written) == 4
    assert driver.written[-1].shape == (2,) and not driver.written[-1].any()


def test_every_reading_is_checked_against_the_robot():
    q, v, _ = good(0, SOLO)
    far = q.copy()
    far[3:7] = (0.0, 0.0, 0.0, 1.2)  # a quaternion 20 % off unit norm
    near = q.copy()
    near[3:7] = (0.0, 0.0, 0.0, 1.0 + 1e-4)  # within the checks' 1e-3: normalised
    nan_v = v.copy()
    nan_v[4] = np.nan
    readings = [
        (q, v, 0.000),
        (q[:-1], v, 0.001),  # nq - 1 entries
        (q, v[:-1], 0.002),
        (q.astype(complex), v, 0.003),
        (q, nan_v, 0.004),
        (far, v, 0.005),
        (near, v, 0.006),
        (q, v, "0.007"),
        (q, v, 0.008, "extra"),
    ]
    seen = []

    def effort(k, q_read, v_read):
        seen.append(q_read)
        return np.zeros(18)

    stats = run(Law(SOLO, effort), Driver(readings), len(readings))
    assert stats.reasons == {
        "malformed reading": 5,
        "non-finite": 1,
        "non-unit quaternion": 1,
    }
    assert len(seen) == 2  # the good reading and the near-unit one, normalised
    assert np.linalg.norm(seen[1][3:7]) == pytest.approx(1.0, abs=1e-15)


@pytest.mark.parametrize(
    "bad",
    [
        np.ones(2, dtype=complex),
        np.array([1.0 + 1e-3j, 1.0]),
        np.ones(3),
        np.array([np.inf, 0.0]),
        np.array([True, False]),
        "1 1",
    ],
)
def test_a_bad_effort_sends_the_safe_action_without_a_warning(bad):
    driver = Driver([good(k) for k in range(3)])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a ComplexWarning would fail the test
        stats = run(Law(PENDULUM, lambda k, q, v: bad), driver, 2)
    assert stats.reasons == {"bad effort": 2}
    assert all(tau.dtype == float and not tau.any() for tau in driver.written)


def test_hold_repeats_the_last_good_effort_for_hold_time_then_zero():
    def effort(k, q, v):
        return np.array([k, -k], dtype=float) if k <= 2 else va.ConstraintError("infeasible")

    driver = Driver([good(k) for k in range(10)])
    stats = run(Law(PENDULUM, effort), driver, 8, rate_hz=100.0, safe_action="hold", hold_time=0.03)
    written = [tau.tolist() for tau in driver.written]
    held = [2.0, -2.0]
    assert written == [[1, -1], held, held, held, held, [0, 0], [0, 0], [0, 0], [0, 0]]
    assert stats.failed_ticks == 6 and stats.zero_ticks == 3
    assert stats.reasons == {"controller error: ConstraintError": 6}


def test_damping_is_minus_d_v_on_the_driven_joints_and_clipped():
    q, v, _ = good(0, SOLO)
    v = np.linspace(-3.0, 4.0, 18)
    driver = Driver([(q, v, 0.001 * k) for k in range(3)])
    law = Law(SOLO, lambda k, q, v: RuntimeError("law broke"))
    stats = run(law, driver, 2, safe_action="damp")
    expected = -DEFAULT_DAMPING * v
    expected[:6] = 0.0  # the floating base is not driven
    np.testing.assert_array_equal(driver.written[0], expected)
    assert stats.reasons == {"controller error: RuntimeError": 2}
    # per-joint gains, used as given, and clipped to the URDF's effort limits (1000 N m)
    gains = np.full(18, 2.0)
    gains[10] = 1e6
    driver = Driver([(q, v, 0.001 * k) for k in range(3)])
    run(law, driver, 2, safe_action="damp", damping=gains)
    expected = -2.0 * v
    expected[10] = -math.copysign(SOLO.model.effortLimit[10], v[10])
    assert SOLO.model.effortLimit[10] < 1e6 * abs(v[10])  # the clip binds
    np.testing.assert_array_equal(driver.written[0], expected)
    assert not driver.written[-1].any()


def test_damping_without_a_valid_velocity_is_zero():
    readings = [(np.zeros(2), np.array([np.nan, 1.0]), 0.0), (np.zeros(2), np.ones(2), 0.001)]
    driver = Driver(readings)
    stats = run(Law(PENDULUM, lambda k, q, v: np.ones(2)), driver, 2, safe_action="damp")
    assert driver.written[0].tolist() == [0.0, 0.0] and stats.zero_ticks == 1
    assert driver.written[1].tolist() == [1.0, 1.0]


def test_a_controller_s_attachment_failures_are_counted():
    model = SOLO.model
    feet = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
    limits = np.r_[np.zeros(6), np.full(12, 3.0)]
    body = va.ParallelVirtualActuator(
        SOLO, "base_link", feet, min_normal=60.0, torque_limits=limits, friction=0.8
    )
    controller = va.Controller(SOLO, on_failure="fallback")
    controller.add("body", body, [va.ConstantForce(("z",), 25.0)], method="qp")
    driver = Driver([good(k, SOLO) for k in range(3)])
    stats = run(controller, driver, 2)
    assert stats.attachment_failures == {"body: constraint -> fallback": 2}
    assert stats.failed_ticks == 0 and driver.written[0].shape == (model.nv,)


def test_the_loop_ends_at_its_duration_within_a_long_period(monkeypatch):
    class Clock:  # the loop's clock, advanced only by its sleeps
        now = 0.0
        slept = []

        @classmethod
        def perf_counter(cls):
            return cls.now

        @classmethod
        def sleep(cls, seconds):
            cls.slept.append(seconds)
            cls.now += seconds

    monkeypatch.setattr(run_loop, "clock", Clock)
    driver = Driver([good(k) for k in range(3)])
    law = Law(PENDULUM, lambda k, q, v: np.ones(2))
    stats = va.run(law, driver.read_state, driver.write_effort, rate_hz=0.5, duration=0.2)
    assert stats.ticks == 1 and Clock.slept == [pytest.approx(0.2)]  # not the 2 s period
    assert stats.wall_time == pytest.approx(0.2)


def test_a_write_error_ends_the_loop_after_trying_zero_effort():
    class Broken(Driver):
        def write_effort(self, tau):
            super().write_effort(tau)
            if len(self.written) == 2:
                raise OSError("motor bus down")

    driver = Broken([good(k) for k in range(9)])
    with pytest.raises(OSError, match="bus down"):
        run(Law(PENDULUM, lambda k, q, v: np.ones(2)), driver, 8)
    assert len(driver.written) == 3 and not driver.written[-1].any()


def test_bad_arguments_are_typed_errors_naming_them():
    driver = Driver([good(0)])
    law = Law(PENDULUM, lambda k, q, v: np.ones(2))
    cases = [
        (dict(should_stop=3, duration=1.0), "should_stop"),
        (dict(rate_hz=1e-300, duration=1.0), "rate_hz"),
        (dict(rate_hz=math.inf, duration=1.0), "rate_hz"),
        (dict(duration=1.0, realtime="yes"), "realtime"),
        (dict(duration=1.0, safe_action="brake"), "safe_action"),
        (dict(duration=1.0, damping=-1.0), "damping"),
        (dict(duration=1.0, damping=[1.0, 2.0, 3.0]), "damping"),
        (dict(duration=1.0, hold_time=math.nan), "hold_time"),
        (dict(duration=1.0, robot="double_pendulum"), "robot"),
        (dict(duration=1.0, robot=SOLO), "controller's robot"),
    ]
    for options, match in cases:
        with pytest.raises(va.InvalidInputError, match=match):
            va.run(law, driver.read_state, driver.write_effort, **options)

    class Robotless:
        def compute(self, q, v, time):
            return np.ones(2)

    with pytest.raises(va.InvalidInputError, match="robot="):
        va.run(Robotless(), driver.read_state, driver.write_effort, duration=1.0)
    assert driver.written == []  # refused before the first tick
    stats = va.run(
        Robotless(), driver.read_state, driver.write_effort, duration=0.0, robot=PENDULUM
    )
    assert stats.ticks == 0 and [tau.tolist() for tau in driver.written] == [[0.0, 0.0]]


class Stance:
    """solo12 standing on a contact QP that becomes infeasible at 0.1 s.

    Until then the body's spring-damper runs on a QP with no least normal force; from then on
    the same request goes to a QP whose least normal force (60 N per foot) the joints' 3 N m
    torque limits cannot give (a ConstraintError every tick).
    """

    def __init__(self, on_failure: str) -> None:
        self.robot = SOLO
        self.controller = va.Controller(SOLO, on_failure=on_failure)
        feet = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
        limits = np.r_[np.zeros(6), np.full(12, 3.0)]
        q0 = SOLO.neutral()
        for name, least in (("feasible", 0.0), ("infeasible", 60.0)):
            body = va.ParallelVirtualActuator(
                SOLO, "base_link", feet, friction=0.8, min_normal=least, torque_limits=limits
            )
            pose = va.VirtualActuator(SOLO, "base_link", "world", "world", body.axes).position(q0)
            stiffness, damping = (800.0,) * 3 + (40.0,) * 3, (40.0,) * 3 + (2.0,) * 3
            spring = va.SpringDamper(body.axes, stiffness, damping, setpoint=pose)
            weight = va.ConstantForce(("z",), SOLO.mass * 9.81)
            self.controller.add(name, body, [spring, weight], method="qp")

    def compute(self, q, v, time):
        active = "feasible" if time < 0.1 - 1e-9 else "infeasible"
        return self.controller.compute(q, v, time, active=active)


@pytest.mark.parametrize("on_failure", ["fallback", "raise"])
def test_an_infeasible_contact_qp_falls_back_and_the_robot_stays_up(on_failure):
    simulator = Simulator(SOLO, control_rate=200.0)
    simulator.reset(SOLO.neutral())
    hardware = MujocoHardware(simulator)
    heights = []
    stats = va.run(
        Stance(on_failure),
        hardware.read_state,
        hardware.write_effort,
        rate_hz=200.0,
        realtime=False,
        should_stop=lambda: heights.append(simulator.q[2]) or simulator.time >= 0.35 - 1e-9,
    )
    infeasible_ticks = 50  # 0.1 s to 0.35 s at 200 Hz
    if on_failure == "fallback":
        assert stats.attachment_failures == {"infeasible: constraint -> fallback": infeasible_ticks}
        assert stats.failed_ticks == 0
        assert min(heights) > 0.2  # [m] the base stays up (0.238 m measured; 0.235 m start)
    else:  # the error reaches va.run, whose zero effort drops the robot
        assert stats.reasons == {"controller error: ConstraintError": infeasible_ticks}
        assert heights[-1] < 0.1  # [m] collapsed (0.03 m measured)
