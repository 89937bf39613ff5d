"""Whole-length walks of the seeds' bipeds in MuJoCo: metrics and real-time factors.

Prints a table and can write JSON (and the plots):

    python benchmarks/bench_walk.py [--only turkey-flat] [--json walk.json] [--plots DIR]

Cases: Spring Turkey 20 s on level ground at 0.5 m/s (seed: about 0.5 m/s, height within 3 cm,
pitch within 0.1 rad, steps of about 0.5 s); Spring Flamingo 40 s over profile-one and
profile-two at 0.4 m/s (seed: 12 m of slopes between -20 and +20 degrees without falling), and
on level ground; and at 0.5 m/s over both profiles. Two columns say whether the feet in
support pushed and held: the least normal force and the largest tangential / normal ratio,
measured on MuJoCo's contact forces (its friction coefficient is 1). Three say whether the loop
is smooth at the tick rate (issue 35, after the first second; ``effort_smoothness``): the
efforts' tick-rate oscillation (75th percentile, worst joint) and their rms change per tick, in
percent of the effort limits, and the percentage of ticks at which the base's angular rate (the
bipeds' pitch rate) zigzags.
"""

from __future__ import annotations

import argparse
import json
import platform
from pathlib import Path

from virtual_actuators.demos import WALKS, run_walk

CASES = {
    "turkey-flat": ("turkey-walk", "flat", 20.0),
    "flamingo-flat": ("flamingo-slopes", "flat", 30.0),
    "flamingo-profile-one": ("flamingo-slopes", "profile-one", 40.0),
    "flamingo-profile-two": ("flamingo-slopes", "profile-two", 45.0),
    "flamingo-one-0.5": ("flamingo-slopes", "profile-one", 40.0, 0.5),
    "flamingo-two-0.5": ("flamingo-slopes", "profile-two", 40.0, 0.5),
    "hexapod-line": ("hexapod-walk", "flat", 10.0),
}
COLUMNS = (  # key, title, format of the value (times the scale)
    ("fell", "fell", "{}"),
    ("distance_m", "dist [m]", "{:.2f}"),
    ("mean_speed_mps", "speed [m/s]", "{:.3f}"),
    ("height_dev_m", "|dz| [m]", "{:.3f}"),
    ("pitch_max_abs_rad", "|pitch| [rad]", "{:.3f}"),
    ("steps", "steps", "{}"),
    ("step_time_mean_s", "step [s]", "{:.2f}"),
    ("stance_normal_min_n", "min Fn [N]", "{:.1f}"),
    ("stance_friction_ratio_max", "max Ft/Fn", "{:.2f}"),
    ("realtime_factor", "x real time", "{:.2f}"),
    ("effort_oscillation", "osc [%]", "{:.3f}", 100.0),
    ("effort_change_rms", "chg [%/tick]", "{:.2f}", 100.0),
    ("base_rate_alternation", "rate alt [%]", "{:.1f}", 100.0),
)


def main() -> None:
    """Run the cases, print the table, optionally write JSON and plots."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", choices=sorted(CASES), action="append")
    parser.add_argument("--json", default=None)
    parser.add_argument("--plots", default=None, help="folder for one PNG per case")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    args = parser.parse_args()
    results = {}
    header = f"{'case':<22}" + "".join(f"{title:>14}" for _, title, *_ in COLUMNS)
    print("each walk shows a progress bar on stderr; the table goes to stdout", flush=True)
    print(header)
    for case in args.only or CASES:
        walk, terrain, duration, *speed = CASES[case]
        result = run_walk(
            walk,
            duration=duration,
            terrain=terrain,
            speed=speed[0] if speed else None,
            progress=not args.quiet,
        )
        metrics = {k: v for k, v in result.to_json().items() if k not in ("trace", "config")}
        figures = result.figures()  # the same columns for every walk
        metrics.update(distance_m=figures.distance, mean_speed_mps=figures.mean_speed)
        results[case] = metrics
        cells = []
        for key, _, fmt, *scale in COLUMNS:
            value = metrics.get(key)
            shown = "-" if value is None else fmt.format(abs(value * scale[0]) if scale else value)
            cells.append(f"{shown:>14}")
        print(f"{case:<22}" + "".join(cells), flush=True)
        if args.plots:
            folder = Path(args.plots)
            folder.mkdir(parents=True, exist_ok=True)
            WALKS[walk].plot(result, folder / f"{case}.png", None)
    if args.json:
        Path(args.json).parent.mkdir(parents=True, exist_ok=True)
        payload = {"machine": platform.platform(), "python": platform.python_version(), **results}
        Path(args.json).write_text(json.dumps(payload, indent=2, sort_keys=True))
        print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
