"""Benchmark ParallelVirtualActuator.solve: partitioned vs the dense eq. 10-11 baseline.

Prints a table of median / p90 times per call and can write JSON:

    python benchmarks/bench_solve.py [--repeat 2000] [--json results.json]
"""

from __future__ import annotations

import argparse
import json
import platform
import time
from collections.abc import Callable

import numpy as np
import pinocchio as pin

import virtual_actuators as va


def _timeit(fn: Callable[[], object], repeat: int) -> dict[str, float]:
    fn()  # warm-up (caches, first re-picks)
    samples = np.empty(repeat)
    for i in range(repeat):
        start = time.perf_counter_ns()
        fn()
        samples[i] = time.perf_counter_ns() - start
    samples /= 1e3
    return {
        "median_us": float(np.median(samples)),
        "p90_us": float(np.percentile(samples, 90)),
        "min_us": float(samples.min()),
    }


def _bent(robot: va.Robot, seed: int = 3) -> np.ndarray:
    rng = np.random.default_rng(seed)
    q = pin.integrate(robot.model, robot.neutral(), rng.uniform(-0.05, 0.05, robot.model.nv))
    return pin.normalize(robot.model, q)


def cases() -> list[tuple[str, va.ParallelVirtualActuator, np.ndarray, np.ndarray]]:
    """The benchmark cases: name, actuator, configuration, wrench."""
    out = []
    solo = va.load_robot("solo12")
    feet = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
    q = solo.neutral()
    wrench = np.array([2.0, 1.0, 25.0, 0.1, -0.2, 0.05])
    out.append(
        (
            "solo12 body, 4 point feet, min-norm",
            va.ParallelVirtualActuator(solo, "base_link", feet, reference="base_link"),
            q,
            wrench,
        )
    )
    # all x forces equal, y forces equal front and hind, diagonal z sums equal: r = 6
    design = [
        va.Equal((feet[0], "x"), (feet[1], "x")),
        va.Equal((feet[0], "x"), (feet[2], "x")),
        va.Equal((feet[0], "x"), (feet[3], "x")),
        va.Equal((feet[0], "y"), (feet[1], "y")),
        va.Equal((feet[2], "y"), (feet[3], "y")),
        va.Linear({(feet[0], "z"): 1, (feet[3], "z"): 1, (feet[1], "z"): -1, (feet[2], "z"): -1}),
    ]
    out.append(
        (
            "solo12 body, 6 design constraints (square)",
            va.ParallelVirtualActuator(
                solo, "base_link", feet, reference="base_link", design=design
            ),
            q,
            wrench,
        )
    )
    for legs in (6, 100):
        robot = va.millipede(legs=legs)
        reactions = [f"foot_{i}" for i in range(1, legs + 1)]
        out.append(
            (
                f"millipede {legs} legs, min-norm",
                va.ParallelVirtualActuator(robot, "body", reactions, reference="body"),
                _bent(robot),
                np.array([1.0, 0.5, 9.81 * legs * 0.1, 0.1, 0.2, 0.05]),
            )
        )
    return out


def main() -> None:
    """Run the benchmark."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=2000)
    parser.add_argument("--json", help="write the results to this file")
    args = parser.parse_args()
    rows = []
    for name, actuator, q, wrench in cases():
        for method in ("partitioned", "dense"):
            repeat = args.repeat if method == "partitioned" or actuator.p < 50 else 50

            def call(a=actuator, m=method, q=q, w=wrench):
                return a.solve(q, w, method=m)

            stats = _timeit(call, repeat)
            sol = actuator.solve(q, wrench, method=method)
            rows.append({"case": name, "solver": method, "method": sol.method, **stats})
    width = max(len(r["case"]) for r in rows)
    print(f"{'case':<{width}}  {'solver':<12}{'method':<16}{'median us':>11}{'p90 us':>10}")
    for r in rows:
        print(
            f"{r['case']:<{width}}  {r['solver']:<12}{r['method']:<16}"
            f"{r['median_us']:>11.1f}{r['p90_us']:>10.1f}"
        )
    if args.json:
        meta = {
            "python": platform.python_version(),
            "machine": platform.machine(),
            "pin": pin.__version__,
        }
        with open(args.json, "w") as stream:
            json.dump({"meta": meta, "results": rows}, stream, indent=2)
        print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
