"""Cold start for ``bench_realtime.py`` figure 8: the first calls in a new process.

Run as a script (``python _cold_start.py SPEC``) it is the child: it times ``import
virtual_actuators``, loading solo12, the body actuator's declaration, the first and second
``solve``, the declaration with friction and the first and second ``solve(method="qp")``, and
prints one JSON line. Nothing but the standard library is imported before the clock starts.

The parent side starts that child, and the README's demo command, with Python's bytecode cache
in a directory of its choosing (``PYTHONPYCACHEPREFIX``): a new empty one is a cold start (every
module compiled to bytecode on import: a fresh install, a container, a read-only site-packages,
a new user), the same directory again is a warm start (the ``.pyc`` files the cold run wrote).
Nothing else is compiled at run time: the kernels are the compiled core's, built at install.
"""

from __future__ import annotations

import json
import os
import re
import select
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent  # the repository (imported by the children)
DEMO = ("-m", "virtual_actuators", "demo")  # the README's first command's demo
#: The demo's progress bar, ``0.1/20.0 s``: done and total simulated seconds.
PROGRESS = re.compile(rb"(\d+(?:\.\d+)?)/(\d+(?:\.\d+)?) s")


def _child(spec: dict[str, Any]) -> dict[str, float]:
    """The steps of a new process, timed [s]."""
    clock = time.perf_counter
    times = {"launch_to_main": time.time() - spec["launched"]}
    start = clock()
    import virtual_actuators as va

    times["import"] = clock() - start
    import numpy as np

    feet, wrench = spec["feet"], np.array(spec["wrench"])
    start = clock()
    robot = va.load_robot("solo12")
    times["load_robot"] = clock() - start
    declare = {"reference": "base_link", "contact": "point"}
    start = clock()
    body = va.ParallelVirtualActuator(robot, "base_link", feet, **declare)
    times["declare"] = clock() - start
    q = robot.neutral()
    for key in ("first_solve", "second_solve"):
        start = clock()
        body.solve(q, wrench)
        times[key] = clock() - start
    start = clock()
    body_qp = va.ParallelVirtualActuator(robot, "base_link", feet, friction=spec["mu"], **declare)
    times["declare_qp"] = clock() - start
    for key in ("first_qp", "second_qp"):
        start = clock()
        body_qp.solve(q, wrench, method="qp")
        times[key] = clock() - start
    return times


def _environment(cache_dir: str | None) -> dict[str, str]:
    """This environment with Python's bytecode cache in ``cache_dir`` (None: where it is now)
    and the repository importable."""
    path = os.environ.get("PYTHONPATH")
    out = {**os.environ, "PYTHONPATH": str(ROOT) if not path else f"{ROOT}{os.pathsep}{path}"}
    if cache_dir is not None:
        out["PYTHONPYCACHEPREFIX"] = cache_dir
    return out


def first_calls(cache_dir: str | None, spec: dict[str, Any], timeout: float) -> dict[str, Any]:
    """Run the child with the bytecode cache in ``cache_dir``; its step times [s] and its wall time
    from launch to exit, or ``{"ok": False, "error": ...}``."""
    spec = {**spec, "launched": time.time()}
    start = time.perf_counter()
    try:
        done = subprocess.run(
            [sys.executable, __file__, json.dumps(spec)], capture_output=True, text=True,
            timeout=timeout, env=_environment(cache_dir), cwd=ROOT,
        )  # fmt: skip
    except subprocess.TimeoutExpired:
        return {"ok": False, "error": f"timeout after {timeout:g} s"}
    wall = time.perf_counter() - start
    if done.returncode != 0:
        lines = done.stderr.strip().splitlines() or [f"exit code {done.returncode}"]
        return {"ok": False, "error": lines[-1], "wall_s": wall}
    return {"ok": True, **json.loads(done.stdout.strip().splitlines()[-1]), "wall_s": wall}


def demo_first_tick(cache_dir: str | None, timeout: float) -> dict[str, Any]:
    """Launch the README's demo (``python -m virtual_actuators demo``) with the bytecode cache in
    ``cache_dir``; the seconds from launch until its progress bar first shows, and until it
    first shows simulated time past 0 (then the demo is stopped).

    The bar shows its first position after a tick count (every 100 ticks, at most ten redraws a
    second), so the second figure is an upper bound of when the first tick started: it
    includes the first 0.1-0.2 simulated seconds (100-200 ticks, ~10-40 ms at the demo's speed).
    """
    command = [sys.executable, *DEMO]
    start = time.perf_counter()
    child = subprocess.Popen(
        command, cwd=ROOT, env=_environment(cache_dir), stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )  # fmt: skip
    out: dict[str, Any] = {"ok": False, "bar_s": None, "first_progress_s": None}
    seen = b""
    try:
        while True:
            left = timeout - (time.perf_counter() - start)
            if left <= 0 or not select.select([child.stderr], [], [], left)[0]:
                out["error"] = f"no progress within {timeout:g} s"
                break
            chunk = os.read(child.stderr.fileno(), 1 << 16)
            now = time.perf_counter() - start
            if not chunk:  # it ended before showing any progress
                out["error"] = f"ended (exit code {child.wait()}): {seen.decode()[-200:]!r}"
                break
            seen = (seen + chunk)[-4096:]
            shown = [float(done) for done, _ in PROGRESS.findall(seen)]
            if shown and out["bar_s"] is None:
                out["bar_s"] = now
            if any(value > 0.0 for value in shown):
                out |= {"ok": True, "first_progress_s": now, "shown_sim_s": max(shown)}
                break
    finally:
        if child.poll() is None:
            child.kill()
        child.wait()
    return out


if __name__ == "__main__":
    print(json.dumps(_child(json.loads(sys.argv[1]))))
