"""``demo balance``: any legged robot standing in MuJoCo, pushed (`Push`), without stepping."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ...control.controller import ControlOutput
from ...exceptions import InvalidInputError
from ...experiments.plot_panels import FORCE_STYLE, new_figure, set_heading
from ...experiments.recorder import Recorder
from ...experiments.smoothness import SmoothnessFigures
from ...experiments.walk_log import WalkLog
from ...models.efforts import implausible_effort_limits
from ...models.loader import load_robot
from ...models.robot import Robot
from ...simulation.simulator import Simulator
from ...simulation.terrain import Terrain
from ..attitude import attitude_and_velocity
from ..base import Walk, WalkRequest
from ..push import Push
from ..runner import (
    TRACE_RATE,
    Episode,
    WalkFigures,
    WalkResult,
    allowed_geoms,
    has_fallen,
    number,
    trace_of,
)  # fmt: skip
from ..walk_loop import drive
from .balancer import BalanceParameters, Balancer

if TYPE_CHECKING:
    from matplotlib.figure import Figure

CHANNELS = ("time", "x", "y", "z", "roll", "pitch", "yaw", "vx", "vy", "normal_min", "fallen")
#: The first seconds, while the robot settles on the ground, are left out of the contact figures.
SETTLE_TIME = 0.1


@dataclass(frozen=True)
class BalanceMetrics(SmoothnessFigures):
    """The summary figures of a balance run (NaN: not measured), with `SmoothnessFigures`.

    Attributes:
        robot: The robot's name.
        feet: Its foot frames.
        fell: Whether it fell.
        fall_time_s: When it first fell [s].
        duration_s: Simulated time [s].
        realtime_factor: Simulated time over wall time.
        push: ``"N@T:DEG"`` or None.
        max_tilt_rad: Largest body tilt (roll and pitch combined) [rad].
        max_drift_m: Largest horizontal distance of the body from its start [m].
        final_drift_m: That distance at the end [m].
        height_error_m: Mean body height over the last second minus the standing pose's [m].
        stance_normal_min_n: Least normal force on a foot after `SETTLE_TIME` [N].
        implausible_limits: Joints whose URDF effort limit no motor could have
            ([`implausible_effort_limits`][]).
    """

    robot: str
    feet: tuple[str, ...]
    fell: bool
    fall_time_s: float | None
    duration_s: float
    realtime_factor: float | None
    push: str | None
    max_tilt_rad: float
    max_drift_m: float
    final_drift_m: float
    height_error_m: float
    stance_normal_min_n: float
    implausible_limits: tuple[str, ...] = ()

    def summary(self) -> str:
        """One line for the terminal."""
        state = f"FELL at {self.fall_time_s:.2f} s" if self.fell else "stood"
        push = f", push {self.push}" if self.push else ""
        rate = f", {self.realtime_factor:.2f}x real time" if self.realtime_factor else ""
        limits = self.implausible_limits
        note = f" (implausible URDF effort limits on {len(limits)} joints)" if limits else ""
        smoothness = self.smoothness_summary()
        height = round(self.height_error_m * 1000, 1) + 0.0  # [mm], never -0.0
        return (
            f"{self.robot} {state} for {self.duration_s:.2f} s{push}: tilt <= "
            f"{self.max_tilt_rad:.3f} rad, drift <= {self.max_drift_m:.3f} m, height error "
            f"{height:+.1f} mm{rate}{note}"
            f"{', ' if smoothness else ''}{smoothness}"
        )

    def to_dict(self) -> dict[str, Any]:
        """The figures as a JSON-able dict."""
        return {k: list(v) if isinstance(v, tuple) else v for k, v in asdict(self).items()}


@dataclass
class BalanceResult(WalkResult):
    """A balance run: the log at `TRACE_RATE`, the metrics, the balancer, the simulator."""

    metrics: BalanceMetrics
    gait: Balancer

    def trace(self) -> dict[str, list]:
        """The body's ``t, x, y, z, roll, pitch, yaw, vx, vy``, ``normal_min`` [N], ``state``."""
        return trace_of(self.log, ("normal_min",))

    def figures(self) -> WalkFigures:
        """What a sweep tabulates (the distance is the final drift)."""
        m = self.metrics
        return WalkFigures(bool(m.fell), number(m.fall_time_s), m.final_drift_m, 0.0, 0)

    def to_json(self) -> dict[str, Any]:
        """The figures and ``trace``."""
        return {**self.metrics.to_dict(), "trace": self.trace(), **self.estimation_json()}


class BalanceEpisode(Episode):
    """A balance run under `drive`: push, judge, record `CHANNELS` at `TRACE_RATE`.

    Attributes:
        start: The configuration at the start.
        stand_height: The base's height above the terrain at the start [m].
    """

    def __init__(
        self, gait: Balancer, simulator: Simulator, terrain: Terrain, recorder: Recorder,
        push: Push | None,
    ) -> None:  # fmt: skip
        super().__init__(gait, simulator, terrain, recorder)
        self.push, self.pushed = push, push is None
        self.record_every = max(1, round(1.0 / (TRACE_RATE * simulator.control_period)))
        self.start = simulator.q.copy()
        self.stand_height = self.height(self.start)
        model = gait.robot.model
        joints = {model.frames[model.getFrameId(f)].parentJoint for f in gait.contacts}
        feet = frozenset(f.name for f in model.frames if f.parentJoint in joints)
        self.feet = allowed_geoms(simulator, feet.__contains__)
        self.attitude = (0.0, 0.0, 0.0, 0.0, 0.0)

    def sense(self, q: np.ndarray, v: np.ndarray, now: float) -> None:
        """Start the push when its time comes; read the body's attitude."""
        if not self.pushed and now >= self.push.time - 1e-9:
            self.push.apply(self.simulator, self.gait.body, self.gait.parameters.push_duration)
            self.pushed = True
        self.attitude = attitude_and_velocity(q, v)

    def fallen(self, q: np.ndarray) -> bool:
        """Tilted, low, or touching the ground with something else than a foot (`has_fallen`)."""
        _, pitch, roll, _, _ = self.attitude
        tilt = math.hypot(roll, pitch)
        return has_fallen(self.simulator, self.height(q), tilt, self.stand_height, self.feet)

    def record(
        self, now: float, q: np.ndarray, v: np.ndarray, output: ControlOutput, fallen: bool
    ) -> None:
        """One sample of `CHANNELS`."""
        yaw, pitch, roll, vx, vy = self.attitude
        normal = float(self.simulator.contact_forces(self.gait.contacts)[:, 2].min())
        row = (now, q.item(0), q.item(1), self.height(q), roll, pitch, yaw, vx, vy, normal)
        self.recorder.append_row((*row, float(fallen)), 0)


def run_balance(
    robot: str | Robot = "talos",
    duration: float = 5.0,
    push: str | Push | None = None,
    terrain: str | Terrain = "flat",
    parameters: BalanceParameters | None = None,
    progress: bool = True,
    on_tick: Callable[[Simulator, Balancer], None] | None = None,
    stop_on_fall: bool = True,
    seed: int | None = None,
    estimator: bool = False,
) -> BalanceResult:
    """Simulate a legged robot standing (and pushed) and measure it.

    Args:
        robot: A name or URDF path for [`load_robot`][], or a robot.
        duration: Simulated time [s].
        push: ``"N@T[:DEG]"``, a `Push` or ``(N, T, DEG)``, or None.
        terrain: A [`Terrain`][] or its spec.
        parameters: The balancer's constants.
        progress: Show a progress bar.
        on_tick: Called after every physics step (a viewer).
        stop_on_fall: End the run 0.5 s after a fall.
        seed: Without ``push``, draws one of a tenth of the weight, at 0.5 to 1 s, any direction.
        estimator: Stand on a `LeggedEstimator` fed by the simulated sensors.

    Returns:
        The `BalanceResult`.

    Raises:
        RobotNotFoundError: No such robot.
        FrameNotFoundError: A robot without feet.
        InvalidInputError: A bad push, terrain or duration.
    """
    push = None if push is None else Push.of(push)
    robot = load_robot(robot) if not isinstance(robot, Robot) else robot
    terrain = terrain if isinstance(terrain, Terrain) else Terrain.parse(terrain)
    if push is None and seed is not None:
        rng = np.random.default_rng(seed)
        weight = robot.mass * 9.81
        push = Push(0.1 * weight, float(rng.uniform(0.5, 1.0)), float(rng.uniform(0.0, 360.0)))
    gait = Balancer(robot, parameters)
    simulator = Simulator(robot, terrain)
    q0 = gait.initial_configuration()
    q0[:2] = 0.0
    q0 = simulator.on_ground(q0)
    simulator.reset(q0)
    gait.start(q0)
    recorder = Recorder(
        CHANNELS, state_names=("stand",), capacity=int(duration * TRACE_RATE) + 16,
        metadata={"robot": robot.name, "walk": "balance", "push": push and list(push)},
    )
    episode = BalanceEpisode(gait, simulator, terrain, recorder, push)
    if estimator:
        episode.use_estimator(tuple(gait.feet))
    end = drive(episode, duration, progress, on_tick, stop_on_fall)
    log = recorder.to_log()
    realtime = end.realtime_factors(simulator.time)["realtime_factor"]
    return episode.finish(end, log, _metrics(episode, log, end.fall_time, realtime), BalanceResult)


def _metrics(episode: BalanceEpisode, log, fall_time, realtime) -> BalanceMetrics:
    """The summary figures of a finished run."""
    gait, push = episode.gait, episode.push
    drift = np.hypot(log["x"] - episode.start[0], log["y"] - episode.start[1])
    tilt = np.hypot(log["roll"], log["pitch"])
    last = log.time >= log.time[-1] - 1.0
    settled = log["normal_min"][log.time >= SETTLE_TIME]
    return BalanceMetrics(
        robot=gait.robot.name,
        feet=tuple(gait.feet),
        fell=fall_time is not None,
        fall_time_s=fall_time,
        duration_s=float(log.time[-1]) if len(log) else 0.0,
        realtime_factor=realtime,
        push=str(push) if push else None,
        max_tilt_rad=float(tilt.max()),
        max_drift_m=float(drift.max()),
        final_drift_m=float(drift[-1]),
        height_error_m=float(log["z"][last].mean() - episode.stand_height),
        stance_normal_min_n=float(settled.min()) if len(settled) else math.nan,
        implausible_limits=tuple(implausible_effort_limits(gait.robot)),
    )


def run_request(request: WalkRequest) -> BalanceResult:
    """``balance`` as `run_walk` starts it (``speed`` is not used).

    Raises:
        InvalidInputError: A distribution other than ``"qp"``; a bad push, terrain or duration.
        RobotNotFoundError: No such robot.
    """
    if request.distribution not in (None, "qp"):
        raise InvalidInputError("balance stands on the contact QP: --distribution qp only.")
    options = request.options
    return run_balance(
        options.get("robot", request.walk.robot), request.duration, options.get("push"),
        request.terrain, request.parameters, *request.loop, request.seed,
        options.get("estimator", False),
    )  # fmt: skip


PANELS = (
    (("x", "y"), "drift [m]", True),
    (("z",), "height [m]", False),
    (("roll", "pitch"), "tilt [rad]", False),
    (("vx", "vy"), "velocity [m/s]", False),
)


def draw_balance_log(log: WalkLog, summary: str = "") -> Figure:
    """The body's drift, height, roll and pitch, and horizontal velocity, ``summary`` its title."""
    figure = new_figure(8.0, 8.0, dpi=110)
    axes = figure.subplots(len(PANELS), 1, sharex=True)
    t = log.time
    for ax, (names, label, relative) in zip(axes, PANELS, strict=True):
        for k, name in enumerate(names):
            values = log[name] - log[name][0] if relative else log[name]
            style = FORCE_STYLE if k else {"color": "C0", "lw": 1.2}
            ax.plot(t, values, label=name, **style)
        ax.set_ylabel(label)
        ax.grid(True, lw=0.4, alpha=0.5)
        ax.legend(loc="upper right", fontsize=7)
    axes[-1].set_xlabel("time [s]")
    if summary:
        set_heading(figure, summary, fontsize=9)
    return figure


def draw_balance(result: BalanceResult, window: None = None) -> Figure:
    """A balance run's figure (`draw_balance_log`, titled by its summary)."""
    return draw_balance_log(result.log, summary=result.metrics.summary())


WALK = Walk(
    name="balance",
    robot="talos",
    run=run_request,
    parameters=BalanceParameters,
    duration=5.0,
    draw=draw_balance,
    description="Any legged robot standing on the contact QP, pushed, without stepping",
    options=("robot", "push", "estimator"),
    force_scale=1 / 400,
    # the robot with the sole-centre frames the balancer adds (its contacts), as the run has it
    viewer_robot=lambda robot="talos", **_: Balancer(load_robot(robot)).robot,
)
