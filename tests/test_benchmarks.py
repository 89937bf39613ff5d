"""``benchmarks/bench_realtime.py`` runs: its worst-case and cold-start figures in ``--quick`` mode.

No timed asserts: the figures' times depend on the machine. What is checked is what must hold
whatever the machine: every run and loop is there with its tick count, the tails are ordered
(p50 <= p99 <= p99.9 <= max), a tick's controller compute (its wall and its CPU time) and its
MuJoCo step lie inside the same tick's loop iteration (so every percentile of each is at most
the loop's), and the new
processes of the cold-start figure ran their steps and saw the demo's first tick.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BENCH = ROOT / "benchmarks" / "bench_realtime.py"
KEYS = ("p50", "p99", "p99.9", "max")


def test_worst_case_and_cold_start_figures_run_quick(tmp_path):
    out = tmp_path / "bench.json"
    path = os.environ.get("PYTHONPATH")
    env = {**os.environ, "PYTHONPATH": f"{ROOT}{os.pathsep}{path}" if path else str(ROOT)}
    command = [sys.executable, str(BENCH), "--quick", "--only", "7", "--only", "8", "--json", out]
    done = subprocess.run(command, capture_output=True, text=True, timeout=900, env=env, cwd=ROOT)
    assert done.returncode == 0, done.stderr[-3000:]
    assert "issue 27's rows" in done.stdout
    result = json.loads(out.read_text())
    assert all("FAILED" not in r["figure"] for r in result["rows"]), result["rows"]
    runs = result["figures"]["7"]
    walks = [title for title in runs if not title.startswith("va.run")]
    assert len(walks) >= 5 and sum(title.startswith("va.run") for title in runs) == 2
    for title, run in runs.items():
        assert run["ticks"] == 500, title  # 0.5 simulated s at 1 kHz, or 500 loop ticks
        for part in ("controller", "controller_cpu", "loop", "mujoco_step"):
            values = [run[part][k] for k in KEYS]
            assert values == sorted(values) and values[0] > 0, (title, part, values)
            assert run[part]["n"] == 500, (title, part)
        for part in ("controller", "controller_cpu", "mujoco_step"):
            for k in KEYS:
                assert run[part][k] <= run["loop"][k], (title, part, k)
    assert len(result["issue27"]) == len(result["rows"])  # figures 7 and 8 are the rows
    cold = result["figures"]["8"]
    assert cold["cold"] is None and cold["warm"]["ok"], cold  # --quick: the warm runs only
    steps = ("import", "declare", "first_solve", "first_qp", "second_qp")
    assert all(cold["warm"][k] > 0 for k in steps)
    demo = cold["warm_demo"]
    assert demo["ok"] and demo["shown_sim_s"] > 0, demo
    assert 0 < demo["bar_s"] <= demo["first_progress_s"]
