"""``demo balance``: legged robots standing on the contact QP in MuJoCo, pushed, not stepping."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

import virtual_actuators as va
from virtual_actuators.gaits.balance import Push, run_balance
from virtual_actuators.gaits.balance.walk import BalanceMetrics
from virtual_actuators.gaits.registry import WALKS


def _settled(result, tolerance):
    """The body back where it started: drift and tilt small over the last 0.2 s."""
    log = result.log
    last = log.time >= log.time[-1] - 0.2
    drift = np.hypot(log["x"][last] - log["x"][0], log["y"][last] - log["y"][0])
    tilt = np.hypot(log["roll"][last], log["pitch"][last])
    return drift.max() < tolerance and tilt.max() < 0.05


def test_talos_recovers_from_a_250_newton_push_without_stepping():
    result = run_balance("talos", 2.5, "250@0.5:0", progress=False)
    m = result.metrics
    assert not m.fell
    assert m.max_drift_m > 0.02  # it was pushed
    assert _settled(result, 0.02)
    # both soles loaded all along: no step, no foot lifted
    assert m.stance_normal_min_n > 0.05 * 90.0 * 9.81 / 2


def test_talos_sideways():
    result = run_balance("talos", 2.0, "200@0.5:90", progress=False)
    assert not result.metrics.fell and _settled(result, 0.02)


def test_g1_without_srdf_stands_and_takes_a_push():
    result = run_balance("g1", 2.5, "60@0.5:180", progress=False)
    m = result.metrics
    assert not m.fell and _settled(result, 0.02)
    assert 0.6 < result.log["z"][0] < 0.8  # the generated standing pose, on the ground
    assert abs(m.height_error_m) < 0.01


def test_quadruped_on_point_feet():
    result = run_balance("solo12", 2.0, "30@0.5:0", progress=False)
    assert not result.metrics.fell and _settled(result, 0.02)


def test_a_push_too_strong_is_a_fall():
    result = run_balance("solo12", 1.5, "150@0.3:90", progress=False)
    m = result.metrics
    assert m.fell and 0.3 < m.fall_time_s < 1.5
    assert result.log["fallen"][-1] == 1.0


def test_trace_and_json():
    result = run_balance("solo12", 0.5, None, progress=False)
    data = result.to_json()
    trace = data["trace"]
    names = ("t", "x", "y", "z", "roll", "pitch", "yaw", "vx", "vy", "state")
    assert all(name in trace for name in names)
    assert len({len(trace[name]) for name in names}) == 1
    assert np.diff(trace["t"]).max() <= 1 / 50 + 1e-9  # >= 50 Hz
    assert set(trace["state"]) == {"stand"}
    assert data["fell"] is False and data["realtime_factor"] > 0
    json.dumps(data)  # JSON-able


def test_the_summary_never_prints_minus_zero():
    figures = dict(robot="g1", feet=("left", "right"), fell=False, fall_time_s=None,
                   duration_s=3.0, realtime_factor=None, push=None, max_tilt_rad=0.0,
                   max_drift_m=0.0, final_drift_m=0.0, stance_normal_min_n=10.0)  # fmt: skip
    summary = BalanceMetrics(**figures, height_error_m=-4e-5, effort_oscillation=-0.0,
                             effort_oscillation_joint="knee", effort_change_rms=-0.0).summary()
    assert "height error +0.0 mm" in summary and "-0" not in summary, summary
    assert summary.endswith("effort osc 0.00 % (knee), change 0.0 %/tick")
    assert "height error -0.1 mm" in BalanceMetrics(**figures, height_error_m=-1e-4).summary()


def test_push_parsing():
    assert Push.parse("250@1.5") == Push(250.0, 1.5, 0.0)
    assert Push.parse("60@2:90") == Push(60.0, 2.0, 90.0)
    assert Push.parse("-3@1") == Push(3.0, 1.0, 180.0)  # a negative force pushes the other way
    for bad in ("250", "a@1", "250@-1", "250@1:x", "250@nan"):
        with pytest.raises(va.InvalidInputError, match="N@T"):
            Push.parse(bad)


def test_registered_and_on_the_command_line(tmp_path):
    assert "balance" in WALKS and WALKS["balance"].options == ("robot", "push", "estimator")
    out = tmp_path / "balance.json"
    command = [sys.executable, "-m", "virtual_actuators", "demo", "balance", "--robot",
               "solo12", "--duration", "1", "--push", "150@0.3:90", "--quiet", "--json", str(out)]
    run = subprocess.run(command, capture_output=True, text=True, timeout=600)
    assert run.returncode == 1, run.stderr  # it fell
    assert json.loads(out.read_text())["fell"] is True
    bad = subprocess.run(command[:-4] + ["--push", "150"], capture_output=True, text=True)
    assert bad.returncode == 2 and "N@T" in bad.stderr


def test_the_humanoid_tutorial_runs():
    """docs/tutorials/humanoid.md's program, run for 2 s instead of 4."""
    import contextlib
    import io
    import re
    from pathlib import Path

    page = Path(__file__).resolve().parents[1] / "docs" / "tutorials" / "humanoid.md"
    code = re.findall(r"```python\n(.*?)```", page.read_text(), re.S)[0]
    assert code.count("simulator.time < 4.0") == 1
    namespace: dict = {}
    with contextlib.redirect_stdout(io.StringIO()) as out:
        exec(compile(code.replace("simulator.time < 4.0", "simulator.time < 2.0"), "tut", "exec"),
             namespace)
    assert "pelvis at" in out.getvalue()
    assert namespace["drift"] < 0.02 and max(namespace["tilt"]) < 0.1
    assert abs(namespace["simulator"].q[2] - namespace["q0"][2]) < 0.01


def test_a_quadruped_with_paws_and_no_srdf_stands(tmp_path):
    """solo12 renamed (feet *_paw, no SRDF beside it): feet by structure, a generated pose."""
    text = va.load_robot("solo12").urdf_string.replace("_FOOT", "_paw").replace("_ANKLE", "_tip")
    path = tmp_path / "paws.urdf"
    path.write_text(text)
    result = run_balance(path.as_posix(), 1.5, "20@0.5:0", progress=False)
    assert sorted(result.metrics.feet) == ["FL_paw", "FR_paw", "HL_paw", "HR_paw"]
    assert not result.metrics.fell and _settled(result, 0.02)


def test_go2_sideways():
    result = run_balance("go2", 2.0, "120@0.5:90", progress=False)
    assert not result.metrics.fell and _settled(result, 0.02)
