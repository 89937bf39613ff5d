"""Closed-loop walking in MuJoCo: short runs of the seeds' gaits, the demo runner and its CLI.

Whole-length walks (20 s of turkey walking, 12 m of slopes) belong to the demos and
benchmarks/bench_walk.py; here each run lasts a few simulated seconds.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import virtual_actuators as va
from virtual_actuators.__main__ import main
from virtual_actuators.demos import WALKS, run_walk
from virtual_actuators.gaits.planar import lift_profile
from virtual_actuators.gaits.planar_walk import RECORD_EVERY
from virtual_actuators.gaits.turkey import TurkeyParameters, TurkeyWalker

pytestmark = [pytest.mark.slow]  # subprocesses or simulation: run with -m slow

JSON_KEYS = {
    "fell",
    "distance_m",
    "mean_speed_mps",
    "height_dev_m",
    "pitch_max_abs_rad",
    "steps",
    "realtime_factor",
}


@pytest.fixture(scope="module")
def turkey_run():
    return run_walk("turkey-walk", duration=5.0, progress=False)


def test_turkey_walks_at_about_the_commanded_speed(turkey_run):
    metrics = turkey_run.metrics
    assert not metrics.fell
    assert 0.35 < metrics.mean_speed_mps < 0.7  # commanded 0.5 m/s
    assert metrics.height_dev_m < 0.03  # seed: within 3 cm of the nominal 54 cm
    assert metrics.pitch_max_abs_rad < 0.1  # seed: within +-0.1 rad
    assert metrics.steps >= 6  # steps of about 0.5 s


def test_turkey_visits_every_state_of_table_1(turkey_run):
    visited = {name for _, name in turkey_run.gait.machine.history}
    assert visited == {
        "double_support",
        "left_support",
        "left_support_2",
        "right_support",
        "right_support_2",
    }
    # the buffer states always lead to double support, single support always to a buffer
    history = [name for _, name in turkey_run.gait.machine.history]
    for before, after in zip(history, history[1:], strict=False):
        if before.endswith("_2"):
            assert after == "double_support"
        elif before.endswith("_support") and before != "double_support":
            assert after == f"{before}_2"


def test_turkey_log_is_consistent(turkey_run):
    log = turkey_run.log
    assert len(log) == pytest.approx(5000 / RECORD_EVERY, abs=2)  # a row every few ticks
    assert turkey_run.loop.efforts.shape[0] == turkey_run.loop.ticks == 5000  # every tick
    # the log's x and height follow the simulator's state at the end
    q = turkey_run.simulator.q
    assert log["x"][-1] == pytest.approx(q[0], abs=0.01)
    # the bunny speed is recorded only in double support
    double = log.state == log.state_index("double_support")
    assert np.all(np.isfinite(log["xdot_setpoint"][double]))
    assert np.all(np.isnan(log["xdot_setpoint"][~double]))


def test_stance_ankle_and_limp_swing_leg_get_zero_effort():
    robot = va.load_robot("spring_turkey")
    gait = TurkeyWalker(robot, initial="left_support_2")
    q, v = gait.initial_configuration(), np.zeros(robot.model.nv)
    out = gait.compute(q, v, 0.0)
    limp = gait.controller.joint_indices(["right_hip", "right_knee"])
    assert np.all(out.tau[limp] == 0.0)
    assert np.any(out.tau[gait.controller.joint_indices(["left_hip", "left_knee"])] != 0.0)


def test_lift_profile_shape():
    assert lift_profile(0.0, 0.35) == pytest.approx(0.0, abs=1e-12)
    assert lift_profile(0.35, 0.35) == pytest.approx(1.0)
    assert lift_profile(1.0, 0.35) == pytest.approx(0.0, abs=1e-12)
    assert lift_profile(2.0, 0.35) == pytest.approx(0.0, abs=1e-12)  # clipped


def test_turkey_speed_follows_the_bunny():
    slow = run_walk("turkey-walk", duration=4.0, speed=0.4, progress=False).metrics
    fast = run_walk("turkey-walk", duration=4.0, speed=0.6, progress=False).metrics
    assert not slow.fell and not fast.fell
    assert slow.mean_speed_mps < fast.mean_speed_mps


def test_flamingo_walks_on_level_ground():
    metrics = run_walk("flamingo-slopes", duration=5.0, terrain="flat", progress=False).metrics
    assert not metrics.fell
    assert 0.2 < metrics.mean_speed_mps < 0.6  # commanded 0.4 m/s
    assert metrics.pitch_max_abs_rad < 0.1
    assert metrics.steps >= 4


def test_run_walk_errors():
    with pytest.raises(va.InvalidInputError, match="turkey-walk"):
        run_walk("turkey-wlk")
    with pytest.raises(va.InvalidInputError, match="duration"):
        run_walk("turkey-walk", duration=-1.0)
    with pytest.raises(va.InvalidInputError, match="speed"):
        run_walk("turkey-walk", speed=float("nan"))
    with pytest.raises(va.InvalidInputError):
        run_walk("turkey-walk", terrain="0:0,zz")


def test_every_walk_is_declared_with_a_known_robot():
    names = set(va.list_robots(include_aliases=True))  # "talos" is an alias
    for spec in WALKS.values():
        assert spec.robot in names


def test_cli_writes_json_and_plot(tmp_path, capsys):
    json_path, plot_path = tmp_path / "m.json", tmp_path / "p.png"
    code = main(
        [
            "demo",
            "turkey-walk",
            "--duration",
            "2.5",
            "--json",
            str(json_path),
            "--plot",
            str(plot_path),
            "--quiet",
        ]
    )
    assert code == 0
    data = json.loads(json_path.read_text())
    assert JSON_KEYS <= set(data)
    assert data["fell"] is False and data["distance_m"] > 0.3
    assert plot_path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "mean speed" in capsys.readouterr().out


def test_cli_terrain_points(tmp_path):
    json_path = tmp_path / "m.json"
    code = main(
        ["demo", "turkey-walk", "--duration", "1", "--terrain", "0:0,5:0", "--quiet"]
        + ["--json", str(json_path)]
    )
    assert code == 0
    assert json.loads(json_path.read_text())["duration_s"] == pytest.approx(1.0, abs=2e-3)


def test_turkey_parameters_are_documented():
    doc = TurkeyParameters.__doc__
    for name in TurkeyParameters.__dataclass_fields__:
        assert f"{name}:" in doc, name


def test_flamingo_climbs_a_fifteen_degree_slope_blind():
    # level to x = 0.6 m, then 15 degrees up to x = 6 m: premature landings, the global slope
    # estimate, eq. 15 heights and the friction-cone-limited bunny all take part
    rise = 5.4 * np.tan(np.radians(15.0))
    result = run_walk(
        "flamingo-slopes", duration=8.0, terrain=f"0.6:0,6:{rise:.4f}", progress=False
    )
    metrics = result.metrics
    assert not metrics.fell
    assert metrics.distance_m > 2.0  # the slope starts at 0.6 m
    assert metrics.height_dev_m < 0.05
    assert result.gait.slope > np.radians(12.0)  # the estimate converged to the real slope
