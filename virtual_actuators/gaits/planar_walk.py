"""The planar bipeds' walk in MuJoCo: turkey walking and blind walking over slopes.

:func:`run_planar_walk` builds the robot, its gait and a
:class:`~virtual_actuators.simulation.Simulator`, then runs the control loop at 1 kHz: read
``q``, ``v`` and the contact switches, let the gait compute the joint efforts, step the physics.
Every tick is recorded (see :mod:`virtual_actuators.experiments.walk_log` for the channels); the
result carries the log and its metrics (JSON-able), and can be plotted like the seed's Figs. 9
and 15 (:func:`plot_planar_walk`). The robot is judged fallen by
:func:`~virtual_actuators.gaits.runner.has_fallen`.
"""

from __future__ import annotations

import dataclasses
import math
import time as wallclock
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ..exceptions import InvalidInputError
from ..experiments.contact_stats import StanceForces
from ..experiments.metrics import compute_metrics
from ..experiments.progress import Progress
from ..experiments.recorder import Recorder
from ..experiments.walk_log import STANDARD_CHANNELS
from ..models.loader import load_robot
from ..simulation.simulator import Simulator
from ..simulation.terrain import Terrain
from .base import Gait, Walk, check_distribution
from .runner import WalkResult, has_fallen, terrain_points

STARTUP = 2.0  # [s] metrics ignore the first seconds (start-up)
STANCE_SAMPLING = 4  # stance contact forces are read every this many ticks (250 Hz)


def with_speed(parameters, speed: float | None):
    """``parameters`` with ``speed`` (unchanged for None)."""
    return parameters if speed is None else dataclasses.replace(parameters, speed=speed)


def run_planar_walk(
    walk: Walk,
    duration: float,
    speed: float | None = None,
    terrain: str | Terrain | None = None,
    progress: bool = True,
    on_tick: Callable[[Simulator, Gait], None] | None = None,
    stop_on_fall: bool = True,
    seed: int | None = None,
    parameters: object | None = None,
    distribution: str | None = None,
) -> WalkResult:
    """Simulate a planar biped's walk and measure it (a :class:`Walk`'s ``run``).

    Args:
        walk: The walk (its robot, gait, push and defaults).
        duration: Simulated time [s].
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
        parameters: The gait's parameters (a ``walk.parameters``; default: the gait's);
            ``speed`` overrides theirs.
        distribution: ``"partitioned"`` or ``"qp"``: how double support shares the body's
            wrench (overrides ``parameters.distribution``; default: the gait's).

    Returns:
        The :class:`~virtual_actuators.gaits.runner.WalkResult`.

    Raises:
        InvalidInputError: Bad speed, terrain, seed, parameters or distribution.

    """
    if speed is not None and not (math.isfinite(speed) and 0.0 < speed <= 1.5):
        raise InvalidInputError(f"speed must be in (0, 1.5] m/s, got {speed}.")
    if terrain is None:
        terrain = walk.terrain
    terrain_model = terrain if isinstance(terrain, Terrain) else Terrain.parse(terrain)
    expected = walk.parameters
    if parameters is not None and not isinstance(parameters, expected):
        raise InvalidInputError(
            f"{walk.name}: parameters must be a {expected.__name__}, got "
            f"{type(parameters).__name__}."
        )
    if distribution is not None:
        check_distribution(distribution)
        parameters = dataclasses.replace(parameters or expected(), distribution=distribution)
    robot = load_robot(walk.robot)
    gait = walk.make_gait(robot, speed, parameters)
    simulator = Simulator(robot, terrain_model)
    q0 = gait.initial_configuration()
    q0[_index(robot, "boom_z")] += float(terrain_model.height(0.0))
    simulator.reset(q0)
    push, push_time = _push(walk, seed)
    simulator.push(np.array([push, 0.0, 0.0]), frame="body", duration=push_time)
    recorder = Recorder(
        STANDARD_CHANNELS,
        state_names=gait.machine.names,
        capacity=int(duration * 1000) + 16,
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
    stance = StanceForces(simulator, terrain_model)
    bar = Progress(duration) if progress else None
    gait.controller.warm_up(simulator.q)  # kernels loaded before the clock starts
    start = wallclock.perf_counter()
    _loop(gait, simulator, terrain_model, recorder, stance, duration, bar, on_tick, stop_on_fall)
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


def _push(walk: Walk, seed: int | None) -> tuple[float, float]:
    """The start-up push ``(force [N], duration [s])``, varied by ``seed``.

    Raises:
        InvalidInputError: ``seed`` is neither None nor an int.

    """
    push, push_time = walk.push, walk.push_time  # [N], [s]
    if seed is not None:
        if isinstance(seed, bool) or not isinstance(seed, int | np.integer):
            raise InvalidInputError(f"seed must be an int or None, got {seed!r}.")
        force_scale, time_scale = np.random.default_rng(int(seed)).uniform(0.7, 1.3, size=2)
        push, push_time = push * float(force_scale), push_time * float(time_scale)
    return push, push_time


def _loop(
    gait: Gait,
    simulator: Simulator,
    terrain: Terrain,
    recorder: Recorder,
    stance: StanceForces,
    duration: float,
    bar: Progress | None,
    on_tick: Callable[[Simulator, Gait], None] | None,
    stop_on_fall: bool,
) -> None:
    """The control loop at 1 kHz: read, compute, step, record every tick."""
    robot, machine = gait.robot, gait.machine
    x_index, z_index = _index(robot, "boom_x"), _index(robot, "boom_z")
    pitch_index = _index(robot, "boom_pitch")
    v_x = robot.model.joints[robot.model.getJointId("boom_x")].idx_v
    contact_frames = gait.contact_frames
    nominal = gait.nominal_height()  # [m]
    fall_time = None
    tick = 0
    append_row, state_index, bunny, granny = (
        recorder.append_row,
        machine.index,
        gait.bunny,
        gait.granny,
    )
    height_at = terrain.height
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
        if bar is not None and tick % 100 == 0:
            bar.set(simulator.time)
        if stop_on_fall and fall_time is not None and now > fall_time + 0.5:
            break


def plot_planar_walk(result: WalkResult, path: str | Path, window=None) -> Path:
    """Draw a planar walk like the seed's Fig. 9 (level ground) or Fig. 15 (slopes).

    Args:
        result: The walk.
        path: The image to write.
        window: ``(t0, t1)`` simulated seconds to draw (either may be None), or None for all.

    Returns:
        The path written.

    """
    from ..experiments.plots import plot_walk

    log = result.log
    title = f"{log.metadata['walk']}: {log.metadata['robot']} on {log.metadata['terrain']}"
    heights = log.terrain_points[:, 1]
    layout = "time" if np.ptp(heights) == 0.0 else "terrain"  # Fig. 9 vs Fig. 15
    return plot_walk(
        log, path, title=title, metrics=result.metrics, layout=layout, window=window
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
