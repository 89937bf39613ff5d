"""Any legged robot walking in MuJoCo: ``demo legged``, [`run_legged_walk`][] and its episode.

A fall is the base below half its standing height, tilted beyond 0.8 rad, or a part other than a
foot touching the ground.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict, dataclass, field, replace
from typing import Any

import numpy as np

from ...control.controller import ControlOutput
from ...exceptions import InvalidInputError
from ...experiments.plot_panels import new_figure, set_heading
from ...experiments.recorder import Recorder
from ...models.catalog import ALIASES
from ...models.loader import load_robot
from ...simulation.simulator import Simulator
from ...simulation.terrain import Terrain
from ..base import Walk
from ..guidance import PlanarState, SinePath, TrackObject, check_path, path_guidance
from ..push import Push
from ..runner import (
    TRACE_RATE,
    ConfiguredResult,
    FloatingEpisode,
    allowed_geoms,
    terrain_points,
    trace_of,
)  # fmt: skip
from ..walk_loop import drive
from .metrics import LeggedMetrics, legged_metrics
from .parameters import LeggedParameters
from .patterns import PATTERNS
from .walker import LeggedWalker

CHANNELS = ("time", "x", "y", "z", "roll", "pitch", "yaw", "vx", "vy", "fallen")

#: The legged walk's own desired speed [m/s], before it is moved into the pattern's range.
NOMINAL_SPEED = 0.4

#: The supported desired speeds ``{pattern: {robot (file stem) or None: (low, high)}}`` [m/s],
#: measured (each range's ends walk 4 s on flat ground); another robot gets the ``None`` entry,
#: and the trot has none (an unmeasured robot trots at any speed).
LEGGED_SPEEDS: dict[str, dict[str | None, tuple[float, float]]] = {
    "trot": {
        "go2": (0.1, 1.5),
        "solo12": (0.1, 0.8),
        "anymal": (0.1, 1.0),
        "anymal_c": (0.1, 1.0),
        "hyq_no_sensors": (0.1, 1.0),
    },
    "pace": {None: (0.1, 0.4)},
    "walk": {"hexapod": (0.05, 0.3), None: (0.05, 0.2)},
    "tripod": {None: (0.1, 0.8)},
}


def legged_speeds(
    robot: str = "solo12", gait: str = "trot", **options: Any
) -> tuple[float, float] | None:
    """The supported desired speeds ``(low, high)`` [m/s] of ``robot`` walking ``gait``, or None.

    An unknown pattern gets the trot's (the walk itself refuses it).
    """
    table = LEGGED_SPEEDS.get(gait, LEGGED_SPEEDS["trot"])
    name = ALIASES.get(str(robot), str(robot))
    return table.get(name, table.get(None))


@dataclass(frozen=True)
class LeggedWalkConfig:
    """What to walk (SI units, angles in radians except the push's).

    Attributes:
        robot: A robot name or URDF path for [`load_robot`][].
        gait: ``"trot"``, ``"pace"``, ``"walk"`` or ``"tripod"``.
        feet: Foot frames (None: found on the robot).
        speed: [m/s]; None: `NOMINAL_SPEED` moved into the robot and gait's supported range.
        direction: Travel direction relative to the heading [rad].
        yaw_rate: [rad/s] (the velocity fixed in the body frame: a circle).
        push: A `Push` on the base (or its text, or ``(N, T [s], DEG)``), or None.
        path: ``"line"`` or ``"sine"`` (``y = A sin(2 pi x / L)`` from the start, heading held).
        amplitude: The sine's ``A`` [m].
        wavelength: The sine's ``L`` [m].
        track: Face an object circling the start (line path, no yaw rate).
        terrain: A [`Terrain.parse`][] spec.
        duration: Simulated time [s].
        distribution: ``"qp"`` or ``"partitioned"``.
        seed: An int draws the initial base velocity (up to 0.05 m/s, 0.1 rad/s per axis).
        estimator: Walk on a `LeggedEstimator` fed by the simulated sensors (MEMS IMU,
            encoders) instead of the simulator's state; the truth only scores it.

    Raises:
        InvalidInputError: A value out of its range (`check_path`), or an unknown gait.
    """

    robot: str = "solo12"
    gait: str = "trot"
    feet: tuple[str, ...] | None = None
    speed: float | None = None
    direction: float = 0.0
    yaw_rate: float = 0.0
    push: Push | None = None
    path: str = "line"
    amplitude: float = 0.2
    wavelength: float = 2.0
    track: bool = False
    terrain: str = "flat"
    duration: float = 4.0
    distribution: str = "qp"
    seed: int | None = None
    estimator: bool = False

    def __post_init__(self) -> None:
        if self.speed is None:
            object.__setattr__(self, "speed", WALK.default_speed(robot=self.robot, gait=self.gait))
        check_path(self)
        if self.gait not in PATTERNS:
            raise InvalidInputError(f"gait must be one of {PATTERNS}, got {self.gait!r}.")
        if self.push is not None:
            object.__setattr__(self, "push", Push.of(self.push))


@dataclass
class LeggedResult(ConfiguredResult):
    """A legged walk: the log, [`LeggedMetrics`][], the walker, the simulator, the config."""

    metrics: LeggedMetrics
    gait: LeggedWalker
    config: LeggedWalkConfig = field(default_factory=LeggedWalkConfig)


class LeggedEpisode(FloatingEpisode):
    """A legged walk under `drive`: the push, `CHANNELS` at `TRACE_RATE`."""

    def __init__(
        self, gait: LeggedWalker, simulator: Simulator, terrain: Terrain, recorder: Recorder,
        config: LeggedWalkConfig,
    ) -> None:  # fmt: skip
        super().__init__(gait, simulator, terrain, recorder, path_guidance(config))
        self.config, self.pushed = config, config.push is None
        model = simulator.mujoco_model
        geoms = [geom for foot in gait.feet for geom in model.frame_geoms.get(foot, ())]
        # the frames that may touch the ground: the feet, those sharing a geometry with one
        allowed = frozenset(gait.feet).union(*(model.geom_frames[geom] for geom in geoms))
        self.feet = allowed_geoms(simulator, allowed.__contains__)

    def sense(self, q: np.ndarray, v: np.ndarray, now: float) -> dict[str, bool]:
        """The push when its time comes, then `FloatingEpisode.sense`."""
        if not self.pushed and now >= self.config.push.time:
            self.config.push.apply(self.simulator, self.gait.body_frame)
            self.pushed = True
        return super().sense(q, v, now)

    def record(
        self, now: float, q: np.ndarray, v: np.ndarray, output: ControlOutput, fallen: bool
    ) -> None:
        """One sample of `CHANNELS`."""
        row = (*self.trace_row(now, q), float(fallen))
        self.recorder.append_row(row, self.gait.machine.current_index)


def run_legged_walk(
    config: LeggedWalkConfig | None = None,
    parameters: LeggedParameters | None = None,
    progress: bool = True,
    on_tick: Callable[[Simulator, LeggedWalker], None] | None = None,
    stop_on_fall: bool = True,
) -> LeggedResult:
    """Simulate a legged robot walking and measure it.

    Args:
        config: What to walk (default: solo12 trotting at `NOMINAL_SPEED` for 4 s).
        parameters: Gait choices (default [`LeggedParameters`][] with the config's distribution).
        progress: Show a progress bar.
        on_tick: Called after every physics step (e.g. a viewer's update).
        stop_on_fall: End the run 0.5 s after the first fallen tick.

    Returns:
        The `LeggedResult`.

    Raises:
        InvalidInputError: A bad terrain spec or pattern for this robot.
        RobotNotFoundError: No such robot.
        FrameNotFoundError: No feet found (give ``feet``).
    """
    config = config or LeggedWalkConfig()
    parameters = parameters or LeggedParameters(distribution=config.distribution)
    terrain = Terrain.parse(config.terrain)
    robot = load_robot(config.robot)
    gait = LeggedWalker(robot, config.feet, config.gait, parameters)
    simulator = Simulator(robot, terrain)
    q0 = simulator.on_ground(gait.initial_configuration())
    v0 = np.zeros(robot.model.nv)
    if config.seed is not None:
        scale = np.array((0.05, 0.05, 0.05, 0.1, 0.1, 0.1))  # [m/s, rad/s]
        v0[:6] = np.random.default_rng(config.seed).uniform(-1.0, 1.0, 6) * scale
    simulator.reset(q0, v0)
    recorder = Recorder(
        CHANNELS,
        state_names=gait.machine.names,
        capacity=int(config.duration * TRACE_RATE) + 16,
        metadata={"robot": robot.name, "walk": "legged", "config": asdict(config),
                  "terrain_points": terrain_points(terrain, config.duration)},
    )
    episode = LeggedEpisode(gait, simulator, terrain, recorder, config)
    if config.estimator:
        episode.use_estimator(tuple(gait.feet))
    end = drive(episode, config.duration, progress, on_tick, stop_on_fall)
    log = recorder.to_log()
    steps = gait.machine.steps_into(gait.step_states)
    metrics = legged_metrics(
        trace_of(log), config.speed, config.direction, config.yaw_rate, steps, end.fall_time
    )
    normal_min, ratio_max = episode.stance.figures()
    if isinstance(episode.guidance, SinePath):  # how far from the curve, not which direction
        error = sine_error(episode.guidance, trace_of(log))
        metrics = replace(metrics, direction_error_rad=None, path_error_max_m=error)
    elif isinstance(episode.guidance, TrackObject):  # facing the object, turning at will
        error = bearing_error(episode.guidance, trace_of(log))
        metrics = replace(
            metrics, direction_error_rad=None, heading_drift_rad=None, bearing_error_max_rad=error
        )
    metrics = replace(
        metrics, stance_normal_min_n=normal_min, stance_friction_ratio_max=ratio_max,
        **end.realtime_factors(simulator.time),
    )  # fmt: skip
    return episode.finish(end, log, metrics, LeggedResult, config=config, ticks=end.ticks)


def sine_error(guidance: SinePath, trace: dict[str, list]) -> float:
    """Largest distance across from the commanded sine over the trace's second half [m]."""
    half = len(trace["t"]) // 2
    points = [guidance.to_path(x, y) for x, y in zip(trace["x"], trace["y"], strict=True)]
    return max(
        (abs(across - float(guidance.curve(along))) for along, across in points[half:]),
        default=0.0,
    )


def bearing_error(guidance: TrackObject, trace: dict[str, list], settle: float = 3.0) -> float:
    """Largest ``|bearing to the tracked object - heading|`` after ``settle`` seconds [rad]."""
    return max(
        (
            abs(guidance.bearing_error(PlanarState(t, x, y, yaw, 0.0, 0.0)))
            for t, x, y, yaw in zip(trace["t"], trace["x"], trace["y"], trace["yaw"], strict=True)
            if t >= settle
        ),
        default=0.0,
    )


def draw_legged_walk(result: LeggedResult, window: None = None) -> Any:
    """The path and the attitude of a legged walk, titled by the robot, gait and summary."""
    trace = result.trace()
    figure = new_figure(8.0, 7.0, dpi=100)
    top, bottom = figure.subplots(2, 1)
    top.plot(trace["x"], trace["y"], label="body path")
    top.set(xlabel="x [m]", ylabel="y [m]")
    top.set_aspect("equal", adjustable="datalim")
    title = f"{result.gait.robot.name} ({result.config.gait}): {result.metrics.summary()}"
    set_heading(figure, title, fontsize=9)
    for name in ("roll", "pitch", "yaw"):
        bottom.plot(trace["t"], trace[name], label=name)
    bottom.set(xlabel="t [s]", ylabel="body attitude [rad]")
    bottom.legend()
    return figure


WALK = Walk(
    name="legged",
    robot="solo12",
    run=lambda request: request.run_with(run_legged_walk, LeggedWalkConfig),
    parameters=LeggedParameters,
    duration=4.0,
    draw=draw_legged_walk,
    description="Any legged robot (a name or a URDF path) trotting, pacing or walking with "
    "the public gait layer",
    options=(
        "robot", "gait", "feet", "direction", "yaw_rate", "push", "path", "amplitude",
        "wavelength", "track", "estimator",
    ),
    viewer_robot=lambda robot="solo12", **_: load_robot(robot),
    speeds=legged_speeds,
    nominal_speed=NOMINAL_SPEED,
)
