"""The 1996 hexapod walking in MuJoCo: lines, circles, sine waves, a pendulum, tracking.

A fall is a part other than a foot touching the ground, the body below half its nominal height,
roll or pitch beyond 0.8 rad, or the pendulum beyond ``HexapodParameters.pendulum_fall``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import asdict, dataclass, field, replace
from typing import Any

import numpy as np

from ...control.controller import ControlOutput
from ...experiments.recorder import Recorder
from ...models.catalog import robots_dir
from ...models.loader import load_robot
from ...models.robot import Robot
from ...simulation.simulator import Simulator
from ...simulation.terrain import Terrain
from ..base import Walk
from ..guidance import Guidance, SinePath, TrackObject, check_path, path_guidance
from ..runner import (
    TRACE_CHANNELS,
    TRACE_RATE,
    ConfiguredResult,
    FloatingEpisode,
    terrain_points,
    trace_of,
)  # fmt: skip
from ..walk_loop import drive
from .metrics import HexapodMetrics, compute_hexapod_metrics
from .parameters import HexapodParameters
from .walker import HexapodWalker

_OWN_CHANNELS = ("vx_heading", "vx_command", "yaw_rate", "fx", "pendulum", "target_x", "target_y")
CHANNELS = ("time", *TRACE_CHANNELS, *_OWN_CHANNELS, "fallen")
#: The attachments whose components move the body, in the order its wrench is read from.
BODY_ATTACHMENTS = ("support_a", "support_b", "support_all")


@dataclass(frozen=True)
class HexapodWalkConfig:
    """What to walk (SI units, angles in radians).

    Attributes:
        speed: Body speed [m/s].
        direction: Travel direction relative to the heading [rad].
        yaw_rate: [rad/s] (line path only: a circle of radius ``speed / yaw_rate``).
        path: ``"line"`` (the velocity fixed in the body frame) or ``"sine"``.
        amplitude: Sine amplitude [m].
        wavelength: Sine wavelength [m].
        pendulum: Balance the pendulum (its LQR owns the x motion).
        track: Face an object circling the start while walking.
        terrain: A `Terrain.parse` spec (profiles run along the world x axis).
        duration: Simulated time [s].
        seed: Random initial disturbance (body velocity, pendulum angle); None for none.
        distribution: ``"qp"`` or ``"partitioned"``.
        estimator: Walk on a `LeggedEstimator` fed by the simulated sensors.

    Raises:
        InvalidInputError: Values that do not hold together (`check_path`).
    """

    speed: float = 0.4
    direction: float = 0.0
    yaw_rate: float = 0.0
    path: str = "line"
    amplitude: float = 0.2
    wavelength: float = 2.0
    pendulum: bool = False
    track: bool = False
    terrain: str = "flat"
    duration: float = 10.0
    seed: int | None = None
    distribution: str = "qp"
    estimator: bool = False

    def __post_init__(self) -> None:
        check_path(self)


def command_path(config: HexapodWalkConfig, guidance: Guidance) -> np.ndarray:
    """The commanded path, ``(n, 2)`` world points [m] (the object's circle when tracking)."""
    x0, y0, yaw0 = guidance.start
    reach = max(config.speed * config.duration, 1e-3)
    if isinstance(guidance, TrackObject):
        angles = np.linspace(0.0, 2.0 * np.pi, 181)
        return np.c_[x0 + guidance.radius * np.cos(angles), y0 + guidance.radius * np.sin(angles)]
    if isinstance(guidance, SinePath):
        along = np.linspace(0.0, reach, 400)
        across = guidance.curve(along)
    elif config.yaw_rate != 0.0 and config.speed > 0.0:
        radius = config.speed / abs(config.yaw_rate)
        sweep = min(abs(config.yaw_rate) * config.duration, 2.0 * np.pi)
        angles = np.linspace(0.0, sweep, 181) * np.sign(config.yaw_rate)
        # start at the origin heading along the travel direction, centre on the turning side
        side = np.sign(config.yaw_rate) * radius * (1 - np.cos(angles))
        local = np.c_[radius * np.sin(np.abs(angles)), side]
        c, s = math.cos(config.direction), math.sin(config.direction)
        along, across = c * local[:, 0] - s * local[:, 1], s * local[:, 0] + c * local[:, 1]
    else:
        distances = np.linspace(0.0, reach, 2)
        along = distances * math.cos(config.direction)
        across = distances * math.sin(config.direction)
    c, s = math.cos(yaw0), math.sin(yaw0)
    return np.c_[x0 + c * along - s * across, y0 + s * along + c * across]


@dataclass
class HexapodResult(ConfiguredResult):
    """What a hexapod walk produced: its log at `TRACE_RATE` (`CHANNELS`), metrics and trace."""

    metrics: HexapodMetrics
    gait: HexapodWalker
    config: HexapodWalkConfig = field(default_factory=HexapodWalkConfig)

    def trace(self) -> dict[str, list[float]]:
        """The body's pose and velocity, ``vx_command``, ``fx``, ``state``, ``pendulum``/target."""
        extra = ["vx_command", "fx"]
        if self.config.pendulum:
            extra.append("pendulum")
        if self.config.track:
            extra += ["target_x", "target_y"]
        return trace_of(self.log, tuple(extra))


def hexapod_robot(pendulum: bool = False) -> Robot:
    """The hexapod, or its variant with the pendulum on its back (``hexapod_pendulum``)."""
    if pendulum:
        return load_robot(robots_dir / "hexapod" / "hexapod_pendulum.urdf", floating_base=True)
    return load_robot("hexapod")


def run_hexapod_walk(
    config: HexapodWalkConfig | None = None,
    parameters: HexapodParameters | None = None,
    progress: bool = True,
    on_tick: Callable[[Simulator, HexapodWalker], None] | None = None,
    stop_on_fall: bool = True,
) -> HexapodResult:
    """Simulate the hexapod walking and measure it.

    Args:
        config: What to walk (default: a 0.4 m/s line for 10 s).
        parameters: Gait constants (default `HexapodParameters` with the config's distribution).
        progress: Show a tqdm progress bar.
        on_tick: Called after every physics step (e.g. a viewer's update).
        stop_on_fall: End the run 0.5 s after the first fallen tick.

    Returns:
        The `HexapodResult`.

    Raises:
        InvalidInputError: A bad terrain spec.
    """
    config = config or HexapodWalkConfig()
    parameters = parameters or HexapodParameters(distribution=config.distribution)
    terrain = Terrain.parse(config.terrain)
    robot = hexapod_robot(config.pendulum)
    gait = HexapodWalker(robot, parameters)
    simulator = Simulator(robot, terrain)
    q0 = gait.initial_configuration()
    q0[2] += float(terrain.height(0.0))
    v0 = np.zeros(robot.model.nv)
    if config.seed is not None:
        rng = np.random.default_rng(config.seed)
        v0[:6] = rng.uniform(-1.0, 1.0, 6) * (0.02, 0.02, 0.01, 0.05, 0.05, 0.05)
        if config.pendulum:
            q0[-1] = rng.uniform(-0.01, 0.01)
    simulator.reset(q0, v0)
    recorder = Recorder(
        CHANNELS,
        state_names=gait.machine.names,
        capacity=int(config.duration * TRACE_RATE) + 16,
        metadata={
            "robot": robot.name,
            "walk": "hexapod-walk",
            "terrain": config.terrain,
            "terrain_points": terrain_points(terrain, config.duration),
            "speed_setpoint_mps": config.speed,
            "nominal_height_m": parameters.height,
            "step_states": list(gait.step_states),
            "double_support_states": ["double_a", "double_b"],
            "config": asdict(config),
        },
    )
    guidance = path_guidance(config)
    episode = HexapodEpisode(gait, simulator, terrain, recorder, guidance)
    if config.estimator:
        episode.use_estimator()
    end = drive(episode, config.duration, progress, on_tick, stop_on_fall)
    recorder.metadata["command_path"] = command_path(config, guidance)
    log = recorder.to_log()
    steps = gait.machine.steps_into(gait.step_states)
    stance = episode.stance.figures()
    metrics = compute_hexapod_metrics(log, guidance, steps, end.fall_time, *stance)
    metrics = replace(metrics, **end.realtime_factors(simulator.time))
    return episode.finish(end, log, metrics, HexapodResult, config=config, ticks=end.ticks)


class HexapodEpisode(FloatingEpisode):
    """The hexapod's walk under `drive`: `CHANNELS` at `TRACE_RATE`, the pendulum's fall."""

    def fallen(self, q: np.ndarray) -> bool:
        """`FloatingEpisode.fallen`, or the pendulum leaning beyond its fall angle."""
        if super().fallen(q):
            return True
        fall, gait = self.gait.parameters.pendulum_fall, self.gait
        return gait.pendulum is not None and abs(gait.pendulum_angle) > fall

    def record(
        self, now: float, q: np.ndarray, v: np.ndarray, output: ControlOutput, fallen: bool
    ) -> None:
        """One sample of `CHANNELS`."""
        gait = self.gait
        yaw, _, _, vx, vy = self.attitude
        target_x, target_y = self.guidance.target(now) or (math.nan, math.nan)
        wrench = next(
            (w for w in map(output.wrench_of, BODY_ATTACHMENTS) if w is not None), np.zeros(6)
        )
        x, y, z, w = q[3:7].tolist()  # the body's world z rate: row z of its rotation . omega
        row_z = 2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)
        c, s = math.cos(yaw), math.sin(yaw)
        base = self.trace_row(now, q)
        own = (  # _OWN_CHANNELS, in its order
            c * vx + s * vy,
            float(self.command[0]),
            sum(r * rate for r, rate in zip(row_z, v[3:6].tolist(), strict=True)),
            c * wrench.item(0) + s * wrench.item(1),
            gait.pendulum_angle if gait.pendulum is not None else math.nan,
            target_x,
            target_y,
        )
        self.recorder.append_row((*base, *own, float(fallen)), gait.machine.current_index)


def draw_hexapod_walk(result: HexapodResult, window: None = None) -> Any:
    """A hexapod walk's figure (`draw_hexapod`, with its summary)."""
    from .plots import draw_hexapod

    return draw_hexapod(result.log, summary=result.metrics.summary())


WALK = Walk(
    name="hexapod-walk",
    robot="hexapod",
    run=lambda request: request.run_with(run_hexapod_walk, HexapodWalkConfig),
    parameters=HexapodParameters,
    duration=10.0,
    draw=draw_hexapod_walk,
    description="The 1996 hexapod's tripod gait on commanded paths, with a pendulum or "
    "tracking an object (VAC section 4)",
    options=(
        "direction", "yaw_rate", "path", "amplitude", "wavelength", "pendulum", "track",
        "estimator",
    ),
    force_scale=1 / 100,
    viewer_robot=lambda pendulum=False, **_: hexapod_robot(pendulum),
    # the supported speeds (measured) and the own one [m/s]: slower with the pendulum or tracking
    speeds=lambda pendulum=False, track=False, **_: (0.1, 0.4 if pendulum or track else 1.0),
    nominal_speed=lambda pendulum=False, track=False, **_: 0.2 if pendulum or track else 0.4,
)
