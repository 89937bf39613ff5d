"""The 1996 hexapod walking in MuJoCo: lines, circles, sine waves, a pendulum, tracking.

`run_hexapod_walk` builds the hexapod (with the pendulum on its back for
``pendulum=True``), its `HexapodWalker`, a guidance that turns the
requested path into the seed's three inputs (`guidance`) and
a [`Simulator`][], then runs the control loop at 1 kHz. The body
state is sampled at `TRACE_RATE` into a `WalkLog`;
`HexapodMetrics` summarises it (the
issue's targets are checked on these figures) and
`HexapodResult.to_json` is what ``--json`` writes. Every tick the feet's contact switches
(MuJoCo's contacts) go to the walker, whose stance ends when its swing tripod is down, and
`StanceForces` reads MuJoCo's contact forces
on the feet the current state has in support (``stance_normal_min_n``,
``stance_friction_ratio_max`` in the JSON).

The robot is judged fallen when a part other than a foot touches the ground, when the body drops
below half its nominal height above the terrain, when it rolls or pitches beyond 0.8 rad, or when
the pendulum leans beyond ``HexapodParameters.pendulum_fall``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from ...control.controller import ControlOutput
from ...exceptions import InvalidInputError
from ...experiments.recorder import Recorder
from ...models.catalog import robots_dir
from ...models.loader import load_robot
from ...models.robot import Robot
from ...simulation.simulator import Simulator
from ...simulation.terrain import Terrain
from ..attitude import attitude_and_velocity, rotation
from ..base import Walk
from ..guidance import Guidance, PlanarState, wrap
from ..runner import (
    Episode,
    WalkFigures,
    WalkResult,
    drive,
    has_fallen,
    number,
    terrain_points,
)
from .config import HexapodWalkConfig, command_path
from .metrics import HexapodMetrics, compute_hexapod_metrics
from .parameters import HexapodParameters
from .walker import HexapodWalker

TRACE_RATE = 100.0  # [Hz] samples of the trace and the log
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
class HexapodResult(WalkResult):
    """What a hexapod walk produced: a walk's result with the hexapod's metrics and trace.

    A `WalkResult` whose ``figures()`` and ``to_json()``
    are the hexapod's own, with its configuration and tick count.

    Attributes:
        log: The body state at `TRACE_RATE` (channels `CHANNELS`).
        metrics: The summary figures.
        gait: The walker (its state machine history included).
        simulator: The simulator in its final state.
        wall_time: Wall-clock seconds of the loop.
        extra: Anything a caller attaches.
        config: The configuration.
        ticks: Control ticks run.

    """

    metrics: HexapodMetrics
    gait: HexapodWalker
    config: HexapodWalkConfig = field(default_factory=HexapodWalkConfig)
    ticks: int = 0

    def trace(self) -> dict[str, list[float]]:
        """The trace: a dict of equal-length lists sampled at `TRACE_RATE`.

        ``t, x, y, z, roll, pitch, yaw, vx, vy`` (world frame; ``z`` above the terrain, ``yaw``
        unwrapped), ``vx_command``, ``fx`` (virtual force along the heading), ``state`` names,
        plus ``pendulum`` (rad, from the vertical) or ``target_x, target_y``.
        """
        log = self.log
        names = ["x", "y", "z", "roll", "pitch", "yaw", "vx", "vy", "vx_command", "fx"]
        if self.config.pendulum:
            names.append("pendulum")
        if self.config.track:
            names += ["target_x", "target_y"]
        trace = {"t": log.time.tolist(), **{name: log[name].tolist() for name in names}}
        trace["state"] = [log.state_names[i] for i in log.state]
        return trace

    def figures(self) -> WalkFigures:
        """What a sweep tabulates (the distance is the straight line from start to end)."""
        m, x, y = self.metrics, self.log["x"], self.log["y"]
        distance = math.hypot(x[-1] - x[0], y[-1] - y[0]) if len(x) else math.nan
        return WalkFigures(
            bool(m.fell), number(m.fall_time_s), distance, number(m.speed_mps), int(m.steps)
        )

    def to_json(self) -> dict[str, Any]:
        """``fell``, ``realtime_factor``, ``steps``, the summary figures, config and ``trace``."""
        figures = asdict(self.metrics)
        return {
            **figures,
            "ticks": self.ticks,
            "config": asdict(self.config),
            "trace": self.trace(),
        }

    def __repr__(self) -> str:
        return f"HexapodResult({self.metrics.summary()})"


def hexapod_robot(pendulum: bool = False) -> Robot:
    """The hexapod, or its variant with the pendulum on its back (``hexapod_pendulum``).

    Args:
        pendulum: Load ``robots/hexapod/hexapod_pendulum.urdf`` (generated by ``build.py``).

    Returns:
        The [`Robot`][] (free-flyer base).

    """
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
        parameters: Gait constants (default `HexapodParameters` with the config's
            distribution).
        progress: Show a tqdm progress bar.
        on_tick: Called after every physics step (e.g. a viewer's throttled update).
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
    return HexapodResult(log, metrics, gait, simulator, end.wall, config=config, ticks=end.ticks)


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


class HexapodEpisode(Episode):
    """The hexapod's walk under `drive`.

    Every tick the guidance steers the walker and the feet's contact switches are read; the body
    state is recorded at `TRACE_RATE`.
    """

    ignore_unactuated = True

    def __init__(
        self,
        gait: HexapodWalker,
        simulator: Simulator,
        terrain: Terrain,
        recorder: Recorder,
        guidance: Guidance,
    ) -> None:
        super().__init__(gait, simulator, terrain, recorder)
        self.guidance = guidance
        self.record_every = max(1, round(1.0 / (TRACE_RATE * simulator.control_period)))
        self.attitude = (0.0, 0.0, 0.0, 0.0, 0.0)  # yaw, pitch, roll, vx, vy this tick
        self.command = np.zeros(2)
        self.yaw_unwrapped, self.yaw_last = 0.0, 0.0
        self._touching: frozenset[str] | None = None  # the last contact set and its switches
        self._switches: dict[str, bool] = {}

    def sense(self, q: np.ndarray, v: np.ndarray, now: float) -> dict[str, bool]:
        """Steer the walker along the guidance; the feet's contact switches.

        The switches are the same dict while the contacts stay the same (do not modify it).
        """
        self.attitude = yaw, _, _, vx, vy = attitude_and_velocity(q, v)
        state = PlanarState(now, float(q[0]), float(q[1]), yaw, vx, vy)
        self.command, yaw_rate = self.guidance.command(state)
        self.gait.set_command(self.command, yaw_rate)
        touching = self.simulator.touching_frames()  # the same set object for the same contacts
        if touching is not self._touching:
            self._touching = touching
            self._switches = {foot: foot in touching for foot in self.gait.contact_frames}
        return self._switches

    def fallen(self, q: np.ndarray) -> bool:
        """Body low or tilted, something else than a foot down, or the pendulum leaning."""
        _, pitch, roll, _, _ = self.attitude
        gait, parameters = self.gait, self.gait.parameters
        height = float(q[2] - self.terrain.height(q[0]))
        tilt = max(abs(roll), abs(pitch))
        fallen = has_fallen(self.simulator, height, tilt, parameters.height)
        leaning = gait.pendulum is not None and abs(gait.pendulum_angle) > parameters.pendulum_fall
        return fallen or leaning

    def record(
        self, now: float, q: np.ndarray, v: np.ndarray, output: ControlOutput, fallen: bool
    ) -> None:
        """One sample of `CHANNELS`."""
        gait, machine = self.gait, self.gait.machine
        yaw, pitch, roll, vx, vy = self.attitude
        self.yaw_unwrapped += wrap(yaw - self.yaw_last)
        self.yaw_last = yaw
        target = self.guidance.target(now) or (np.nan, np.nan)
        wrench = _body_wrench(output)
        axes = rotation(q)
        c, s = math.cos(yaw), math.sin(yaw)
        self.recorder.append(
            state=machine.index[machine.current.name],
            time=now,
            x=q[0],
            y=q[1],
            z=float(q[2] - self.terrain.height(q[0])),
            roll=roll,
            pitch=pitch,
            yaw=self.yaw_unwrapped,
            vx=vx,
            vy=vy,
            vx_heading=c * vx + s * vy,
            vx_command=float(self.command[0]),
            yaw_rate=float(axes[2] @ (axes @ v[3:6])),
            fx=c * wrench[0] + s * wrench[1],
            pendulum=gait.pendulum_angle if gait.pendulum is not None else np.nan,
            target_x=target[0],
            target_y=target[1],
            fallen=float(fallen),
        )


def _body_wrench(output) -> np.ndarray:
    """The virtual wrench the body's components ask for this tick (world axes)."""
    for name in ("support_a", "support_b", "support_all"):
        if name in output.wrenches:
            return output.wrenches[name]
    return np.zeros(6)


def _with_timing(
    metrics: HexapodMetrics, simulated: float, wall: float, physics: float
) -> HexapodMetrics:
    return replace(
        metrics,
        realtime_factor=simulated / wall if wall > 0 else None,
        physics_realtime_factor=simulated / physics if physics > 0 else None,
    )


def run_registered(
    walk: Walk,
    duration: float,
    speed: float | None = None,
    terrain: str | None = None,
    progress: bool = True,
    on_tick: Callable[[Simulator, HexapodWalker], None] | None = None,
    stop_on_fall: bool = True,
    seed: int | None = None,
    parameters: HexapodParameters | None = None,
    distribution: str | None = None,
    **options: Any,
) -> HexapodResult:
    """The hexapod's walk as a `Walk` runs it.

    ``speed`` defaults to 0.2 m/s with the pendulum or tracking, else 0.4 m/s; ``options`` are
    `HexapodWalkConfig`'s path fields (``direction``, ``yaw_rate``, ``path``,
    ``amplitude``, ``wavelength``, ``pendulum``, ``track``); ``distribution`` overrides
    ``parameters.distribution`` (default: ``"qp"``).

    Raises:
        InvalidInputError: A bad configuration or parameters.

    """
    if speed is None:
        speed = 0.2 if (options.get("pendulum") or options.get("track")) else 0.4
    if parameters is not None and not isinstance(parameters, HexapodParameters):
        raise InvalidInputError(
            f"{walk.name}: parameters must be a HexapodParameters, got {type(parameters).__name__}."
        )
    if distribution is None:
        distribution = "qp" if parameters is None else parameters.distribution
    elif parameters is not None:
        parameters = replace(parameters, distribution=distribution)
    config = HexapodWalkConfig(
        speed=speed,
        terrain=walk.terrain if terrain is None else terrain,
        duration=duration,
        seed=seed,
        distribution=distribution,
        **options,
    )
    return run_hexapod_walk(config, parameters, progress, on_tick, stop_on_fall)


def plot_hexapod_walk(result: HexapodResult, path: str, window: None = None) -> Path:
    """Draw a hexapod walk (`plot_hexapod`)."""
    from ...experiments.plot_panels import save_figure

    return save_figure(draw_hexapod_walk(result), path)


def draw_hexapod_walk(result: HexapodResult) -> Any:
    """The matplotlib figure `plot_hexapod_walk` saves."""
    from .plots import draw_hexapod

    return draw_hexapod(result.log, summary=result.metrics.summary())


def _viewer_robot(pendulum: bool = False, **options: Any) -> Robot:
    return hexapod_robot(pendulum)


def hexapod_speeds(
    pendulum: bool = False, track: bool = False, **options: Any
) -> tuple[float, float]:
    """The supported desired speeds [m/s]: slower with the pendulum or tracking (measured)."""
    return (0.1, 0.4) if (pendulum or track) else (0.1, 1.0)


WALK = Walk(
    name="hexapod-walk",
    robot="hexapod",
    run=run_registered,
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
)
