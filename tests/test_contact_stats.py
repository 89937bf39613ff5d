"""Stance forces measured in MuJoCo: the one-pass force query and the walks' figures."""

from __future__ import annotations

import numpy as np
import pytest

from virtual_actuators.demos import run_walk


def test_contact_forces_equal_the_per_frame_query():
    result = run_walk("flamingo-slopes", duration=0.6, progress=False)
    simulator = result.simulator
    frames = ["left_heel", "left_toe", "right_heel", "right_toe", "body"]
    together = simulator.contact_forces(frames)
    apart = np.array([simulator.contact_force(frame) for frame in frames])
    assert np.allclose(together, apart, rtol=0.0, atol=1e-12)
    assert together[:4, 2].sum() > 50.0  # standing: the feet carry the robot


@pytest.mark.slow
@pytest.mark.parametrize(
    ("walk", "normal", "ratio"), [("turkey-walk", 5.0, 0.6), ("flamingo-slopes", 5.0, 0.8)]
)
def test_feet_in_support_push_and_do_not_slide(walk, normal, ratio):
    metrics = run_walk(walk, duration=6.0, progress=False).metrics
    assert not metrics.fell
    assert metrics.stance_normal_min_n > normal  # [N]
    assert metrics.stance_friction_ratio_max < ratio  # MuJoCo's friction coefficient is 1
    data = metrics.to_dict()
    assert {"stance_normal_min_n", "stance_friction_ratio_max"} <= data.keys()
