"""Summarise a recorded walking run (`WalkLog`) in the figures of seed 003, section 5."""

from __future__ import annotations

import json
import math
import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

import numpy as np

from virtual_actuators.exceptions import InvalidInputError
from virtual_actuators.experiments.smoothness import SmoothnessFigures
from virtual_actuators.experiments.walk_log import WalkLog, resolve_step_states
from virtual_actuators.vocabulary.arguments import check_number


@dataclass(frozen=True)
class WalkMetrics(SmoothnessFigures):
    """What a walking run achieved. All SI; ``None`` when a quantity could not be measured.

    The smoothness figures (`SmoothnessFigures`) are set by the walk, which has every tick's
    efforts.

    Attributes:
        fell: Whether any tick has ``fallen`` set.
        fall_time_s: Time of the first fallen tick [s], or None.
        duration_s: Time from the first to the last tick [s].
        distance_m: ``x`` at the last tick minus ``x`` at the first [m].
        mean_speed_mps: ``(x(T) - x(t0)) / (T - t0)`` over the statistics window [m/s].
        speed_std_mps: Standard deviation of ``xdot`` (else of ``x``'s differences) [m/s].
        height_dev_m: Largest ``|z - z_setpoint|`` over the window [m].
        height_mean_m: Mean ``z`` over the window [m].
        pitch_max_abs_rad: Largest ``|pitch|`` over the window [rad].
        pitch_dev_rad: Largest ``|pitch - pitch_setpoint|`` over the window [rad].
        steps: Entries into a step (single-support) state while walking.
        step_time_mean_s: Mean time between consecutive step entries [s].
        realtime_factor: ``duration_s / wall_time_s`` (above 1: faster than real time).
        speed_setpoint_mps: The desired speed [m/s] (metadata ``speed_setpoint_mps``, else the
            median of ``xdot_setpoint`` in the window).
        startup_s: The start-up time excluded from the statistics [s].
        window_start_s: Time of the first tick of the statistics window [s].
        window_end_s: Time of the last tick of the statistics window [s].
        samples: Number of ticks in the log.
        step_states: The state names whose entries were counted as steps.
        stance_normal_min_n: Least normal force of a foot in support [N] (`contact_stats`).
        stance_friction_ratio_max: Largest tangential / normal force of a foot in support.
    """

    fell: bool
    fall_time_s: float | None
    duration_s: float
    distance_m: float | None
    mean_speed_mps: float | None
    speed_std_mps: float | None
    height_dev_m: float | None
    height_mean_m: float | None
    pitch_max_abs_rad: float | None
    pitch_dev_rad: float | None
    steps: int
    step_time_mean_s: float | None
    realtime_factor: float | None
    speed_setpoint_mps: float | None
    startup_s: float
    window_start_s: float | None
    window_end_s: float | None
    samples: int
    step_states: tuple[str, ...] = ()
    stance_normal_min_n: float | None = None
    stance_friction_ratio_max: float | None = None

    def to_dict(self) -> dict[str, Any]:
        """The metrics as a JSON-able dict."""
        return {f.name: _plain(getattr(self, f.name)) for f in fields(self)}

    def summary(self) -> str:
        """A one-line human summary, e.g. for a plot title or a log line."""
        parts = [f"{_fmt(self.distance_m, 'm')} in {self.duration_s:z.2f} s"]
        speed = f"mean speed {_fmt(self.mean_speed_mps, 'm/s')}"
        if self.speed_setpoint_mps is not None:
            speed += f" (set {self.speed_setpoint_mps:z.2f})"
        parts.append(speed)
        parts.append(f"height dev {_fmt(self.height_dev_m, 'm', 3)}")
        parts.append(f"|pitch| <= {_fmt(self.pitch_max_abs_rad, 'rad', 3)}")
        steps = f"{self.steps} steps"
        if self.step_time_mean_s is not None:
            steps += f" of {self.step_time_mean_s:z.2f} s"
        parts.append(steps)
        if self.fell:
            parts.append(f"FELL at {self.fall_time_s:z.2f} s")
        if self.realtime_factor is not None:
            parts.append(f"{self.realtime_factor:z.2f}x real time")
        if smoothness := self.smoothness_summary():
            parts.append(smoothness)
        return ", ".join(parts)


def _fmt(value: float | None, unit: str, digits: int = 2) -> str:
    return "n/a" if value is None else f"{value:z.{digits}f} {unit}"


def _plain(value: Any) -> Any:
    """NumPy scalars as Python ones, NaN and infinities as None, tuples as lists."""
    if isinstance(value, bool | np.bool_):
        return bool(value)
    if isinstance(value, int | np.integer):
        return int(value)
    if isinstance(value, float | np.floating):
        value = float(value)
        return value if math.isfinite(value) else None
    if isinstance(value, tuple | list):
        return [_plain(v) for v in value]
    return value


def _nanmax_abs(values: np.ndarray) -> float | None:
    finite = values[np.isfinite(values)]
    return float(np.max(np.abs(finite))) if finite.size else None


def _check_log(log: WalkLog) -> None:
    """Refuse anything but a `WalkLog` of two ticks or more with an ``x`` channel."""
    if not isinstance(log, WalkLog):
        raise InvalidInputError(f"log: expected a WalkLog, got {type(log).__name__}.")
    n = len(log)
    if n < 2:
        raise InvalidInputError(f"log: an empty run ({n} tick{'s' * (n != 1)}); need at least 2.")
    log.channel("x")  # raises, listing the channels the log has


def first_fall(log: WalkLog) -> tuple[bool, float | None, int]:
    """Whether a tick has ``fallen`` above 0.5, the first one's time and index (or ``len(log)``)."""
    if "fallen" in log.data:
        fallen = np.nan_to_num(log["fallen"], nan=0.0) > 0.5
        if np.any(fallen):
            end = int(np.argmax(fallen))
            return True, float(log.time[end]), end
    return False, None, len(log)


def _window(t: np.ndarray, end: int, startup_s: float) -> np.ndarray:
    """The statistics window: walking ticks at or after ``startup_s`` (all if too few)."""
    walking = np.arange(t.size) < end
    window = walking & (t - t[0] >= startup_s)
    if np.count_nonzero(window) < 2 or np.ptp(t[window]) <= 0:
        return walking
    return window


def _speeds(log: WalkLog, window: np.ndarray) -> tuple[float | None, float | None]:
    """Mean speed over the window (from ``x``) and the deviation of ``xdot`` in it."""
    t, x = log.time, log["x"]
    mean_speed = None
    usable = np.flatnonzero(window & np.isfinite(x))
    if usable.size >= 2 and t[usable[-1]] > t[usable[0]]:
        i, j = usable[0], usable[-1]
        mean_speed = float((x[j] - x[i]) / (t[j] - t[i]))
    if log.has("xdot"):
        xdot = log["xdot"][window]
    elif usable.size >= 2:
        xdot = np.gradient(x[usable], t[usable]) if np.all(np.diff(t[usable]) > 0) else np.zeros(0)
    else:
        xdot = np.zeros(0)
    xdot = xdot[np.isfinite(xdot)]
    return mean_speed, float(np.std(xdot)) if xdot.size else None


def _tracking(log: WalkLog, window: np.ndarray, name: str) -> tuple[float | None, float | None]:
    """Mean z (largest |pitch|) in the window and its largest deviation from the set point."""
    if name not in log.data:
        return None, None
    values = log[name][window]
    finite = values[np.isfinite(values)]
    if name == "pitch":
        figure = _nanmax_abs(values)
    else:
        figure = float(np.mean(finite)) if finite.size else None
    if f"{name}_setpoint" not in log.data:
        return figure, None
    return figure, _nanmax_abs(values - log[f"{name}_setpoint"][window])


def _speed_setpoint(log: WalkLog, window: np.ndarray) -> float | None:
    """The desired speed: the metadata's (checked), else the median bunny speed in the window."""
    setpoint = log.metadata.get("speed_setpoint_mps")
    if setpoint is not None:
        try:
            value = float(setpoint)
        except (TypeError, ValueError):
            raise InvalidInputError(
                f"metadata['speed_setpoint_mps']: expected a number, got {setpoint!r}."
            ) from None
        return value if math.isfinite(value) else None
    if "xdot_setpoint" in log.data:
        bunny = log["xdot_setpoint"][window]
        bunny = bunny[np.isfinite(bunny)]
        return float(np.median(bunny)) if bunny.size else None
    return None


def compute_metrics(
    log: WalkLog,
    *,
    startup_s: float = 2.0,
    wall_time_s: float | None = None,
    step_states: Iterable[str] | None = None,
) -> WalkMetrics:
    """Compute what a walking run achieved.

    The walking ticks are those before the first fallen tick. Speed, height and pitch use the
    walking ticks from ``startup_s`` on (all of them when fewer than two are); steps count over
    the walking ticks; duration and distance over the whole log. NaN samples are ignored.

    Args:
        log: The run; needs ``time`` and ``x``; ``xdot``, ``z``, ``z_setpoint``, ``pitch``,
            ``pitch_setpoint``, ``fallen`` and the state are used when present.
        startup_s: Seconds after the first tick left out of the statistics.
        wall_time_s: Wall-clock seconds of the run (else ``metadata["wall_time_s"]``).
        step_states: States whose entries count as steps (else ``metadata["step_states"]``,
            else `default_step_states`).

    Raises:
        InvalidInputError: If the log has fewer than two ticks or no ``x`` channel, or an
            argument is invalid (the message names it).
    """
    _check_log(log)
    startup_s = check_number(startup_s, "startup_s", minimum=0.0)
    wall, what = wall_time_s, "wall_time_s"
    if wall is None:
        wall, what = log.metadata.get("wall_time_s"), "metadata['wall_time_s']"
    wall = None if wall is None else check_number(wall, what, positive=True)

    t, x = log.time, log["x"]
    duration = float(t[-1] - t[0])
    fell, fall_time, end = first_fall(log)

    window = _window(t, end, startup_s)
    finite_x = np.flatnonzero(np.isfinite(x))
    distance = float(x[finite_x[-1]] - x[finite_x[0]]) if finite_x.size else None

    mean_speed, speed_std = _speeds(log, window)
    height_mean, height_dev = _tracking(log, window, "z")
    pitch_max, pitch_dev = _tracking(log, window, "pitch")

    names = resolve_step_states(log.state_names, log.metadata, step_states)
    entries = log.entries(names)
    entries = entries[entries < end]
    steps = int(entries.size)
    step_time = float(np.mean(np.diff(t[entries]))) if entries.size >= 2 else None
    return WalkMetrics(
        fell=fell,
        fall_time_s=fall_time,
        duration_s=duration,
        distance_m=distance,
        mean_speed_mps=mean_speed,
        speed_std_mps=speed_std,
        height_dev_m=height_dev,
        height_mean_m=height_mean,
        pitch_max_abs_rad=pitch_max,
        pitch_dev_rad=pitch_dev,
        steps=steps,
        step_time_mean_s=step_time,
        realtime_factor=duration / wall if wall is not None else None,
        speed_setpoint_mps=_speed_setpoint(log, window),
        startup_s=startup_s,
        window_start_s=float(t[window][0]) if np.any(window) else None,
        window_end_s=float(t[window][-1]) if np.any(window) else None,
        samples=len(log),
        step_states=names,
    )


def write_json(metrics: WalkMetrics | Mapping[str, Any], path: str | os.PathLike[str]) -> Path:
    """Write metrics (a `WalkMetrics` or a dict) to ``path`` as sorted JSON; return ``path``.

    NaN is written as null; parents are created.

    Raises:
        InvalidInputError: If a value cannot be written as JSON (the message names its key).
    """
    if isinstance(metrics, WalkMetrics):
        data = metrics.to_dict()
    elif isinstance(metrics, Mapping):
        data = {str(k): _plain(v) for k, v in metrics.items()}
    else:
        raise InvalidInputError(
            f"metrics: expected WalkMetrics or a dict, got {type(metrics).__name__}."
        )
    for key, value in data.items():
        try:
            json.dumps(value, allow_nan=False)
        except (TypeError, ValueError) as err:
            raise InvalidInputError(f"metrics[{key!r}]: not JSON-able ({err}).") from None
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(data, indent=2, sort_keys=True, allow_nan=False) + "\n")
    return path
