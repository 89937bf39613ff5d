"""The 1996 hexapod walking in MuJoCo: lines, circles, sine waves, a pendulum, tracking.

:func:`run_hexapod_walk` builds the hexapod (with the pendulum on its back for
``pendulum=True``), its :class:`~virtual_actuators.gaits.HexapodWalker`, a guidance that turns the
requested path into the seed's three inputs (:mod:`~virtual_actuators.gaits.hexapod.guidance`) and
a :class:`~virtual_actuators.simulation.Simulator`, then runs the control loop at 1 kHz. The body
state is sampled at :data:`TRACE_RATE` into a :class:`~virtual_actuators.experiments.WalkLog`;
:class:`~virtual_actuators.gaits.hexapod.metrics.HexapodMetrics` summarises it (the
issue's targets are checked on these figures) and
:meth:`HexapodResult.to_json` is what ``--json`` writes. Every tick the feet's contact switches
(MuJoCo's contacts) go to the walker, whose stance ends when its swing tripod is down, and
:class:`~virtual_actuators.experiments.contact_stats.StanceForces` reads MuJoCo's contact forces
on the feet the current state has in support (``stance_normal_min_n``,
``stance_friction_ratio_max`` in the JSON).

The robot is judged fallen when a part other than a foot touches the ground, when the body drops
below half its nominal height above the terrain, when it rolls or pitches beyond 0.8 rad, or when
the pendulum leans beyond ``HexapodParameters.pendulum_fall``.
"""

from __future__ import annotations

import math
import time as wallclock
from collections.abc import Callable
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from ...exceptions import InvalidInputError
from ...experiments.contact_stats import StanceForces
from ...experiments.progress import Progress
from ...experiments.recorder import Recorder
from ...experiments.walk_log import WalkLog
from ...models.catalog import robots_dir
from ...models.loader import load_robot
from ...models.robot import Robot
from ...simulation.simulator import Simulator
from ...simulation.terrain import Terrain
from ..base import Walk, check_distribution
from ..runner import WalkFigures, has_fallen, number, terrain_points
from .body import attitude_and_velocity, rotation
from .guidance import (
    Guidance,
    PlanarState,
    SinePath,
    TrackObject,
    VelocityCommand,
    wrap,
)
from .metrics import HexapodMetrics, compute_hexapod_metrics
from .parameters import HexapodParameters
from .walker import HexapodWalker

TRACE_RATE = 100.0  # [Hz] samples of the trace and the log
PATHS = ("line", "sine")
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
        terrain: A :meth:`Terrain.parse` spec (profiles run along the world x axis).
        duration: Simulated time [s].
        seed: Random initial disturbance (body velocity, pendulum angle); None for none.
        distribution: ``"qp"`` or ``"partitioned"``.

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

    def __post_init__(self) -> None:
        numbers = {k: getattr(self, k) for k in ("speed", "direction", "yaw_rate", "duration")}
        numbers.update(amplitude=self.amplitude, wavelength=self.wavelength)
        for name, value in numbers.items():
            if not (isinstance(value, (int, float)) and math.isfinite(value)):
                raise InvalidInputError(f"{name} must be a finite number, got {value!r}.")
        if not 0.0 <= self.speed <= 1.5:
            raise InvalidInputError(f"speed must be in [0, 1.5] m/s, got {self.speed}.")
        if self.duration <= 0.0:
            raise InvalidInputError(f"duration must be > 0 s, got {self.duration}.")
        if self.path not in PATHS:
            raise InvalidInputError(f"path must be one of {PATHS}, got {self.path!r}.")
        if self.path == "sine" and (self.speed <= 0.0 or self.wavelength <= 0.0):
            raise InvalidInputError("path 'sine' needs a speed > 0 and a wavelength > 0.")
        check_distribution(self.distribution)
        if self.path == "sine" and (self.track or self.yaw_rate != 0.0):
            raise InvalidInputError("path 'sine' holds the heading: no yaw rate and no tracking.")
        if self.track and self.yaw_rate != 0.0:
            raise InvalidInputError("tracking sets the yaw rate itself: leave yaw_rate at 0.")

    def guidance(self) -> Guidance:
        """The guidance for this configuration."""
        if self.path == "sine":
            return SinePath(self.speed, self.amplitude, self.wavelength)
        if self.track:
            return TrackObject(self.speed, self.direction)
        return VelocityCommand(self.speed, self.direction, self.yaw_rate)


@dataclass
class HexapodResult:
    """What a hexapod walk produced.

    Attributes:
        config: The configuration.
        log: The body state at :data:`TRACE_RATE` (channels :data:`CHANNELS`).
        metrics: The summary figures.
        gait: The walker (its state machine history included).
        simulator: The simulator in its final state.
        wall_time: Wall-clock seconds of the loop.
        ticks: Control ticks run.

    """

    config: HexapodWalkConfig
    log: WalkLog
    metrics: HexapodMetrics
    gait: HexapodWalker
    simulator: Simulator
    wall_time: float
    ticks: int
    extra: dict[str, Any] = field(default_factory=dict)

    def trace(self) -> dict[str, list[float]]:
        """The trace: a dict of equal-length lists sampled at :data:`TRACE_RATE`.

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
        The :class:`~virtual_actuators.Robot` (free-flyer base).

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
        parameters: Gait constants (default :class:`HexapodParameters` with the config's
            distribution).
        progress: Show a tqdm progress bar.
        on_tick: Called after every physics step (e.g. a viewer's throttled update).
        stop_on_fall: End the run 0.5 s after the first fallen tick.

    Returns:
        The :class:`HexapodResult`.

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
    guidance = config.guidance()
    guidance.begin(PlanarState(0.0, float(q0[0]), float(q0[1]), 0.0, 0.0, 0.0))
    machine = gait.machine
    recorder = Recorder(
        CHANNELS,
        state_names=machine.names,
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
    stance = StanceForces(simulator, terrain)
    feet = gait.contact_frames
    supports = {state.name: [(foot,) for foot in state.support] for state in machine.states}
    every = max(1, round(1.0 / (TRACE_RATE * simulator.control_period)))
    bar = Progress(config.duration) if progress else None
    fall_time = None
    physics = 0.0
    yaw_unwrapped, yaw_last = 0.0, 0.0
    tick = 0
    gait.controller.warm_up(simulator.q)  # kernels loaded before the clock starts
    start = wallclock.perf_counter()
    while simulator.time < config.duration - 1e-9:
        q, v = simulator.q, simulator.v
        now = simulator.time
        yaw, pitch, roll, vx, vy = attitude_and_velocity(q, v)
        state = PlanarState(now, float(q[0]), float(q[1]), yaw, vx, vy)
        command, yaw_rate = guidance.command(state)
        gait.set_command(command, yaw_rate)
        touching = simulator.touching_terrain()
        contacts = {foot: foot in touching for foot in feet}
        output = gait.compute(q, v, now, contacts)
        mark = wallclock.perf_counter()
        simulator.step(output.tau, ignore_unactuated=True)
        physics += wallclock.perf_counter() - mark
        tick += 1
        if fall_time is None:
            stance.sample(supports[machine.current.name])
        height = float(q[2] - terrain.height(q[0]))
        tilt = max(abs(roll), abs(pitch))
        fallen = fall_time is not None or has_fallen(simulator, height, tilt, parameters.height)
        if gait.pendulum is not None and abs(gait.pendulum_angle) > parameters.pendulum_fall:
            fallen = True
        if fallen and fall_time is None:
            fall_time = now
        if tick % every == 1 or every == 1:
            yaw_unwrapped += wrap(yaw - yaw_last)
            yaw_last = yaw
            target = guidance.target(now) or (np.nan, np.nan)
            wrench = _body_wrench(output)
            axes = rotation(q)
            c, s = math.cos(yaw), math.sin(yaw)
            recorder.append(
                state=machine.index[machine.current.name],
                time=now,
                x=q[0],
                y=q[1],
                z=height,
                roll=roll,
                pitch=pitch,
                yaw=yaw_unwrapped,
                vx=vx,
                vy=vy,
                vx_heading=c * vx + s * vy,
                vx_command=float(command[0]),
                yaw_rate=float(axes[2] @ (axes @ v[3:6])),
                fx=c * wrench[0] + s * wrench[1],
                pendulum=gait.pendulum_angle if gait.pendulum is not None else np.nan,
                target_x=target[0],
                target_y=target[1],
                fallen=float(fallen),
            )
        if on_tick is not None:
            on_tick(simulator, gait)
        if bar is not None and tick % 100 == 0:
            bar.set(simulator.time)
        if stop_on_fall and fall_time is not None and now > fall_time + 0.5:
            break
    wall = wallclock.perf_counter() - start
    if bar is not None:
        bar.close(simulator.time)
    recorder.metadata["wall_time_s"] = wall
    recorder.metadata["command_path"] = _command_path(config, guidance)
    log = recorder.to_log()
    steps = machine.steps_into(gait.step_states)
    metrics = compute_hexapod_metrics(log, guidance, steps, fall_time, *stance.figures())
    metrics = _with_timing(metrics, simulator.time, wall, physics)
    return HexapodResult(config, log, metrics, gait, simulator, wall, tick)


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


def _command_path(config: HexapodWalkConfig, guidance: Guidance) -> np.ndarray:
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
        local = np.c_[
            radius * np.sin(np.abs(angles)),
            np.sign(config.yaw_rate) * radius * (1 - np.cos(angles)),
        ]
        c, s = math.cos(config.direction), math.sin(config.direction)
        along, across = c * local[:, 0] - s * local[:, 1], s * local[:, 0] + c * local[:, 1]
    else:
        distances = np.linspace(0.0, reach, 2)
        along = distances * math.cos(config.direction)
        across = distances * math.sin(config.direction)
    c, s = math.cos(yaw0), math.sin(yaw0)
    return np.c_[x0 + c * along - s * across, y0 + s * along + c * across]


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
    """The hexapod's walk as a :class:`~virtual_actuators.gaits.base.Walk` runs it.

    ``speed`` defaults to 0.2 m/s with the pendulum or tracking, else 0.4 m/s; ``options`` are
    :class:`HexapodWalkConfig`'s path fields (``direction``, ``yaw_rate``, ``path``,
    ``amplitude``, ``wavelength``, ``pendulum``, ``track``); ``distribution`` overrides
    ``parameters.distribution`` (default: ``"qp"``).

    Raises:
        InvalidInputError: A bad configuration or parameters.

    """
    if speed is None:
        speed = 0.2 if (options.get("pendulum") or options.get("track")) else 0.4
    if parameters is not None and not isinstance(parameters, HexapodParameters):
        raise InvalidInputError(
            f"{walk.name}: parameters must be a HexapodParameters, got "
            f"{type(parameters).__name__}."
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
    """Draw a hexapod walk (:func:`~virtual_actuators.gaits.hexapod.plots.plot_hexapod`)."""
    from .plots import plot_hexapod

    return plot_hexapod(result.log, path, summary=result.metrics.summary())


def _viewer_robot(pendulum: bool = False, **options: Any) -> Robot:
    return hexapod_robot(pendulum)


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
)
