"""The command line a newcomer tries first: version, robots, stand on any legged robot, sweeps,
walks with a distribution, a seed and a plot window."""

from __future__ import annotations

import csv
import json
import shutil

import pytest

import virtual_actuators as va
from virtual_actuators.__main__ import main

pytestmark = pytest.mark.slow  # each runs the command line (and walks)


def test_version(capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["--version"])
    assert exit_info.value.code == 0
    assert capsys.readouterr().out.strip() == f"virtual_actuators {va.__version__}"


def test_robots_table_lists_aliases(capsys):
    assert main(["robots"]) == 0
    out = capsys.readouterr().out
    for name in ("solo12", "talos", "ur5", "go2", "hexapod"):
        assert name in out


@pytest.mark.parametrize(("robot", "feet"), [("go2", 4), ("talos", 2), ("hexapod", 6)])
def test_stand_on_any_legged_robot(capsys, robot, feet):
    assert main(["demo", "stand", "--robot", robot]) == 0
    out = capsys.readouterr().out
    assert f"on {feet} feet" in out and "residual" in out


def copied_go1(folder) -> str:
    """example-robot-data's go1 URDF and meshes copied into ``folder``: no SRDF beside them."""
    description = va.load_robot("go1").urdf_path.parents[1]
    for part in ("urdf", "meshes"):
        shutil.copytree(description / part, folder / part)
    return str(folder / "urdf" / "go1.urdf")


def test_stand_builds_the_pose_of_a_robot_without_an_srdf_pose(capsys, tmp_path):
    """laikago and a copied go1 stand as the walker and the balancer stand them (issue 35: the
    straight neutral pose was "singular ... Bend the chain")."""
    for robot in ("laikago", copied_go1(tmp_path)):
        assert va.load_robot(robot).default_pose is None
        assert main(["demo", "stand", "--robot", robot]) == 0
        out = capsys.readouterr().out
        assert "on 4 feet" in out and "residual" in out


def test_stand_with_named_feet(capsys):
    assert main(["demo", "stand", "--robot", "solo12", "--feet", "FL_FOOT,FR_FOOT,HL_FOOT"]) == 0
    assert "on 3 feet" in capsys.readouterr().out


def test_walk_with_distribution_seed_and_window(tmp_path, capsys):
    plot, report = tmp_path / "w.png", tmp_path / "w.json"
    arguments = ["demo", "turkey-walk", "--duration", "1.5", "--seed", "2", "--quiet"]
    arguments += ["--distribution", "partitioned", "--plot", str(plot), "--window", "0.5:1.5"]
    assert main([*arguments, "--json", str(report)]) == 0
    data = json.loads(report.read_text())
    assert data["stance_normal_min_n"] > 0 and data["stance_friction_ratio_max"] < 1.0
    assert plot.stat().st_size > 10_000


def test_sweep_with_two_workers(tmp_path, capsys):
    out, plot = tmp_path / "s.csv", tmp_path / "s.png"
    arguments = ["sweep", "turkey-walk", "--speed", "0.4:0.5:0.1", "--terrain", "flat"]
    arguments += ["--seeds", "2", "--duration", "1.0", "--workers", "2", "--quiet"]
    assert main([*arguments, "--out", str(out), "--plot", str(plot)]) == 0
    rows = list(csv.DictReader(out.open()))
    assert len(rows) == 4 and {row["fell"] for row in rows} == {"False"}
    assert "100%" in capsys.readouterr().out and plot.stat().st_size > 1000


def test_a_push_typed_with_a_minus_pushes_the_other_way(tmp_path, capsys):
    out = tmp_path / "pushed.json"
    arguments = ["demo", "legged", "--push", "-10@0.05", "--duration", "0.2", "--quiet"]
    assert main([*arguments, "--json", str(out)]) == 0
    assert json.loads(out.read_text())["config"]["push"] == [10.0, 0.05, 180.0]


def test_stand_prints_no_negative_zero_and_aligns_long_joint_names(capsys):
    import re

    assert main(["demo", "stand", "--robot", "go2"]) == 0  # its produced y was "-0.000"
    assert not re.search(r"(?<![\w.])-0(?:\.0+)?(?![\d.])", capsys.readouterr().out)
    assert main(["demo", "stand", "--robot", "talos"]) == 0  # joint names up to 17 characters
    out = capsys.readouterr().out
    table = out.split("joint efforts:\n", 1)[1].split("\n\n", 1)[0].splitlines()
    assert len(table) > 30 and max(len(line.split()[0]) for line in table) > 16
    assert len({len(line) for line in table}) == 1, table  # one column of efforts, right-aligned


def test_the_legged_plot_names_the_robot_and_the_gait():
    from virtual_actuators.gaits.legged.walk import draw_legged_walk
    from virtual_actuators.gaits.registry import run_walk

    result = run_walk("legged", robot="go2", gait="pace", duration=0.3, progress=False)
    title = draw_legged_walk(result).get_suptitle()
    assert title.startswith("go2 (pace): ") and "steps" in title
