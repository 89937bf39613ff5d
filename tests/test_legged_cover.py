"""The legged and balance demos end to end: robots nobody here built, the outputs, the sweep.

A quadruped URDF copied out of its package, its feet renamed ``*_paw`` and without its SRDF,
trots from the command line with no ``--feet``; laikago (whose all-zero pose has straight legs)
starts from the standing pose built from its legs; the hexapod walks one leg at a time and on
tripods through the same layer; ``--plot``, ``--record``, ``--viz`` and ``sweep`` work for both
demos. Short closed loops in MuJoCo.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

pytest.importorskip("mujoco")

import virtual_actuators as va  # noqa: E402
from virtual_actuators.__main__ import main  # noqa: E402
from virtual_actuators.gaits.legged import LeggedWalker  # noqa: E402
from virtual_actuators.gaits.legged.walk import LeggedWalkConfig, run_legged_walk  # noqa: E402


def _second_half_speed(trace: dict) -> float:
    """Mean speed over the trace's second half, from the positions [m/s]."""
    half = len(trace["t"]) // 2
    dx, dy = trace["x"][-1] - trace["x"][half], trace["y"][-1] - trace["y"][half]
    return float(np.hypot(dx, dy) / (trace["t"][-1] - trace["t"][half]))


@pytest.mark.slow
def test_a_quadruped_with_paws_and_no_srdf_trots_from_its_urdf_path(tmp_path):
    text = va.load_robot("go2").urdf_string.replace("_foot", "_paw")
    assert "package://" in text  # the meshes stay in their package
    urdf = tmp_path / "go2_paws.urdf"
    urdf.write_text(text)
    robot = va.load_robot(urdf)
    assert robot.default_pose is None and "FL_foot" not in robot.frame_names
    walker = LeggedWalker(robot)
    assert sorted(walker.feet) == ["FL_paw", "FR_paw", "RL_paw", "RR_paw"]
    out = tmp_path / "trace.json"
    command = ["demo", "legged", "--robot", str(urdf), "--speed", "0.5", "--duration", "3",
               "--quiet", "--json", str(out)]
    assert main(command) == 0
    data = json.loads(out.read_text())
    assert data["fell"] is False
    assert abs(_second_half_speed(data["trace"]) / 0.5 - 1.0) < 0.2
    assert max(map(abs, data["trace"]["roll"] + data["trace"]["pitch"])) < 0.3


@pytest.mark.slow
def test_laikago_trots_from_the_standing_pose_built_from_its_legs():
    robot = va.load_robot("laikago")
    assert robot.default_pose is None
    q0 = LeggedWalker(robot).initial_configuration()
    assert np.abs(q0[7:] - robot.neutral()[7:]).max() > 0.2  # knees bent, not the straight neutral
    result = run_legged_walk(
        LeggedWalkConfig(robot="laikago", speed=0.5, duration=3.0), progress=False
    )
    m = result.metrics
    assert not m.fell, m.summary()
    assert abs(m.speed_mps / 0.5 - 1.0) < 0.2, m.summary()
    assert m.roll_max_rad < 0.3 and m.pitch_max_rad < 0.3, m.summary()


@pytest.mark.slow
@pytest.mark.parametrize("gait", ["walk", "tripod"])
def test_the_hexapod_walks_and_tripods_through_demo_legged(gait, tmp_path):
    out = tmp_path / f"{gait}.json"
    command = ["demo", "legged", "--robot", "hexapod", "--gait", gait, "--speed", "0.3",
               "--duration", "3", "--quiet", "--json", str(out)]
    assert main(command) == 0
    data = json.loads(out.read_text())
    assert data["fell"] is False and data["steps"] >= 6
    assert abs(_second_half_speed(data["trace"]) / 0.3 - 1.0) < 0.2
    states = set(data["trace"]["state"])
    swings = {s for s in states if s.startswith("swing_")}
    assert len(swings) == (6 if gait == "walk" else 2)  # one leg at a time, or two tripods


@pytest.mark.parametrize(
    ("demo", "extra"),
    [
        ("legged", ["--speed", "0.3"]),
        ("balance", ["--robot", "solo12", "--push", "5@0.1"]),
        ("balance", []),  # talos: flat feet, whose sole-centre frames the balancer adds
    ],
)
def test_demo_plot_and_record(demo, extra, tmp_path, capsys):
    """``--plot`` and ``--record`` (a live ``--viz`` serves until interrupted: see
    tests/test_cli_paper_cuts.py, which runs it in a subprocess)."""
    plot, record, out = tmp_path / "run.png", tmp_path / "run.html", tmp_path / "run.json"
    command = ["demo", demo, *extra, "--duration", "0.3", "--quiet", "--record",
               str(record), "--plot", str(plot), "--json", str(out)]
    assert main(command) == 0
    printed = capsys.readouterr().out
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "MeshCat" in record.read_text(encoding="utf-8")
    assert f"recording: {record}" in printed
    trace = json.loads(out.read_text())["trace"]
    assert len(trace["t"]) >= 25 and trace["t"][-1] > 0.25  # 100 Hz over 0.3 s


@pytest.mark.parametrize("walk", ["legged", "balance"])
def test_sweep_runs_the_demo(walk, tmp_path, capsys):
    out = tmp_path / "sweep.json"
    command = ["sweep", walk, "--speed", "0.2:0.3:0.1", "--seeds", "1", "--duration", "0.6",
               "--workers", "1", "--quiet", "--out", str(out)]
    assert main(command) == 0
    rows = json.loads(out.read_text())["results"]
    assert [row["speed"] for row in rows] == pytest.approx([0.2, 0.3])
    assert all(row["walk"] == walk and not row["fell"] and not row["error"] for row in rows)
    if walk == "legged":
        assert all(row["steps"] >= 1 and row["distance"] > 0.0 for row in rows)
    assert f"2 walks of {walk}" in capsys.readouterr().out


@pytest.mark.slow
@pytest.mark.parametrize("robot", ["go2", "solo12", "anymal"])
def test_pace_from_the_standing_stance(robot):
    """A pace (lateral pairs) with short swings and a narrow stance: no fall, speed, attitude."""
    result = run_legged_walk(
        LeggedWalkConfig(robot=robot, gait="pace", speed=0.4, duration=3.0), progress=False
    )
    m = result.metrics
    assert not m.fell, m.summary()
    assert abs(m.speed_mps / 0.4 - 1.0) < 0.2, m.summary()
    assert m.direction_error_rad < 0.2 and m.heading_drift_rad < 0.2, m.summary()
    assert m.roll_max_rad < 0.3 and m.pitch_max_rad < 0.3, m.summary()
    swings = {s for s in result.trace()["state"] if s.startswith("swing_")}
    assert swings == {"swing_0", "swing_1"} and m.steps >= 10


def test_pace_pattern_swings_sides_quickly_on_a_narrow_stance():
    from virtual_actuators.gaits.legged.patterns import PACE_SWING_TIME, PACE_WIDTH

    robot = va.load_robot("go2")
    trot, pace = LeggedWalker(robot, pattern="trot"), LeggedWalker(robot, pattern="pace")
    left, right = pace.groups
    assert {f[:2] for f in left} == {"FL", "RL"} and {f[:2] for f in right} == {"FR", "RR"}
    assert pace.swing_time == pytest.approx(PACE_SWING_TIME * trot.swing_time)
    np.testing.assert_allclose(pace.nominal[:, 0], trot.nominal[:, 0])
    np.testing.assert_allclose(pace.nominal[:, 1], PACE_WIDTH * trot.nominal[:, 1])
    given = LeggedWalker(robot, pattern="pace", parameters=va.LeggedParameters(swing_time=0.5))
    assert given.swing_time == pytest.approx(0.5 * trot.swing_time)  # the user's choice wins
    with pytest.raises(va.InvalidInputError, match="width"):
        va.GaitPattern("p", {"a": 0.0, "b": 0.5}, width=0.0)
