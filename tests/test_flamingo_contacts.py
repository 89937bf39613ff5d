"""Spring Flamingo's feet on the slopes with the QP distribution: loaded and not sliding.

Oracle: MuJoCo's contact forces (each contact split along the normal MuJoCo reports), read by
:class:`~virtual_actuators.experiments.contact_stats.StanceForces` on 40 s blind walks over the
built-in profiles, against MuJoCo's friction coefficient 1. The QP's cones follow the soles
(``normals="frames"``): with world-z cones the same walks let feet unload to 0 N and slide, and
the partitioned split reaches a ratio of 1.0 on profile-one at 0.4 m/s.
"""

from __future__ import annotations

import pytest

from virtual_actuators.demos import run_walk


@pytest.mark.slow
@pytest.mark.parametrize(
    ("terrain", "speed"), [("profile-one", 0.4), ("profile-one", 0.5), ("profile-two", 0.5)]
)
def test_flamingo_qp_feet_stay_loaded_and_do_not_slide(terrain, speed):
    result = run_walk(
        "flamingo-slopes", terrain=terrain, speed=speed, distribution="qp", progress=False
    )
    double = result.gait.controller.attachments["double"].actuator
    assert double.contact_limits.frame_normals.all()  # the cones follow the soles
    metrics = result.metrics
    assert not metrics.fell
    assert metrics.distance_m > 14.0  # [m] in 40 s: the walk crossed the profile
    assert metrics.stance_normal_min_n > 20.0  # [N]: every supporting foot carries load
    assert metrics.stance_friction_ratio_max < 0.95  # MuJoCo's friction coefficient is 1
