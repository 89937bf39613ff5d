"""What every walk shares: its result, the fall test and the terrain drawn under it.

A walk's closed loop (the planar bipeds' in :mod:`~virtual_actuators.gaits.planar_walk`, the
hexapod's in :mod:`~virtual_actuators.gaits.hexapod.walk`) judges the robot fallen with
:func:`has_fallen`: a part other than a foot touches the ground, the hip drops below half its
nominal height above the terrain, or the body tilts beyond :data:`FALL_PITCH`.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from ..experiments.metrics import WalkMetrics
from ..experiments.walk_log import WalkLog
from ..simulation.simulator import Simulator
from ..simulation.terrain import Terrain
from .base import Gait

FOOT_WORDS = ("foot", "heel", "toe")
FALL_PITCH = 0.8  # [rad]


class WalkFigures(NamedTuple):
    """The figures a sweep tabulates of one walk (NaN: not measured)."""

    fell: bool
    fall_time: float  # [s]
    distance: float  # [m]
    mean_speed: float  # [m/s]
    steps: int


def number(value: float | None) -> float:
    """``value`` as a float, NaN for None."""
    return float("nan") if value is None else float(value)


@dataclass
class WalkResult:
    """What a walk produced.

    Attributes:
        log: Every control tick.
        metrics: The summary (``metrics.to_dict()`` is the JSON).
        gait: The gait (its state machine history included).
        simulator: The simulator in its final state.
        wall_time: Wall-clock seconds of the loop.
        extra: Anything a caller attaches.

    """

    log: WalkLog
    metrics: WalkMetrics
    gait: Gait
    simulator: Simulator
    wall_time: float
    extra: dict = field(default_factory=dict)

    def figures(self) -> WalkFigures:
        """What a sweep tabulates."""
        m = self.metrics
        return WalkFigures(
            bool(m.fell),
            number(m.fall_time_s),
            number(m.distance_m),
            number(m.mean_speed_mps),
            int(m.steps),
        )

    def to_json(self) -> dict[str, Any]:
        """What ``--json`` writes: the metrics as a JSON-able dict."""
        return self.metrics.to_dict()

    def __repr__(self) -> str:
        return f"WalkResult({self.metrics.summary()})"


def terrain_points(terrain: Terrain, duration: float) -> np.ndarray:
    """Terrain vertices for plots: at least two, covering the walk's likely reach."""
    points = np.asarray(terrain.points, dtype=float)
    reach = max(1.5 * duration, float(points[-1, 0]) + 1.0)  # [m], 1.5 m/s at most
    start = min(-1.0, float(points[0, 0]) - 1.0)
    return np.vstack(
        ([start, float(terrain.height(start))], points, [reach, float(terrain.height(reach))])
    )


def has_fallen(simulator: Simulator, height: float, pitch: float, nominal: float) -> bool:
    """Whether a walker fell (hip low, body tilted, or something else than a foot down).

    Fallen: the hip below half its ``nominal`` height above the terrain, the body tilted beyond
    :data:`FALL_PITCH`, or a part other than a foot touching the ground.

    Args:
        simulator: The simulation (its terrain contacts).
        height: Hip height above the terrain [m].
        pitch: Body tilt [rad].
        nominal: Nominal hip height [m].

    """
    if height < 0.5 * nominal or abs(pitch) > FALL_PITCH:
        return True
    return not _only_feet(simulator.touching_frames())


@functools.lru_cache(maxsize=256)
def _only_feet(frames: frozenset[str]) -> bool:
    """Whether every frame of a contact set is a foot's (cached: the sets recur tick after tick)."""
    return all(map(_is_foot, frames))


@functools.cache
def _is_foot(frame: str) -> bool:
    return any(word in frame for word in FOOT_WORDS)
