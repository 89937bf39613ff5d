"""The 1996 hexapod walking in MuJoCo: lines, circles, sine waves, a pendulum, tracking.

A fall is a part other than a foot touching the ground, the body below half its nominal height,
roll or pitch beyond 0.8 rad, or the pendulum beyond ``HexapodParameters.pendulum_fall``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from ...experiments.recorder import Recorder
from ...models.catalog import robots_dir
from ...models.loader import load_robot
from ...models.robot import Robot
from ...simulation.simulator import Simulator
from ...simulation.terrain import Terrain
from ..base import Walk
from ..guidance import PlanarState
from ..registered import ConfiguredResult, WalkRequest
from ..runner import terrain_points, trace_of
from ..smoothness import loop_smoothness
from ..walk_loop import drive
from .config import HexapodWalkConfig, command_path
from .episode import TRACE_RATE, HexapodEpisode
from .metrics import HexapodMetrics, compute_hexapod_metrics
from .parameters import HexapodParameters
from .walker import HexapodWalker

CHANNELS = (
    "time",
    "x",
    "y",
    "z",
    "roll",
    "pitch",
    "yaw",
    "vx",
    "vy",
    "vx_heading",
    "vx_command",
    "yaw_rate",
    "fx",
    "pendulum",
    "target_x",
    "target_y",
    "fallen",
)


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
    episode = _prepare(config, parameters)
    end = drive(episode, config.duration, progress, on_tick, stop_on_fall)
    gait, simulator, guidance = episode.gait, episode.simulator, episode.guidance
    episode.recorder.metadata["command_path"] = command_path(config, guidance)
    log = episode.recorder.to_log()
    steps = gait.machine.steps_into(gait.step_states)
    normal_min, ratio_max = episode.stance.figures()
    metrics = compute_hexapod_metrics(log, guidance, steps, end.fall_time, normal_min, ratio_max)
    metrics = _with_timing(metrics, simulator.time, end.wall, end.physics)
    smoothness = loop_smoothness(simulator, end)
    metrics = replace(metrics, **smoothness.metrics_fields())
    return HexapodResult(
        log,
        metrics,
        gait,
        simulator,
        end.wall,
        loop=end,
        smoothness=smoothness,
        config=config,
        ticks=end.ticks,
    )


def _prepare(config: HexapodWalkConfig, parameters: HexapodParameters) -> HexapodEpisode:
    """The robot, its walker, the terrain, the simulator (reset, disturbed), the recorder."""
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
    guidance = config.guidance()
    guidance.begin(PlanarState(0.0, float(q0[0]), float(q0[1]), 0.0, 0.0, 0.0))
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
    return HexapodEpisode(gait, simulator, terrain, recorder, guidance)


def _with_timing(
    metrics: HexapodMetrics, simulated: float, wall: float, physics: float
) -> HexapodMetrics:
    return replace(
        metrics,
        realtime_factor=simulated / wall if wall > 0 else None,
        physics_realtime_factor=simulated / physics if physics > 0 else None,
    )


def run_request(request: WalkRequest) -> HexapodResult:
    """The hexapod's walk as `run_registered` starts it (`Walk.run`).

    Raises:
        InvalidInputError: A bad configuration.
    """
    default = request.walk.default_speed(**request.options) if request.speed is None else None
    config, parameters = request.configured(HexapodWalkConfig, default)
    return run_hexapod_walk(config, parameters, *request.loop)


def plot_hexapod_walk(result: HexapodResult, path: str, window: None = None) -> Path:
    """Draw a hexapod walk (`plot_hexapod`)."""
    from .plots import plot_hexapod

    return plot_hexapod(result.log, path, summary=result.metrics.summary())


def draw_hexapod_walk(result: HexapodResult) -> Any:
    """The matplotlib figure `plot_hexapod_walk` saves."""
    from .plots import draw_hexapod

    return draw_hexapod(result.log, summary=result.metrics.summary())


def _viewer_robot(pendulum: bool = False, **options: Any) -> Robot:
    return hexapod_robot(pendulum)


def hexapod_speed(pendulum: bool = False, track: bool = False, **options: Any) -> float:
    """The hexapod's own desired speed [m/s]: slower with the pendulum or tracking."""
    return 0.2 if (pendulum or track) else 0.4


def hexapod_speeds(
    pendulum: bool = False, track: bool = False, **options: Any
) -> tuple[float, float]:
    """The supported desired speeds [m/s]: slower with the pendulum or tracking (measured)."""
    return (0.1, 0.4) if (pendulum or track) else (0.1, 1.0)


WALK = Walk(
    name="hexapod-walk",
    robot="hexapod",
    run=run_request,
    parameters=HexapodParameters,
    terrain="flat",
    duration=10.0,
    plot=plot_hexapod_walk,
    description="The 1996 hexapod's tripod gait on commanded paths, with a pendulum or "
    "tracking an object (VAC section 4)",
    options=("direction", "yaw_rate", "path", "amplitude", "wavelength", "pendulum", "track"),
    force_scale=1 / 100,
    viewer_robot=_viewer_robot,
    speeds_for=hexapod_speeds,
    nominal_speed=hexapod_speed,
)
