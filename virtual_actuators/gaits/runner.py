"""The generic gait runner: every walk's closed loop, its result, the fall test and terrain.

A walk prepares an `Episode` (its robot, terrain, gait, simulator with the start-up push,
recorder and stance-force reader: the planar bipeds' in `planar_walk`,
the hexapod's in `walk`); `drive` runs it at the
control rate (read ``q``, ``v`` and the contact switches, let the gait compute the efforts, step
the physics, sample the stance forces, test for a fall, record) and the walk summarises the log.
Every tick's applied efforts and the base's angular rate are kept (`LoopEnd`), for
`loop_smoothness` to measure.
Walks judge the robot fallen with `has_fallen`: a part other than a foot touches the
ground, the hip drops below half its nominal height above the terrain, or the body tilts beyond
`FALL_PITCH`.
"""

from __future__ import annotations

import functools
import math
import time as wallclock
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from ..control.controller import ControlOutput
from ..control.gc_policy import LoopCollector, check_gc_policy
from ..experiments.contact_stats import StanceForces
from ..experiments.metrics import WalkMetrics
from ..experiments.progress import Progress
from ..experiments.recorder import Recorder
from ..experiments.smoothness import EffortSmoothness
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
        loop: How the loop ended, with every tick's efforts and base rates (`LoopEnd`).
        smoothness: Its `loop_smoothness`.

    """

    log: WalkLog
    metrics: WalkMetrics
    gait: Gait
    simulator: Simulator
    wall_time: float
    extra: dict = field(default_factory=dict)
    loop: LoopEnd | None = None
    smoothness: EffortSmoothness | None = None

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


#: The base's channels of a JSON trace (``demo legged``, ``demo balance``).
TRACE_CHANNELS = ("x", "y", "z", "roll", "pitch", "yaw", "vx", "vy")


def trace_of(log: WalkLog, extra: tuple[str, ...] = ()) -> dict[str, list]:
    """A walk log's trace: ``t``, `TRACE_CHANNELS` and ``extra`` lists, and ``state``."""
    trace = {"t": log.time.tolist(), **{name: log[name].tolist() for name in TRACE_CHANNELS}}
    trace.update({name: log[name].tolist() for name in extra})
    trace["state"] = [log.state_names[i] for i in log.state]
    return trace


def terrain_points(terrain: Terrain, duration: float) -> np.ndarray:
    """Terrain vertices for plots: at least two, covering the walk's likely reach."""
    points = np.asarray(terrain.points, dtype=float)
    reach = max(1.5 * duration, float(points[-1, 0]) + 1.0)  # [m], 1.5 m/s at most
    start = min(-1.0, float(points[0, 0]) - 1.0)
    return np.vstack(
        ([start, float(terrain.height(start))], points, [reach, float(terrain.height(reach))])
    )


def has_fallen(
    simulator: Simulator, height: float, pitch: float, nominal: float, feet: np.ndarray
) -> bool:
    """Whether a walker fell (hip low, body tilted, or something else than a foot down).

    Fallen: the hip below half its ``nominal`` height above the terrain, the body tilted beyond
    `FALL_PITCH`, or a part other than a foot touching the ground.

    Args:
        simulator: The simulation (its terrain contacts).
        height: Hip height above the terrain [m].
        pitch: Body tilt [rad].
        nominal: Nominal hip height [m].
        feet: The geoms allowed to touch, `foot_geoms` (an episode's ``feet``).

    """
    if height < 0.5 * nominal or abs(pitch) > FALL_PITCH:
        return True
    return simulator.touches_outside(feet)


def allowed_geoms(simulator: Simulator, allowed: Callable[[str], bool]) -> np.ndarray:
    """``(ngeom,)`` int8: 1 for a geom every frame owning which is ``allowed``.

    The geoms that may touch the ground without a fall: a frame touches when a geom it owns does
    ([`touching_frames`][virtual_actuators.simulation.Simulator.touching_frames]), so the
    touching frames are all allowed exactly when no other geom touches
    ([`touches_outside`][virtual_actuators.simulation.Simulator.touches_outside]).
    """
    owners = simulator.mujoco_model.geom_frames
    flags = [all(map(allowed, owners.get(geom, ()))) for geom in range(simulator.model.ngeom)]
    return np.array(flags, dtype=np.int8)


def foot_geoms(simulator: Simulator) -> np.ndarray:
    """`allowed_geoms` of the foot frames (a name with one of `FOOT_WORDS`)."""
    return allowed_geoms(simulator, _is_foot)


@functools.cache
def _is_foot(frame: str) -> bool:
    return any(word in frame for word in FOOT_WORDS)


class Episode:
    """One walk being run: what `drive` steps, and the walk's own hooks.

    A walk subclasses it with `sense`, `fallen` and `record`.

    Args:
        gait: The gait (its controller warmed up by `drive`).
        simulator: The simulation, reset and pushed.
        terrain: The terrain.
        recorder: Where `record` writes.

    Attributes:
        stance_every: Ticks between two readings of the stance forces.
        record_every: Ticks between two calls of `record`.
        ignore_unactuated: Passed to [`Simulator.step`][].
        stance: The stance forces read so far.
        feet: The geoms allowed to touch the ground, `foot_geoms` (for `has_fallen`).
        native: Builds the gait's tick in the compiled core (a `Walk`'s ``native``), or None.
        base_rate: Where ``v`` holds the base's angular velocity (a free-flyer's ``v[3:6]``,
            body axes), or None.

    """

    stance_every = 1
    record_every = 1
    ignore_unactuated = False

    def __init__(
        self, gait: Gait, simulator: Simulator, terrain: Terrain, recorder: Recorder
    ) -> None:
        self.gait = gait
        self.simulator = simulator
        self.terrain = terrain
        self.recorder = recorder
        self.stance = StanceForces(simulator, terrain)
        self.feet = foot_geoms(simulator)
        self.native: Callable[[Gait], Any] | None = None
        self.base_rate: slice | None = slice(3, 6) if simulator.robot.floating_base else None

    def sense(self, q: np.ndarray, v: np.ndarray, now: float) -> Mapping[str, bool]:
        """Before the gait computes: steer it if need be; the contact switches it reads."""
        raise NotImplementedError

    def fallen(self, q: np.ndarray) -> bool:
        """Whether the robot has fallen (asked until it first has)."""
        raise NotImplementedError

    def record(
        self, now: float, q: np.ndarray, v: np.ndarray, output: ControlOutput, fallen: bool
    ) -> None:
        """Record a tick (every `record_every` ticks)."""
        raise NotImplementedError


@dataclass(slots=True)
class LoopEnd:
    """How a run of `drive` ended.

    Attributes:
        ticks: Control ticks run.
        fall_time: Simulated time of the first fallen tick [s], None if none.
        wall: Wall-clock seconds of the loop.
        physics: Wall-clock seconds of it in the physics steps.
        efforts: ``(ticks, nv)`` every tick's efforts, the gait's output given to
            [`Simulator.step`][] [N m or N].
        velocities: ``(ticks, nv)`` every tick's ``v``, the state the gait read.
        base_rate: Where ``v`` holds the base's angular velocity (the episode's), or None.
        fall_tick: Index of the first fallen tick, None if none.
        time_step: Time between two ticks [s].

    """

    ticks: int = 0
    fall_time: float | None = None
    wall: float = 0.0
    physics: float = 0.0
    efforts: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    velocities: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    base_rate: slice | None = None
    fall_tick: int | None = None
    time_step: float = 1e-3

    @property
    def base_rates(self) -> np.ndarray | None:
        """``(ticks, axes)`` the base's angular velocity at every tick [rad/s], or None."""
        return None if self.base_rate is None else self.velocities[:, self.base_rate]


def drive(
    episode: Episode,
    duration: float,
    progress: bool = True,
    on_tick: Callable[[Simulator, Gait], None] | None = None,
    stop_on_fall: bool = True,
    gc_policy: str = "between-ticks",
) -> LoopEnd:
    """Run an episode's closed loop for ``duration`` simulated seconds.

    Args:
        episode: The prepared walk.
        duration: Simulated time [s].
        progress: Show a tqdm progress bar.
        on_tick: Called after every physics step (e.g. a viewer's throttled update).
        stop_on_fall: End the run 0.5 s after the first fallen tick.
        gc_policy: Python's garbage collector during the loop (see
            [`gc_policy`][virtual_actuators.control.gc_policy]): ``"between-ticks"`` collects after
            each tick's recording when CPython would have, never inside the gait's compute or
            the physics step; ``"python"`` leaves it alone.

    Returns:
        The `LoopEnd` (the recorder's metadata gets ``wall_time_s``).

    Raises:
        InvalidInputError: An unknown ``gc_policy``.

    """
    collector = LoopCollector(check_gc_policy(gc_policy, "drive()"))
    simulator = episode.simulator
    bar = Progress(duration) if progress else None
    episode.gait.warm_up(simulator.q)  # lowered, kernels loaded before the clock starts
    with collector:
        start = wallclock.perf_counter()
        end = _loop(episode, duration, bar, on_tick, stop_on_fall, collector)
        end.wall = wallclock.perf_counter() - start
    if bar is not None:
        bar.close(simulator.time)
    episode.recorder.metadata["wall_time_s"] = end.wall
    return end


def _loop(
    episode: Episode,
    duration: float,
    bar: Progress | None,
    on_tick: Callable[[Simulator, Gait], None] | None,
    stop_on_fall: bool,
    collector: LoopCollector,
) -> LoopEnd:
    """The control loop: read, contacts, compute, step, stance forces, fall test, record.

    Then the garbage collector's turn ([`LoopCollector.between_ticks`][]).

    The gait computes the first tick (its state machine starts); then, without ``on_tick``
    (which may read the gait's [`ControlOutput`][]), the episode's
    ``native`` tick computes the others when the compiled core can run the gait: the same
    efforts, bit for bit (its ticks answer the efforts, the active attachments and their
    wrenches, which is what `record` reads). Every tick's efforts and ``v`` are copied into
    rows allocated before the loop.
    """
    gait, simulator = episode.gait, episode.simulator
    native, compute = (episode.native if on_tick is None else None), gait.compute
    native_tick = None
    stance_every, record_every = episode.stance_every, episode.record_every
    ignore = episode.ignore_unactuated
    data = simulator.data  # MuJoCo's state: its time read directly (a tick's cost)
    period = simulator.control_period
    capacity = max(0, math.ceil((duration - data.time) / period)) + 2
    efforts = np.empty((capacity, simulator.robot.model.nv))  # [N m or N]
    velocities = np.empty_like(efforts)
    tick, physics, fall_time, fall_tick = 0, 0.0, None, None
    while data.time < duration - 1e-9:
        q, v = simulator.q, simulator.v
        now = data.time
        try:
            velocities[tick] = v
        except IndexError:  # a time that did not advance by whole periods
            efforts, velocities = _grown(efforts), _grown(velocities)
            velocities[tick] = v
        output = compute(q, v, now, episode.sense(q, v, now))
        efforts[tick] = output.tau
        mark = wallclock.perf_counter()
        simulator.step(output.tau, ignore_unactuated=ignore)
        physics += wallclock.perf_counter() - mark
        tick += 1
        if fall_time is None and tick % stance_every == 0:
            episode.stance.sample(gait.support_contacts())
        fallen = fall_time is not None or episode.fallen(q)
        if fallen and fall_time is None:
            fall_time, fall_tick = now, tick - 1
        if record_every == 1 or tick % record_every == 1:
            episode.record(now, q, v, output, fallen)
        if on_tick is not None:
            on_tick(simulator, gait)
        if bar is not None and tick % 100 == 0:
            bar.set(simulator.time)
        if stop_on_fall and fall_time is not None and now > fall_time + 0.5:
            break
        collector.between_ticks()
        if native is not None:  # after the first tick: the gait's machine has started
            native, native_tick = None, native(gait)
            if native_tick is not None:
                compute = native_tick.compute
    if native_tick is not None:
        native_tick.sync()  # the gait's objects as the native tick left them
    return LoopEnd(
        tick, fall_time, 0.0, physics, efforts[:tick], velocities[:tick], episode.base_rate,
        fall_tick, period,
    )


def _grown(rows: np.ndarray) -> np.ndarray:
    """``rows`` followed by as many uninitialised rows."""
    return np.concatenate([rows, np.empty_like(rows)])

