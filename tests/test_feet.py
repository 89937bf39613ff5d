"""Feet found on robots nobody here wrote (SRDF end effectors, else frame names)."""

from __future__ import annotations

import numpy as np
import pytest

import virtual_actuators as va
from virtual_actuators.models.feet import find_feet

LEGGED = {
    "solo12": ("base_link", 4, "srdf"),
    "anymal": ("base", 4, "srdf"),
    "go2": ("base", 4, "srdf"),
    "hyq_no_sensors": ("base_link", 4, "srdf"),
    "talos_reduced": ("base_link", 2, "srdf"),
    "icub": ("base_link", 2, "srdf"),
    "laikago": ("trunk", 4, "names"),
    "g1_29dof_rev_1_0": ("pelvis", 2, "names"),
    "hexapod": ("body", 6, "names"),
    "spring_flamingo": ("body", 2, "names"),
}


@pytest.mark.parametrize("name", sorted(LEGGED))
def test_legged_robots(name):
    robot = va.load_robot(name)
    body, count, source = LEGGED[name]
    feet = find_feet(robot)
    assert (feet.body, len(feet.feet), feet.source) == (body, count, source)
    assert all(robot.model.existFrame(foot) for foot in feet.feet)
    # one foot per leg: no foot lies on the path from the body to another
    model = robot.model
    joints = [model.frames[model.getFrameId(f)].parentJoint for f in feet.feet]
    assert len(set(joints)) == len(joints)
    for a in joints:
        assert not any(a != b and a in model.supports[b] for b in joints)


@pytest.mark.parametrize("name", ["ur5_robot", "panda", "allegro_right_hand", "iris"])
def test_robots_without_feet_say_so(name):
    with pytest.raises(va.FrameNotFoundError, match="has no feet.*--feet"):
        find_feet(va.load_robot(name))


def test_a_body_actuator_on_the_feet_found_carries_the_weight():
    robot = va.load_robot("go2")
    feet = find_feet(robot)
    body = va.ParallelVirtualActuator(robot, feet.body, list(feet.feet), feet.body)
    weight = robot.mass * 9.81
    solution = body.solve(robot.neutral(), np.array([0.0, 0.0, weight, 0.0, 0.0, 0.0]))
    assert solution.residual < 1e-9 * weight
    assert np.allclose(solution.forces.sum(axis=0)[2], weight)


def test_generated_millipede():
    assert find_feet(va.millipede(legs=7)).feet == tuple(f"foot_{i}" for i in range(1, 8))


def test_foot_words_in_any_naming_style():
    from virtual_actuators.models.feet import _is_foot

    for name in ("LeftFoot", "RAnkle", "FL_FOOT", "l_sole", "left_toe_link", "ankleRoll"):
        assert _is_foot(name), name
    for name in ("Football", "footprint_x", "base_link", "FL_KFE"):
        assert not _is_foot(name), name
