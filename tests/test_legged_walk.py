"""Closed-loop MuJoCo runs of the legged gait layer on example-robot-data quadrupeds.

Each run checks the issue's targets on the trace over its second half: mean speed within 20 % of
the command, travel direction within 0.2 rad, heading drift below 0.2 rad, roll and pitch below
0.3 rad, no fall. The runs are short (3 simulated seconds: a 0.2 s stand, the speed ramp, then
the measured half).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("mujoco")

from virtual_actuators.gaits.legged.walk import LeggedWalkConfig, run_legged_walk  # noqa: E402

# MuJoCo walking runs (a few seconds each)
pytestmark = pytest.mark.slow


def _walk(**config):
    return run_legged_walk(LeggedWalkConfig(**{"duration": 3.0, **config}), progress=False)


def _assert_line(result, speed, direction=0.0):
    m = result.metrics
    assert not m.fell, m.summary()
    assert abs(m.speed_mps / speed - 1.0) < 0.2, m.summary()
    assert m.direction_error_rad < 0.2, m.summary()
    assert m.heading_drift_rad < 0.2, m.summary()
    assert m.roll_max_rad < 0.3 and m.pitch_max_rad < 0.3, m.summary()


@pytest.mark.parametrize(
    ("robot", "speed"),
    [("go2", 1.0), ("solo12", 0.4), ("anymal", 0.6), ("anymal_c", 0.6), ("hyq", 0.6)],
)
def test_trot_reaches_the_commanded_speed(robot, speed):
    result = _walk(robot=robot, speed=speed)
    _assert_line(result, speed)
    assert result.metrics.steps >= 8  # it trots: swings alternate
    # every swing ended on contact (the feet touched down), none on the time bound
    walker, history = result.gait, result.gait.machine.history
    bound = walker.parameters.max_swing * walker.swing_time
    swings = [later - start for (start, name), (later, _) in zip(history[:-1], history[1:],
                                                                  strict=True)
              if name.startswith("swing")]
    assert swings and max(swings) < bound - 0.005, (swings, bound)
    trace = result.trace()
    assert {"swing_0", "double_0", "swing_1", "double_1"} <= set(trace["state"])
    assert len(trace["t"]) == len(trace["x"]) == len(trace["state"])
    assert np.all(np.diff(trace["t"]) <= 1 / 50 + 1e-9)  # at 50 Hz or faster


def test_trot_with_the_partitioned_split():
    result = _walk(robot="go2", speed=1.0, distribution="partitioned")
    _assert_line(result, 1.0)


def test_crab_walk_goes_sideways_facing_forward():
    result = _walk(robot="go2", speed=0.5, direction=math.pi / 2)
    _assert_line(result, 0.5, math.pi / 2)
    trace = result.trace()
    assert abs(trace["x"][-1] - trace["x"][0]) < 0.25 * abs(trace["y"][-1] - trace["y"][0])


def test_circle_turns_at_the_commanded_rate():
    result = _walk(robot="go2", speed=0.5, yaw_rate=0.5, duration=4.0)
    m = result.metrics
    assert not m.fell, m.summary()
    assert abs(m.yaw_rate_radps / 0.5 - 1.0) < 0.1, m.summary()
    assert abs(m.speed_mps / 0.5 - 1.0) < 0.2, m.summary()
    assert m.roll_max_rad < 0.3 and m.pitch_max_rad < 0.3, m.summary()


def test_go2_survives_a_side_push_while_trotting():
    result = _walk(robot="go2", speed=0.5, push=(120.0, 1.5, 90.0), duration=3.0)
    trace = result.trace()
    assert not result.metrics.fell, result.metrics.summary()
    # the push was felt (the body was shoved sideways) and the walk went on along x
    during = [vy for t, vy in zip(trace["t"], trace["vy"], strict=True) if 1.5 <= t <= 1.8]
    assert max(during) > 0.1
    assert result.metrics.roll_max_rad < 0.3


def test_the_body_gives_way_only_where_its_support_cannot_push():
    """On two feet the request is made producible; the QP then meets it exactly."""
    ticks = []

    def collect(simulator, walker):
        state = walker.machine.current
        if state.name.startswith("swing") and np.any(walker.body.missing):
            name = state.active[0]
            ticks.append((walker.body.missing.copy(), walker.last.wrenches[name],
                          walker.last.produced[name]))

    config = LeggedWalkConfig(robot="solo12", speed=0.4, duration=1.5)
    result = run_legged_walk(config, progress=False, on_tick=collect)
    assert not result.metrics.fell
    assert len(ticks) > 300
    exact = 0
    for missing, wrench, produced in ticks:
        assert missing.shape == (6,)  # two point feet: one direction missing
        assert abs(np.linalg.norm(missing) - 1.0) < 1e-12
        scale = np.linalg.norm(wrench)
        assert abs(missing @ wrench) < 1e-9 * scale  # the request is producible
        exact += np.linalg.norm(produced - wrench) < 1e-6 * scale
    assert exact >= 0.95 * len(ticks)


def test_sine_path_is_followed_holding_the_heading():
    result = _walk(robot="go2", speed=0.5, path="sine", amplitude=0.2, wavelength=2.0,
                   duration=4.0)
    m = result.metrics
    assert not m.fell, m.summary()
    assert m.path_error_max_m < 0.05, m.summary()
    assert m.heading_drift_rad < 0.1, m.summary()
    trace = result.trace()
    assert max(trace["y"]) - min(trace["y"]) > 0.25  # it did weave


def test_tracking_faces_an_object_circling_the_start():
    result = _walk(robot="go2", speed=0.3, track=True, duration=5.0)
    m = result.metrics
    assert not m.fell, m.summary()
    assert m.bearing_error_max_rad < 0.05, m.summary()
    yaw = result.trace()["yaw"]
    assert yaw[-1] - yaw[0] > 0.5  # it turned with the object (0.25 rad/s)


def test_walk_pattern_lifts_one_foot_at_a_time():
    result = _walk(robot="go2", gait="walk", speed=0.2, duration=3.0)
    m = result.metrics
    assert not m.fell, m.summary()
    assert abs(m.speed_mps / 0.2 - 1.0) < 0.2, m.summary()
    assert m.roll_max_rad < 0.1 and m.pitch_max_rad < 0.1, m.summary()  # attitude kept
    states = set(result.trace()["state"])
    assert {"swing_0", "swing_1", "swing_2", "swing_3"} <= states


def test_the_hexapod_tripod_is_one_instance_of_the_layer():
    """The 1996 hexapod, walked by the generic layer's tripod: the seed's line to 0.8 m/s."""
    result = _walk(robot="hexapod", gait="tripod", speed=0.8)
    _assert_line(result, 0.8)
    tripods = {frozenset(group) for group in result.gait.groups}
    assert tripods == {frozenset(("foot_1", "foot_3", "foot_5")),
                       frozenset(("foot_2", "foot_4", "foot_6"))}


def test_the_tutorial_program_trots():
    """docs/tutorials/quadruped-walk.md's program, run for 2 s instead of 4."""
    from pathlib import Path

    page = Path(__file__).resolve().parents[1] / "docs" / "tutorials" / "quadruped-walk.md"
    program = page.read_text().split("```python\n")[1].split("```")[0]
    assert len(program.strip().splitlines()) < 30
    assert "DURATION = 4.0" in program
    scope: dict = {}
    exec(program.replace("DURATION = 4.0", "DURATION = 2.0"), scope)  # noqa: S102
    simulator, walker = scope["simulator"], scope["walker"]
    assert simulator.q[0] > 0.6  # 0.8 m/s after the stand and the ramp
    assert walker.machine.steps_into(walker.step_states) >= 8


def test_demo_legged_writes_the_trace_and_exits_1_when_the_robot_falls(tmp_path):
    import json

    from virtual_actuators.__main__ import main

    walked = tmp_path / "trot.json"
    code = main(["demo", "legged", "--robot", "solo12", "--speed", "0.3", "--duration", "1.5",
                 "--quiet", "--json", str(walked)])
    data = json.loads(walked.read_text())
    assert code == 0 and data["fell"] is False
    assert data["realtime_factor"] > 0 and data["physics_realtime_factor"] > 0
    trace = data["trace"]
    names = ("t", "x", "y", "z", "roll", "pitch", "yaw", "vx", "vy", "state")
    assert all(len(trace[name]) == len(trace["t"]) > 100 for name in names)
    assert set(trace["state"]) >= {"stand", "swing_0", "swing_1"}
    # a 100 N side push on a 2.5 kg robot for 0.1 s (4 m/s sideways): it falls
    pushed = tmp_path / "pushed.json"
    code = main(["demo", "legged", "--robot", "solo12", "--speed", "0.3", "--push", "100@0.5:90",
                 "--duration", "1.5", "--quiet", "--json", str(pushed)])
    assert code == 1 and json.loads(pushed.read_text())["fell"] is True


def test_an_arm_on_the_body_is_held_where_it_stands():
    """A legged manipulator's arm is held by the walker's posture: it neither drags nor falls."""
    result = _walk(robot="anymal_kinova", speed=0.5, duration=3.0)
    assert not result.metrics.fell, result.metrics.summary()
    gait = result.gait
    posture = gait.controller.postures["posture"]
    assert posture.joints and all(j.startswith("j2s6s200") for j in posture.joints)
    assert all("posture" in state.active for state in gait.machine.states)
    model = gait.robot.model
    rows = [model.joints[model.getJointId(j)].idx_q for j in posture.joints]
    drift = result.simulator.q[rows] - gait.initial_configuration()[rows]
    assert abs(drift).max() < 0.1  # [rad]
