"""The seeds' walks, closed loop in MuJoCo: turkey walking and blind walking over slopes.

:func:`run_walk` builds the robot, its gait and a :class:`~virtual_actuators.simulation.Simulator`,
then runs the control loop at 1 kHz: read ``q``, ``v`` and the contact switches, let the gait
compute the joint efforts, step the physics. Every tick is recorded (see
:mod:`virtual_actuators.experiments.walk_log` for the channels); the result carries the log and
its metrics (JSON-able), and can be plotted like the seed's Figs. 9 and 15.

The robot is judged fallen when a part other than a foot touches the ground, when the hip drops
below half its nominal height above the terrain, or when the body pitches beyond 0.8 rad.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import time as wallclock
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..exceptions import InvalidInputError, suggestion
from ..experiments.contact_stats import StanceForces
from ..experiments.metrics import WalkMetrics, compute_metrics
from ..experiments.recorder import Recorder
from ..experiments.walk_log import STANDARD_CHANNELS, WalkLog
from ..gaits import FlamingoParameters, FlamingoWalker, Gait, TurkeyParameters, TurkeyWalker
from ..gaits.base import check_distribution
from ..models.loader import load_robot
from ..simulation.simulator import Simulator
from ..simulation.terrain import Terrain
from .progress import Progress

FOOT_WORDS = ("foot", "heel", "toe")
FALL_PITCH = 0.8  # [rad]
STARTUP = 2.0  # [s] metrics ignore the first seconds (start-up)
STANCE_SAMPLING = 4  # stance contact forces are read every this many ticks (250 Hz)


@dataclass(frozen=True)
class WalkSpec:
    """How to run one of the walks.

    Attributes:
        name: Demo name on the command line.
        robot: Robot name for :func:`~virtual_actuators.load_robot`.
        make_gait: Builds the gait from the robot and the desired speed (None: the gait's own).
        terrain: Default terrain (a :meth:`Terrain.parse` spec).
        duration: Default simulated time [s].
        push: Start-up push on the body: force along x [N] for ``push_time`` seconds.
        push_time: [s].
        description: One line for the command-line help.

    """

    name: str
    robot: str
    make_gait: Callable[..., Gait]
    terrain: str
    duration: float
    push: float
    push_time: float
    description: str


def _turkey(robot, speed: float | None, parameters: TurkeyParameters | None = None) -> Gait:
    parameters = _with_speed(parameters or TurkeyParameters(), speed)
    return TurkeyWalker(robot, parameters, initial="double_support")


def _flamingo(robot, speed: float | None, parameters: FlamingoParameters | None = None) -> Gait:
    return FlamingoWalker(robot, _with_speed(parameters or FlamingoParameters(), speed))


def _with_speed(parameters, speed: float | None):
    return parameters if speed is None else dataclasses.replace(parameters, speed=speed)


WALKS: dict[str, WalkSpec] = {
    "turkey-walk": WalkSpec(
        "turkey-walk",
        "spring_turkey",
        _turkey,
        "flat",
        20.0,
        15.0,
        0.2,
        "Spring Turkey walks on level ground (VMC section 5, Table 1)",
    ),
    "flamingo-slopes": WalkSpec(
        "flamingo-slopes",
        "spring_flamingo",
        _flamingo,
        "profile-one",
        40.0,
        10.0,
        0.2,
        "Spring Flamingo walks blind over unknown slopes (VMC section 6)",
    ),
}


@dataclass
class WalkResult:
    """What a walk produced.

    Attributes:
        log: Every control tick.
        metrics: The summary (``metrics.to_dict()`` is the JSON).
        gait: The gait (its state machine history included).
        simulator: The simulator in its final state.
        wall_time: Wall-clock seconds of the loop.

    """

    log: WalkLog
    metrics: WalkMetrics
    gait: Gait
    simulator: Simulator
    wall_time: float
    extra: dict = field(default_factory=dict)

    def __repr__(self) -> str:
        return f"WalkResult({self.metrics.summary()})"


def _spec(name: str) -> WalkSpec:
    if name not in WALKS:
        raise InvalidInputError(f"Unknown walk {name!r}. {suggestion(name, WALKS, 'walks')}")
    return WALKS[name]


def run_walk(
    name: str,
    duration: float | None = None,
    speed: float | None = None,
    terrain: str | Terrain | None = None,
    progress: bool = True,
    on_tick: Callable[[Simulator, Gait], None] | None = None,
    stop_on_fall: bool = True,
    seed: int | None = None,
    parameters: TurkeyParameters | FlamingoParameters | None = None,
    distribution: str | None = None,
) -> WalkResult:
    """Simulate one of the seeds' walks and measure it.

    Args:
        name: ``"turkey-walk"`` or ``"flamingo-slopes"`` (see :data:`WALKS`).
        duration: Simulated time [s] (default: the walk's).
        speed: Desired speed [m/s] (default: the gait's, 0.5 for the turkey, 0.4 for the
            flamingo).
        terrain: A :class:`Terrain` or a spec for :meth:`Terrain.parse`: ``"flat"``, a built-in
            name, or ``"x:z,x:z,..."`` points in metres (default: the walk's).
        progress: Show a tqdm progress bar.
        on_tick: Called after every physics step (e.g. a viewer's throttled update).
        stop_on_fall: End the run at the first fallen tick (plus 0.5 s to see the fall).
        seed: None for the walk's nominal start; an int varies the start-up push (its force
            and duration each scaled by a factor drawn uniformly in [0.7, 1.3]) so that sweeps
            see several starts per setting.
        parameters: The gait's parameters (a :class:`TurkeyParameters` for the turkey, a
            :class:`FlamingoParameters` for the flamingo; default: the gait's); ``speed``
            overrides theirs.
        distribution: ``"partitioned"`` or ``"qp"``: how double support shares the body's
            wrench (overrides ``parameters.distribution``; default: the gait's).

    Returns:
        The :class:`WalkResult`.

    Raises:
        InvalidInputError: Unknown walk, bad duration, speed, terrain, seed, parameters or
            distribution.

    """
    spec = _spec(name)
    duration = spec.duration if duration is None else float(duration)
    if not (math.isfinite(duration) and duration > 0.0):
        raise InvalidInputError(f"duration must be a positive number of seconds, got {duration}.")
    if speed is not None and not (math.isfinite(speed) and 0.0 < speed <= 1.5):
        raise InvalidInputError(f"speed must be in (0, 1.5] m/s, got {speed}.")
    if terrain is None:
        terrain = spec.terrain
    terrain_model = terrain if isinstance(terrain, Terrain) else Terrain.parse(terrain)
    expected = TurkeyParameters if spec.make_gait is _turkey else FlamingoParameters
    if parameters is not None and not isinstance(parameters, expected):
        raise InvalidInputError(
            f"{name}: parameters must be a {expected.__name__}, got {type(parameters).__name__}."
        )
    if distribution is not None:
        check_distribution(distribution)
        parameters = dataclasses.replace(parameters or expected(), distribution=distribution)
    robot = load_robot(spec.robot)
    gait = spec.make_gait(robot, speed, parameters)
    simulator = Simulator(robot, terrain_model)
    q0 = gait.initial_configuration()
    q0[_index(robot, "boom_z")] += float(terrain_model.height(0.0))
    simulator.reset(q0)
    push, push_time = spec.push, spec.push_time  # [N], [s]
    if seed is not None:
        if isinstance(seed, bool) or not isinstance(seed, int | np.integer):
            raise InvalidInputError(f"seed must be an int or None, got {seed!r}.")
        force_scale, time_scale = np.random.default_rng(int(seed)).uniform(0.7, 1.3, size=2)
        push, push_time = push * float(force_scale), push_time * float(time_scale)
    simulator.push(np.array([push, 0.0, 0.0]), frame="body", duration=push_time)

    machine = gait.machine
    recorder = Recorder(
        STANDARD_CHANNELS,
        state_names=machine.names,
        capacity=int(duration * 1000) + 16,
        metadata={
            "robot": robot.name,
            "walk": name,
            "terrain": terrain if isinstance(terrain, str) else repr(terrain),
            "terrain_points": terrain_points(terrain_model, duration),
            "speed_setpoint_mps": float(gait.bunny.speed),
            "nominal_height_m": float(gait.nominal_height()),
            "step_states": list(gait.step_states),
            "double_support_states": ["double_support"],
        },
    )
    x_index, z_index = _index(robot, "boom_x"), _index(robot, "boom_z")
    pitch_index = _index(robot, "boom_pitch")
    v_x = robot.model.joints[robot.model.getJointId("boom_x")].idx_v
    contact_frames = gait.contact_frames
    nominal = gait.nominal_height()  # [m]
    stance = StanceForces(simulator, terrain_model)
    bar = Progress(duration) if progress else None
    fall_time = None
    gait.controller.warm_up(simulator.q)  # kernels loaded before the clock starts
    start = wallclock.perf_counter()
    ticks_per_update = 100
    tick = 0
    append_row, state_index, bunny, granny = (
        recorder.append_row,
        machine.index,
        gait.bunny,
        gait.granny,
    )
    height_at = terrain_model.height
    has_slope = hasattr(gait, "slope")
    nan = math.nan
    data = simulator.data  # MuJoCo's state: its time read directly (a tick's cost)
    while data.time < duration - 1e-9:
        q, v = simulator.q, simulator.v
        now = data.time
        contacts = simulator.contact_switches(contact_frames)
        output = gait.compute(q, v, now, contacts)
        simulator.step(output.tau)
        tick += 1
        if fall_time is None and tick % STANCE_SAMPLING == 0:
            stance.sample(gait.support_contacts())
        x, z_world, pitch = q.item(x_index), q.item(z_index), q.item(pitch_index)
        ground = float(height_at(x))
        fallen = fall_time is not None or has_fallen(simulator, z_world - ground, pitch, nominal)
        if fallen and fall_time is None:
            fall_time = now
        wrench = _body_wrench(output)
        double = "double" in output.active
        set_height, set_pitch = granny.setpoint.tolist()  # [m], [rad]
        append_row(  # one value per STANDARD_CHANNELS entry, in its order
            (
                now,
                x,
                z_world - ground,
                z_world,
                pitch,
                v.item(v_x),
                bunny.position_at(now) if double else nan,
                set_height - ground,
                set_pitch,
                bunny.speed if double else nan,
                wrench[0],
                wrench[1],
                wrench[2],
                gait.slope if has_slope else nan,
                float(fallen),
            ),
            state_index[machine.current.name],
        )
        if on_tick is not None:
            on_tick(simulator, gait)
        if bar is not None and tick % ticks_per_update == 0:
            bar.set(simulator.time)
        if stop_on_fall and fall_time is not None and now > fall_time + 0.5:
            break
    wall = wallclock.perf_counter() - start
    if bar is not None:
        bar.close(simulator.time)
    recorder.metadata["wall_time_s"] = wall
    log = recorder.to_log()
    metrics = compute_metrics(log, startup_s=STARTUP, wall_time_s=wall)
    normal_min, ratio_max = stance.figures()
    metrics = dataclasses.replace(
        metrics, stance_normal_min_n=normal_min, stance_friction_ratio_max=ratio_max
    )
    return WalkResult(log, metrics, gait, simulator, wall)


def terrain_points(terrain: Terrain, duration: float) -> np.ndarray:
    """Terrain vertices for plots: at least two, covering the walk's likely reach."""
    points = np.asarray(terrain.points, dtype=float)
    reach = max(1.5 * duration, float(points[-1, 0]) + 1.0)  # [m], 1.5 m/s at most
    start = min(-1.0, float(points[0, 0]) - 1.0)
    return np.vstack(
        ([start, float(terrain.height(start))], points, [reach, float(terrain.height(reach))])
    )


def _index(robot, joint: str) -> int:
    model = robot.model
    return model.joints[model.getJointId(joint)].idx_q


def _body_wrench(output) -> np.ndarray:
    """The virtual wrench (x, z, ry) the components ask of the body this tick."""
    for name in ("double", "left_stance", "right_stance"):
        if name in output.wrenches:
            return output.wrenches[name]
    return np.zeros(3)


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
