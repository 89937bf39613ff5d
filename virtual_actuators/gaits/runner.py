"""The generic gait runner: a walk's `Episode`, its result (`WalkResult`), the fall test.

A walk prepares an `Episode`; [`drive`][virtual_actuators.gaits.walk_loop.drive] runs it on
[`va.run`][virtual_actuators.run]'s loop and the walk summarises the log.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass, field, replace
from typing import Any, NamedTuple

import numpy as np

from ..control.controller import ControlOutput
from ..control.effort_limits import urdf_effort_limits
from ..control.run_loop import RunStats
from ..experiments.contact_stats import StanceForces
from ..experiments.estimation_score import EstimationScore
from ..experiments.metrics import WalkMetrics
from ..experiments.recorder import Recorder
from ..experiments.smoothness import EffortSmoothness, effort_smoothness
from ..experiments.walk_log import WalkLog
from ..simulation.simulator import Simulator
from ..simulation.terrain import Terrain
from .attitude import attitude_and_velocity
from .base import Gait
from .guidance import Guidance, PlanarState, wrap
from .on_estimate import OnEstimate

FOOT_WORDS = ("foot", "heel", "toe")
FALL_PITCH = 0.8  # [rad]
TRACE_RATE = 100.0  # [Hz] the floating-base walks' log


@dataclass(slots=True)
class LoopEnd:
    """How a run of `drive` ended.

    Attributes:
        ticks: Control ticks run.
        fall_time: Simulated time of the first fallen tick [s], None if none.
        wall: Wall-clock seconds of the loop.
        physics: Wall-clock seconds of it in the physics steps.
        efforts: ``(ticks, nv)`` every tick's efforts given to [`Simulator.step`][] [N m or N].
        velocities: ``(ticks, nv)`` every tick's ``v``, the state the gait read.
        base_rate: Where ``v`` holds the base's angular velocity (the episode's), or None.
        fall_tick: Index of the first fallen tick, None if none.
        time_step: Time between two ticks [s].
        run: What ``va.run`` counted ([`RunStats`][]), or None.
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
    run: RunStats | None = None

    @property
    def base_rates(self) -> np.ndarray | None:
        """``(ticks, axes)`` the base's angular velocity at every tick [rad/s], or None."""
        return None if self.base_rate is None else self.velocities[:, self.base_rate]

    def realtime_factors(self, simulated: float) -> dict[str, float | None]:
        """``realtime_factor`` and ``physics_realtime_factor`` (None: not timed) of the loop."""
        return {
            "realtime_factor": simulated / self.wall if self.wall > 0 else None,
            "physics_realtime_factor": simulated / self.physics if self.physics > 0 else None,
        }


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
        log: The walk's rows: every few ticks (250 Hz planar, 100 Hz others) and the last.
        metrics: The summary (``metrics.to_dict()`` is the JSON).
        gait: The gait (its state machine history included).
        simulator: The simulator in its final state.
        wall_time: Wall-clock seconds of the loop.
        loop: How the loop ended, with every tick's efforts and base rates (`LoopEnd`).
        smoothness: Its `loop_smoothness`.
        estimation: The estimator's score when the walk ran on the estimate, else None.
    """

    log: WalkLog
    metrics: WalkMetrics
    gait: Gait
    simulator: Simulator
    wall_time: float
    loop: LoopEnd | None = None
    smoothness: EffortSmoothness | None = None
    estimation: EstimationScore | None = None

    def estimation_json(self) -> dict[str, Any]:
        """``estimate`` (the estimated base's trace) and ``estimation`` (its score), or {}."""
        return {} if self.estimation is None else self.estimation.to_json()

    def figures(self) -> WalkFigures:
        """What a sweep tabulates."""
        m = self.metrics
        distance, speed = number(m.distance_m), number(m.mean_speed_mps)
        return WalkFigures(bool(m.fell), number(m.fall_time_s), distance, speed, int(m.steps))

    def to_json(self) -> dict[str, Any]:
        """What ``--json`` writes: the metrics as a JSON-able dict."""
        return self.metrics.to_dict()

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.metrics.summary()})"


@dataclass
class ConfiguredResult(WalkResult):
    """A walk's result with its configuration and tick count.

    Attributes:
        config: What was walked.
        ticks: Control ticks run.
    """

    config: Any = None
    ticks: int = 0

    def trace(self) -> dict[str, list]:
        """Equal-length lists of the walk's trace (here `trace_of` the log)."""
        return trace_of(self.log)

    def figures(self) -> WalkFigures:
        """What a sweep tabulates (the distance is the straight line from start to end)."""
        m, x, y = self.metrics, self.log["x"], self.log["y"]
        distance = math.hypot(x[-1] - x[0], y[-1] - y[0]) if len(x) else math.nan
        return WalkFigures(
            bool(m.fell), number(m.fall_time_s), distance, number(m.speed_mps), int(m.steps)
        )

    def to_json(self) -> dict[str, Any]:
        """``fell``, ``realtime_factor``, the summary figures, ``ticks``, ``config``, ``trace``."""
        figures, config = asdict(self.metrics), asdict(self.config)
        trace = {"trace": self.trace(), **self.estimation_json()}
        return {**figures, "ticks": self.ticks, "config": config, **trace}


#: The base's channels of a JSON trace (``demo legged``, ``demo balance``).
TRACE_CHANNELS = ("x", "y", "z", "roll", "pitch", "yaw", "vx", "vy")


def trace_of(log: WalkLog, extra: tuple[str, ...] = ()) -> dict[str, list]:
    """A walk log's trace: ``t``, `TRACE_CHANNELS` and ``extra`` lists, and ``state``."""
    trace = {"t": log.time.tolist(), **{name: log[name].tolist() for name in TRACE_CHANNELS}}
    trace.update({name: log[name].tolist() for name in extra})
    trace["state"] = [log.state_names[i] for i in log.state]
    return trace


def summary_line(metrics: Any, parts: list[str], labelled: tuple, after: tuple = ()) -> str:
    """``parts``, the ``(label, value)`` measured, ``after``, the fall, real time, smoothness.

    ``metrics`` has ``fell``, ``fall_time_s``, ``realtime_factor``, ``physics_realtime_factor``
    and ``smoothness_summary()``.
    """
    parts += [f"{label} {value:z.3f}" for label, value in labelled if value is not None]
    parts += after
    if metrics.fell:
        parts.append(f"FELL at {metrics.fall_time_s:z.2f} s")
    if metrics.realtime_factor is not None:
        parts.append(
            f"{metrics.realtime_factor:z.2f}x real time (MuJoCo alone "
            f"{metrics.physics_realtime_factor:z.1f}x)"
        )
    if smoothness := metrics.smoothness_summary():
        parts.append(smoothness)
    return ", ".join(parts)


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
    """Whether a walker fell: hip under half ``nominal``, tilt over `FALL_PITCH`, a non-foot down.

    Args:
        simulator: The simulation (its terrain contacts).
        height: Hip height above the terrain [m].
        pitch: Body tilt [rad].
        nominal: Nominal hip height [m].
        feet: The geoms allowed to touch, `foot_geoms` (an episode's ``feet``).
    """
    return height < 0.5 * nominal or abs(pitch) > FALL_PITCH or simulator.touches_outside(feet)


def allowed_geoms(simulator: Simulator, allowed: Callable[[str], bool]) -> np.ndarray:
    """``(ngeom,)`` int8: 1 for a geom every frame owning which is ``allowed``.

    The geoms that may touch the ground without a fall (for
    [`touches_outside`][virtual_actuators.simulation.Simulator.touches_outside]).
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


class Episode(OnEstimate):
    """One walk being run: what `drive` steps, and the walk's own hooks.

    A walk subclasses it with `sense`, `fallen` and `record`.

    Args:
        gait: The gait (its controller warmed up by `drive`).
        simulator: The simulation, reset and pushed.
        terrain: The terrain.
        recorder: Where `record` writes.

    Attributes:
        stance_every: Ticks between two readings of the stance forces (None: `record_every`,
            the trace's rate).
        record_every: Ticks between two calls of `record`.
        ignore_unactuated: Passed to [`Simulator.step`][].
        stance: The stance forces read so far.
        feet: The geoms allowed to touch the ground, `foot_geoms` (for `has_fallen`).
        base_rate: Where ``v`` holds the base's angular velocity (a free-flyer's ``v[3:6]``,
            body axes), or None.
        level: The terrain's one height when it is flat [m], else None.
    """

    stance_every: int | None = None
    record_every = 1
    ignore_unactuated = False

    def __init__(
        self, gait: Gait, simulator: Simulator, terrain: Terrain, recorder: Recorder
    ) -> None:
        self.gait = gait
        self.simulator = simulator
        self.terrain = terrain
        self.recorder = recorder
        self.stance = StanceForces(simulator)
        self.feet = foot_geoms(simulator)
        self.base_rate: slice | None = slice(3, 6) if simulator.robot.floating_base else None
        self.level: float | None = float(terrain.height(0.0)) if terrain.is_flat else None

    def sense(self, q: np.ndarray, v: np.ndarray, now: float) -> Mapping[str, bool]:
        """Before the gait computes: steer it if need be; the contact switches it reads."""
        raise NotImplementedError

    def height(self, q: np.ndarray) -> float:
        """The floating base's height above the terrain under it [m]."""
        level = self.level
        return q.item(2) - (float(self.terrain.height(q.item(0))) if level is None else level)

    def fallen(self, q: np.ndarray) -> bool:
        """Whether the robot has fallen (asked until it first has)."""
        raise NotImplementedError

    def record(
        self, now: float, q: np.ndarray, v: np.ndarray, output: ControlOutput, fallen: bool
    ) -> None:
        """Record a tick (every `record_every` ticks)."""
        raise NotImplementedError

    def finish(
        self, end: LoopEnd, log: WalkLog, metrics: Any, result: type = WalkResult, **fields: Any
    ) -> Any:
        """The finished run's ``result`` (with ``fields``), its metrics with `loop_smoothness`."""
        smoothness = loop_smoothness(self.simulator, end)
        metrics = replace(metrics, **smoothness.metrics_fields())
        return result(
            log, metrics, self.gait, self.simulator, end.wall, loop=end, smoothness=smoothness,
            estimation=self.estimation, **fields,
        )  # fmt: skip


class FloatingEpisode(Episode):
    """A floating base's walk at `TRACE_RATE`, steered by a guidance through ``set_command``.

    Args:
        gait: The gait (with ``set_command(velocity, yaw_rate)``).
        simulator: The simulation, reset.
        terrain: The terrain.
        recorder: Where `record` writes.
        guidance: What steers the gait (begun here, at the base's start pose).

    Attributes:
        guidance: The guidance; a fixed one sets the command once, here.
        command: The heading-frame velocity last commanded [m/s].
        attitude: This tick's yaw, pitch, roll [rad] and world x, y velocity [m/s].
        nominal: The gait's nominal height [m] (half of it: fallen).
    """

    ignore_unactuated = True

    def __init__(
        self, gait: Gait, simulator: Simulator, terrain: Terrain, recorder: Recorder,
        guidance: Guidance,
    ) -> None:  # fmt: skip
        super().__init__(gait, simulator, terrain, recorder)
        self.record_every = max(1, round(1.0 / (TRACE_RATE * simulator.control_period)))
        q = simulator.q
        self.attitude = attitude_and_velocity(q, simulator.v)
        self.guidance, self.nominal = guidance, gait.nominal_height()
        guidance.begin(PlanarState(0.0, q.item(0), q.item(1), self.attitude[0], 0.0, 0.0))
        self.command = np.zeros(2)
        if guidance.fixed:  # set once: the state does not change it
            start = PlanarState(simulator.time, *guidance.start, 0.0, 0.0)
            self.command, yaw_rate = guidance.command(start)
            gait.set_command(self.command, yaw_rate)
        self._yaw = self._yaw_last = 0.0

    def sense(self, q: np.ndarray, v: np.ndarray, now: float) -> Mapping[str, bool]:
        """Steer the gait along the guidance; the feet's contact switches."""
        self.attitude = yaw, _, _, vx, vy = attitude_and_velocity(q, v)
        if not self.guidance.fixed:
            state = PlanarState(now, q.item(0), q.item(1), yaw, vx, vy)
            self.command, yaw_rate = self.guidance.command(state)
            self.gait.set_command(self.command, yaw_rate)
        return self.contact_switches()

    def fallen(self, q: np.ndarray) -> bool:
        """Base low or tilted, or something else than a foot down (`has_fallen`)."""
        _, pitch, roll, _, _ = self.attitude
        tilt = max(abs(roll), abs(pitch))
        return has_fallen(self.simulator, self.height(q), tilt, self.nominal, self.feet)

    def trace_row(self, now: float, q: np.ndarray) -> tuple:
        """``time`` and `TRACE_CHANNELS` of this tick, the yaw continuous since the start.

        Called once per recorded row (it unwraps the yaw).
        """
        yaw, pitch, roll, vx, vy = self.attitude
        self._yaw += wrap(yaw - self._yaw_last)
        self._yaw_last = yaw
        return now, q.item(0), q.item(1), self.height(q), roll, pitch, self._yaw, vx, vy


def loop_smoothness(simulator: Simulator, end: LoopEnd) -> EffortSmoothness:
    """`effort_smoothness` of a loop's ticks before its fall, on the motors the simulation drives.

    Each degree of freedom is named by its joint; the limits are the URDF's effort limits of the
    actuated joints [N m or N] (``inf`` elsewhere).

    Raises:
        InvalidInputError: Non-finite efforts or base rates in the record.
    """
    model, actuated = simulator.robot.model, set(simulator.mujoco_model.actuated)
    limits, names = urdf_effort_limits(simulator.robot), [""] * model.nv
    for j in range(1, model.njoints):
        joint = model.joints[j]
        dofs = slice(joint.idx_v, joint.idx_v + joint.nv)
        names[dofs] = [model.names[j]] * joint.nv
        if model.names[j] not in actuated:
            limits[dofs] = np.inf
    until = end.ticks if end.fall_tick is None else end.fall_tick
    rates = None if end.base_rates is None else end.base_rates[:until]
    efforts = end.efforts[:until]
    return effort_smoothness(efforts, limits, rates, time_step=end.time_step, names=names)
