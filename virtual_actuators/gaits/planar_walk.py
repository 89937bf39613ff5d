"""The planar bipeds' walk in MuJoCo: turkey walking and blind walking over slopes (two walks)."""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np

from ..control.controller import ControlOutput
from ..exceptions import InvalidInputError
from ..experiments.metrics import compute_metrics
from ..experiments.recorder import Recorder
from ..experiments.walk_log import STANDARD_CHANNELS
from ..models.loader import load_robot
from ..simulation.simulator import Simulator
from ..simulation.terrain import Terrain
from .base import Gait, Walk, WalkRequest, check_distribution, check_speed_bound
from .flamingo import FlamingoParameters, FlamingoWalker
from .runner import Episode, WalkResult, has_fallen, terrain_points
from .turkey import TurkeyParameters, TurkeyWalker
from .walk_loop import drive

STARTUP = 2.0  # [s] metrics ignore the first seconds (start-up)
RECORD_EVERY = 4  # the log's rows: every this many ticks (250 Hz; the efforts: every tick)
#: The attachments whose components move the body, in the order the wrench is read from.
BODY_ATTACHMENTS = ("double", "left_stance", "right_stance")


def run_planar_walk(request: WalkRequest) -> WalkResult:
    """Simulate a planar biped's walk and measure it (a `Walk`'s ``run``).

    ``speed`` defaults to ``parameters.speed``, else `Walk.default_speed`; ``seed`` scales the
    start-up push's force and duration by factors drawn in [0.7, 1.3].

    Raises:
        InvalidInputError: Bad speed, terrain, seed or distribution.
    """
    walk, speed, parameters = request.walk, request.speed, request.parameters
    duration, terrain, seed = request.duration, request.terrain, request.seed
    if speed is not None:
        check_speed_bound(speed, zero=False)
    if speed is None and parameters is None:
        speed = walk.default_speed()
    parameters = parameters or walk.parameters()
    if request.distribution is not None:
        check_distribution(request.distribution)
        parameters = dataclasses.replace(parameters, distribution=request.distribution)
    if speed is not None:
        parameters = dataclasses.replace(parameters, speed=speed)
    terrain_model = terrain if isinstance(terrain, Terrain) else Terrain.parse(terrain)
    robot = load_robot(walk.robot)
    gait = walk.gait(robot, parameters, initial="double_support")
    simulator = Simulator(robot, terrain_model)
    q0 = gait.initial_configuration()
    q0[_index(robot, "boom_z")] += float(terrain_model.height(0.0))
    simulator.reset(q0)
    push, push_time = walk.push, walk.push_time  # [N], [s], varied by a seed
    if seed is not None:
        if isinstance(seed, bool) or not isinstance(seed, int | np.integer):
            raise InvalidInputError(f"seed must be an int or None, got {seed!r}.")
        force_scale, time_scale = np.random.default_rng(int(seed)).uniform(0.7, 1.3, size=2)
        push, push_time = push * float(force_scale), push_time * float(time_scale)
    simulator.push(np.array([push, 0.0, 0.0]), frame="body", duration=push_time)
    recorder = Recorder(
        STANDARD_CHANNELS,
        state_names=gait.machine.names,
        capacity=int(duration * 1000) // RECORD_EVERY + 16,
        metadata={
            "robot": robot.name,
            "walk": walk.name,
            "terrain": terrain if isinstance(terrain, str) else repr(terrain),
            "terrain_points": terrain_points(terrain_model, duration),
            "speed_setpoint_mps": float(gait.bunny.speed),
            "nominal_height_m": float(gait.nominal_height()),
            "step_states": list(gait.step_states),
            "double_support_states": ["double_support"],
        },
    )
    episode = PlanarEpisode(gait, simulator, terrain_model, recorder)
    end = drive(episode, duration, *request.loop)
    log = recorder.to_log()
    metrics = compute_metrics(log, startup_s=STARTUP, wall_time_s=end.wall)
    normal_min, ratio_max = episode.stance.figures()
    metrics = dataclasses.replace(
        metrics, stance_normal_min_n=normal_min, stance_friction_ratio_max=ratio_max
    )
    return episode.finish(end, log, metrics)


class PlanarEpisode(Episode):
    """A planar biped's walk under `drive`: `STANDARD_CHANNELS` every `RECORD_EVERY` ticks."""

    stance_every = 10  # the stance contact forces at 100 Hz
    record_every = RECORD_EVERY

    def __init__(
        self, gait: Gait, simulator: Simulator, terrain: Terrain, recorder: Recorder
    ) -> None:
        super().__init__(gait, simulator, terrain, recorder)
        robot = gait.robot
        self.x_index, self.z_index = _index(robot, "boom_x"), _index(robot, "boom_z")
        self.pitch_index = _index(robot, "boom_pitch")
        self.v_x = robot.model.joints[robot.model.getJointId("boom_x")].idx_v
        pitch_v = robot.model.joints[robot.model.getJointId("boom_pitch")].idx_v
        self.base_rate = slice(pitch_v, pitch_v + 1)  # the body's pitch rate, recorded per tick
        self.nominal = gait.nominal_height()  # [m]
        self.has_slope = hasattr(gait, "slope")
        self.ground = 0.0  # [m], the terrain's height under the hip at this tick

    def sense(self, q: np.ndarray, v: np.ndarray, now: float) -> dict[str, bool]:
        """The feet's contact switches (and the tick's `ground`)."""
        level = self.level
        self.ground = float(self.terrain.height(q.item(self.x_index))) if level is None else level
        return self.simulator.contact_switches(self.gait.contact_frames)

    def fallen(self, q: np.ndarray) -> bool:
        """Hip low, body tilted or something else than a foot down."""
        height = q.item(self.z_index) - self.ground
        pitch = q.item(self.pitch_index)
        return has_fallen(self.simulator, height, pitch, self.nominal, self.feet)

    def record(
        self, now: float, q: np.ndarray, v: np.ndarray, output: ControlOutput, fallen: bool
    ) -> None:
        """One row of `STANDARD_CHANNELS`."""
        gait, nan, ground = self.gait, math.nan, self.ground
        z_world = q.item(self.z_index)
        body = _body_attachment(output.active)
        wrench = output.wrench_of(body) if body else None
        wrench_x, wrench_z, wrench_ry = (0.0, 0.0, 0.0) if wrench is None else wrench.tolist()
        double = body == "double"
        set_height, set_pitch = gait.granny.setpoint.tolist()  # [m], [rad]
        bunny = gait.bunny
        self.recorder.append_row(  # one value per STANDARD_CHANNELS entry, in its order
            (
                now,
                q.item(self.x_index),
                z_world - ground,
                z_world,
                q.item(self.pitch_index),
                v.item(self.v_x),
                bunny.position_at(now) if double else nan,
                set_height - ground,
                set_pitch,
                bunny.speed if double else nan,
                wrench_x,
                wrench_z,
                wrench_ry,
                gait.slope if self.has_slope else nan,
                float(fallen),
            ),
            gait.machine.current_index,
        )


def draw_planar_walk(result: WalkResult, window=None):
    """A planar walk like the seed's Fig. 9 (level ground) or Fig. 15 (slopes), a figure.

    Args:
        result: The walk.
        window: ``(t0, t1)`` simulated seconds to draw (either may be None), or None for all.
    """
    from ..experiments.plots import draw_walk

    log = result.log
    title = f"{log.metadata['walk']}: {log.metadata['robot']} on {log.metadata['terrain']}"
    heights = log.terrain_points[:, 1]
    layout = "time" if np.ptp(heights) == 0.0 else "terrain"  # Fig. 9 vs Fig. 15
    return draw_walk(log, title=title, metrics=result.metrics, layout=layout, window=window)


def _index(robot, joint: str) -> int:
    model = robot.model
    return model.joints[model.getJointId(joint)].idx_q


@functools.cache
def _body_attachment(active: tuple[str, ...]) -> str:
    """The active attachment the body's wrench is read from ("" when none is)."""
    return next((name for name in BODY_ATTACHMENTS if name in active), "")


#: What both planar walks share: this module runs and draws them, a 0.2 s push starts them.
_PLANAR = {"run": run_planar_walk, "draw": draw_planar_walk, "push_time": 0.2, "plot_window": True}

TURKEY = Walk(
    name="turkey-walk",
    robot="spring_turkey",
    parameters=TurkeyParameters,
    duration=20.0,
    description="Spring Turkey walks on level ground (VMC section 5, Table 1)",
    gait=TurkeyWalker,
    push=15.0,
    nominal_speed=TurkeyParameters.speed,
    speeds=(0.3, 0.6),
    **_PLANAR,
)

FLAMINGO = Walk(
    name="flamingo-slopes",
    robot="spring_flamingo",
    parameters=FlamingoParameters,
    terrain="profile-one",
    duration=40.0,
    description="Spring Flamingo walks blind over unknown slopes (VMC section 6)",
    gait=FlamingoWalker,
    push=10.0,
    nominal_speed=FlamingoParameters.speed,
    speeds=(0.3, 0.5),
    **_PLANAR,
)
