"""Every walk's closed loop: `drive` runs an `Episode` on ``va.run``, with a `MujocoHardware`.

What each hook does: docs/reference/control.md ("The walks run on ``va.run``").
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from ..control.run_loop import RunStats, run
from ..experiments.progress import Progress
from ..simulation.simulator import MujocoHardware, Simulator
from .base import Gait
from .runner import Episode, LoopEnd


def drive(
    episode: Episode,
    duration: float,
    progress: bool = True,
    on_tick: Callable[[Simulator, Gait], None] | None = None,
    stop_on_fall: bool = True,
) -> LoopEnd:
    """Run an episode's closed loop for ``duration`` simulated seconds, on [`run`][].

    No garbage collection inside a tick (``va.run``'s default ``gc_policy``). A failed tick
    sends zero effort (counted in ``LoopEnd.run``); the final zero effort sets MuJoCo's controls
    without stepping (`MujocoHardware.hold_effort`), so the log and the simulator end at the
    last control tick.

    Args:
        episode: The prepared walk.
        duration: Simulated time [s].
        progress: Show a tqdm progress bar.
        on_tick: Called after every physics step (e.g. a viewer's throttled update).
        stop_on_fall: End the run 0.5 s after the first fallen tick.

    Returns:
        The `LoopEnd` (the recorder's metadata gets ``wall_time_s``).
    """
    simulator = episode.simulator
    bar = Progress(duration) if progress else None
    episode.gait.warm_up(simulator.q)  # lowered, kernels loaded before the clock starts
    ticks = WalkTicks(episode, duration, bar, on_tick, stop_on_fall)
    hardware = MujocoHardware(simulator, ignore_unactuated=episode.ignore_unactuated)
    estimation = episode.estimation  # on the estimate: the sensors, never the state
    read = hardware.read_state if estimation is None else hardware.read_sensors
    stats = run(
        ticks, read, hardware.write_effort, 1.0 / simulator.control_period,
        realtime=False, should_stop=ticks.should_stop,
        sense=episode.sense if estimation is None else ticks.score_then_sense,
        after_tick=ticks.after_tick, write_final=hardware.hold_effort,
        estimator=None if estimation is None else estimation.estimator,
    )  # fmt: skip
    if bar is not None:
        bar.close(simulator.time)
    end = ticks.end(stats, hardware.physics_time)
    episode.recorder.metadata["wall_time_s"] = end.wall
    return end


class WalkTicks:
    """An episode's gait as ``va.run``'s controller, and what `drive` does after each tick.

    Args:
        episode: The prepared walk.
        duration: Simulated time [s].
        bar: The progress bar, or None.
        on_tick: Called after every tick, or None.
        stop_on_fall: End the run 0.5 s after the first fallen tick.

    Attributes:
        robot: The gait's robot (the efforts ``va.run`` writes).
        compute: The tick: the compiled machine's ``compute``, else the gait's.
        ticks: Ticks run.
        fall_time: Simulated time of the first fallen tick [s], None if none.
        fall_tick: Index of the first fallen tick, None if none.
    """

    def __init__(
        self,
        episode: Episode,
        duration: float,
        bar: Progress | None,
        on_tick: Callable[[Simulator, Gait], None] | None,
        stop_on_fall: bool,
    ) -> None:
        gait, simulator = episode.gait, episode.simulator
        self.episode, self.gait, self.simulator = episode, gait, simulator
        self.robot = gait.robot
        compiled = gait.compiled  # warmed up by `drive`: its tick, without the two calls above it
        self.compute: Callable[..., Any] = gait.compute if compiled is None else compiled.compute
        self._bar, self._on_tick, self._stop_on_fall = bar, on_tick, stop_on_fall
        self._record_every = episode.record_every
        self._stance_every = episode.stance_every or episode.record_every
        self._sample, self._support = episode.stance.sample, gait.support_contacts
        self._fallen, self._record = episode.fallen, episode.record
        self._data = simulator.data  # MuJoCo's state: its time read directly (a tick's cost)
        self._end_time = duration - 1e-9
        period = simulator.control_period
        self._last_stamp = self._end_time - 1.5 * period  # only the last tick's stamp is later
        capacity = max(0, math.ceil((duration - self._data.time) / period)) + 2
        self._efforts = np.empty((capacity, simulator.robot.model.nv))  # [N m or N]
        self._velocities = np.empty_like(self._efforts)
        self.ticks, self.fall_time, self.fall_tick = 0, None, None
        self._stopping = False

    def score_then_sense(self, q: np.ndarray, v: np.ndarray, now: float) -> object:
        """On the estimate: score it against the truth at its reading's time, then sense."""
        self.episode.estimation.tick()
        return self.episode.sense(q, v, now)

    def should_stop(self) -> bool:
        """Whether the simulated time is up, or the fall was 0.5 s ago (``stop_on_fall``)."""
        return self._stopping or self._data.time >= self._end_time

    def after_tick(
        self, q: np.ndarray | None, v: np.ndarray | None, now: float, output: Any,
        tau: np.ndarray,
    ) -> None:  # fmt: skip
        """Keep the tick's efforts and ``v``; stance forces, fall test, record, watchers."""
        tick = self.ticks
        try:
            self._velocities[tick] = math.nan if v is None else v
        except IndexError:  # a time that did not advance by whole periods
            self._efforts, self._velocities = _grown(self._efforts), _grown(self._velocities)
            self._velocities[tick] = math.nan if v is None else v
        self._efforts[tick] = tau
        self.ticks = tick = tick + 1
        if self.episode.estimation is not None and output is not None:  # the rest: the truth
            q, v = self.simulator.q, self.simulator.v
            self.episode.observe_truth(q, v)
        fall_time = self.fall_time
        if fall_time is None and tick % self._stance_every == 0:
            self._sample(self._support())
        stopping = fall_time is not None and self._stop_on_fall and now > fall_time + 0.5
        if output is not None:  # a tick that passed va.run's checks (q and v too)
            fallen = fall_time is not None or self._fallen(q)
            if fallen and fall_time is None:
                self.fall_time, self.fall_tick = now, tick - 1
            every = self._record_every
            if every == 1 or tick % every == 1 or stopping or now > self._last_stamp:
                self._record(now, q, v, output, fallen)  # the log ends at the last tick
        if self._on_tick is not None:
            self._on_tick(self.simulator, self.gait)
        if self._bar is not None and tick % 100 == 0:
            self._bar.set(self.simulator.time)
        if stopping:
            self._stopping = True

    def end(self, stats: RunStats, physics: float) -> LoopEnd:
        """The `LoopEnd` of the run ``stats`` describes (``physics``: seconds stepping)."""
        tick = self.ticks
        return LoopEnd(
            tick, self.fall_time, stats.wall_time, physics, self._efforts[:tick],
            self._velocities[:tick], self.episode.base_rate, self.fall_tick,
            self.simulator.control_period, stats,
        )  # fmt: skip


def _grown(rows: np.ndarray) -> np.ndarray:
    """``rows`` followed by as many uninitialised rows."""
    return np.concatenate([rows, np.empty_like(rows)])
