"""A fixed-rate control loop for real hardware: ``va.run(controller, read_state, write_effort)``.

Each tick reads the robot's state, computes the efforts and writes them, then sleeps until the
next period. The efforts always have the robot's size and order: ``(model.nv,)``, one per
velocity entry (the robot is the controller's, or ``robot=``), whatever the readings hold.

Safety first. A tick fails when:

- ``read_state`` raises (``"read error: <type>"``), or returns something that is not
  ``(q, v, stamp)`` with ``q`` of ``nq`` and ``v`` of ``nv`` real numbers (``"malformed
  reading"``), values that are not finite (``"non-finite"``), or a quaternion far from unit
  norm (``"non-unit quaternion"``);
- the reading is stale: its stamp did not advance for ``stale_after`` seconds (``"stale"``);
- the controller raises (``"controller error: <type>"``) or returns efforts that are not
  ``nv`` finite real numbers (``"bad effort"``: another size, complex, NaN...).

A failed tick sends the **safe action** instead (``safe_action=``): ``"zero"`` effort (the
default), ``"hold"`` the last good effort for at most ``hold_time`` (then zero), or ``"damp"``,
joint damping ``-damping * v`` clipped to the URDF's effort limits (zero when the tick has no
valid velocity: a failed, malformed or stale reading). [`RunStats`][] counts every failed
tick by reason. Failures inside a [`Controller`][] (one attachment's
singular or infeasible distribution) are its own ``on_failure`` policy's, and counted in
`RunStats.attachment_failures`.

The loop **always ends by writing zero effort** of the robot's size, whatever ended it: the
duration, ``should_stop``, an error of ``write_effort`` or ``should_stop``, or Ctrl-C (then
re-raised, as every exception that is not a per-tick failure, after that write). With
[`MujocoHardware`][virtual_actuators.simulation.MujocoHardware] that last zero command steps the
simulation one more period. A tick that takes longer than the period is an overrun: the loop
does not try to catch up (the next tick starts at once), and counts it.

Python's garbage collector runs between ticks, never inside one (``gc_policy``, see
[`gc_policy`][]). Before the clock starts the controller's kernels load
([`warm_up_driven`][virtual_actuators.control.warm_up.warm_up_driven]): nothing changes.

The callbacks are plain functions, so any driver fits: ``read_state() -> (q, v, stamp)`` with
``stamp`` the time the reading was taken [s] (any clock, increasing), and ``write_effort(tau)``.
[`MujocoHardware`][virtual_actuators.simulation.MujocoHardware] implements both on a MuJoCo
simulation (the simulated robot as the hardware).
"""

from __future__ import annotations

import math
import time as clock
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..exceptions import InvalidInputError
from ..kinematics.tree import KinematicTree, tree_of
from ..models.robot import Robot
from ..vocabulary.arguments import check_flag, check_number, check_robot, describe
from .gc_policy import LoopCollector, check_gc_policy
from .safe_action import (
    DEFAULT_DAMPING,
    DEFAULT_HOLD_TIME,
    SafeAction,
    check_effort,
    check_reading,
    check_state,
)
from .warm_up import warm_up_driven

State = tuple[np.ndarray, np.ndarray, float]

#: Tick durations kept for the statistics (the last ones: memory stays bounded on long runs).
TICK_HISTORY = 100_000

#: The slowest rate ``run`` accepts [Hz] (a period of at most 1000 s).
MIN_RATE_HZ = 1e-3


@dataclass
class RunStats:
    """What a [`run`][] did.

    Attributes:
        ticks: Ticks run.
        overruns: Ticks that took longer than the period.
        failed_ticks: Ticks that sent the safe action instead of the controller's effort.
        zero_ticks: Ticks that sent zero effort (a failed tick whose safe action gave zero).
        reasons: Failed ticks per reason: ``{"stale": n, "non-finite": n, "controller error:
            ConstraintError": n, ...}`` (see `run_loop`).
        attachment_failures: Ticks in which a [`Controller`][]'s failure
            policy fired, per ``"attachment: reason -> action"`` (e.g. ``"stance: constraint
            -> fallback"``).
        tick_times: Duration of the last `TICK_HISTORY` ticks, read to write [s].
        wall_time: Duration of the loop [s].

    """

    ticks: int = 0
    overruns: int = 0
    failed_ticks: int = 0
    zero_ticks: int = 0
    reasons: dict[str, int] = field(default_factory=dict)
    attachment_failures: dict[str, int] = field(default_factory=dict)
    tick_times: deque[float] = field(default_factory=lambda: deque(maxlen=TICK_HISTORY))
    wall_time: float = 0.0

    def summary(self) -> str:
        """One line: ticks, rate, overruns, failed ticks and the tick-time percentiles."""
        times = np.array(self.tick_times) * 1e6 if self.tick_times else np.zeros(1)
        rate = self.ticks / self.wall_time if self.wall_time > 0 else 0.0
        reasons = ", ".join(f"{reason}: {n}" for reason, n in self.reasons.items())
        return (
            f"{self.ticks} ticks at {rate:.0f} Hz, {self.overruns} overruns, "
            f"{self.failed_ticks} failed ticks{f' ({reasons})' if reasons else ''}, "
            f"tick median {np.median(times):.0f} us, p99 {np.percentile(times, 99):.0f} us, "
            f"max {times.max():.0f} us"
        )


def run(
    controller: object,
    read_state: Callable[[], State],
    write_effort: Callable[[np.ndarray], None],
    rate_hz: float = 1000.0,
    duration: float | None = None,
    stale_after: float | None = None,
    realtime: bool = True,
    should_stop: Callable[[], bool] | None = None,
    *,
    robot: Robot | None = None,
    safe_action: str = "zero",
    damping: float | np.ndarray = DEFAULT_DAMPING,
    hold_time: float = DEFAULT_HOLD_TIME,
    gc_policy: str = "between-ticks",
) -> RunStats:
    """Run ``controller`` at ``rate_hz`` until ``duration`` elapses or ``should_stop()``.

    Args:
        controller: Anything with ``compute(q, v, time)`` (``time``: the reading's stamp)
            returning efforts or an object with ``tau`` (a
            [`Controller`][], a gait, your own class).
        read_state: Returns ``(q, v, stamp)``: configuration, velocity, time of the reading [s].
        write_effort: Sends ``(nv,)`` efforts to the motors, in the robot's velocity order
            (`velocity_names`).
        rate_hz: Control rate [Hz], at least `MIN_RATE_HZ`.
        duration: Wall-clock time of the loop [s] (None: until ``should_stop``); the loop ends
            then, even within a long period. On a simulation run with ``realtime=False``, stop
            on the simulated time with ``should_stop`` instead.
        stale_after: A reading whose stamp did not advance for this long is stale [s]
            (default: three periods).
        realtime: Sleep to hold the rate (False: run ticks back to back, e.g. on a simulation).
        should_stop: Polled every tick; True ends the loop.
        robot: The robot whose efforts are written (default: ``controller.robot``, which a
            [`Controller`][] and a gait have). Give it for a controller
            of your own without one.
        safe_action: What a failed tick sends: ``"zero"``, ``"hold"`` or ``"damp"`` (see
            `run_loop`).
        damping: ``safe_action="damp"``: joint damping [N m s/rad, N s/m], one number for every
            velocity entry but a floating base's and the passive joints' (default
            `DEFAULT_DAMPING`, 1), or ``(nv,)``
            numbers used as given.
        hold_time: ``safe_action="hold"``: the longest run of failed ticks that holds the last
            good effort [s] (``hold_time * rate_hz`` ticks); then zero effort.
        gc_policy: ``"between-ticks"`` (no garbage collection inside a tick, see
            [`gc_policy`][]) or ``"python"`` (left alone).

    Returns:
        The [`RunStats`][].

    Raises:
        InvalidInputError: A bad rate, duration, stale time, ``realtime``, ``safe_action``,
            ``damping``, ``hold_time`` or ``gc_policy``; a controller without ``compute``;
            callbacks that are not callable; neither ``duration`` nor ``should_stop``; no
            robot (neither ``robot`` nor ``controller.robot``) or not the controller's.
        KeyboardInterrupt: Ctrl-C, re-raised after the final zero effort (so are the errors
            of ``write_effort`` and ``should_stop``, and exceptions that are not
            `Exception`; if the final write fails too, a note on the error says so).

    """
    settings = _check_run(
        controller, read_state, write_effort, rate_hz, duration, stale_after, realtime,
        should_stop, robot, safe_action, damping, hold_time,
    )
    warm_up_driven(controller, settings.robot)
    stats, ending = RunStats(), None
    with LoopCollector(check_gc_policy(gc_policy, "run()")) as collector:
        start = clock.perf_counter()
        try:
            _loop(controller, read_state, write_effort, should_stop, settings, stats, start,
                  collector)  # fmt: skip
        except BaseException as error:
            ending = error
            raise
        finally:  # whatever ended the loop (Ctrl-C included): motors to zero
            _end_safe(write_effort, settings.tree.nv, ending)
            stats.wall_time = clock.perf_counter() - start
    return stats


@dataclass(frozen=True, slots=True)
class _Settings:
    """[`run`][]'s checked arguments."""

    period: float  # [s]
    duration: float | None  # [s]
    stale_after: float  # [s]
    realtime: bool
    safe: SafeAction
    tree: KinematicTree
    robot: Robot


@dataclass(slots=True)
class _Freshness:
    """The newest stamp read and when it arrived (``perf_counter`` time) [s]."""

    stale_after: float
    last_stamp: float | None = None
    last_fresh: float = 0.0

    def stale(self, stamp: float, now: float) -> bool:
        """Whether the stamps have not advanced for ``stale_after`` at ``now`` (``stamp`` read)."""
        if self.last_stamp is None or stamp > self.last_stamp:
            self.last_stamp, self.last_fresh = stamp, now
        return now - self.last_fresh > self.stale_after


def _check_run(
    controller: object,
    read_state: object,
    write_effort: object,
    rate_hz: object,
    duration: object,
    stale_after: object,
    realtime: object,
    should_stop: object,
    robot: object,
    safe_action: object,
    damping: object,
    hold_time: object,
) -> _Settings:
    """[`run`][]'s arguments checked (its Raises: InvalidInputError, in this order)."""
    rate_hz = check_number(rate_hz, "run(): rate_hz [Hz]", minimum=0.0)
    if rate_hz < MIN_RATE_HZ:
        raise InvalidInputError(
            f"run(): rate_hz must be >= {MIN_RATE_HZ:g} Hz (a period of at most "
            f"{1.0 / MIN_RATE_HZ:g} s), got {rate_hz!r}."
        )
    period = 1.0 / rate_hz
    stale_after = 3.0 * period if stale_after is None else stale_after
    stale_after = check_number(stale_after, "run(): stale_after [s]", minimum=0.0)
    realtime = check_flag(realtime, "run(): realtime")
    if should_stop is not None and not callable(should_stop):
        raise InvalidInputError(
            f"run(): should_stop must be callable (returning True to stop) or None, got "
            f"{describe(should_stop)}."
        )
    if duration is not None:
        duration = check_number(duration, "run(): duration [s]", minimum=0.0)
    elif should_stop is None:
        raise InvalidInputError("run(): give a duration or a should_stop callable.")
    if not callable(getattr(controller, "compute", None)):
        raise InvalidInputError(
            f"run(): controller needs a compute(q, v, time) method, got {describe(controller)}."
        )
    for what, callback in (("read_state", read_state), ("write_effort", write_effort)):
        if not callable(callback):
            raise InvalidInputError(f"run(): {what} must be callable, got {describe(callback)}.")
    robot = _robot_of(controller, robot)
    hold_time = check_number(hold_time, "run(): hold_time [s]", minimum=0.0)
    safe = SafeAction(robot, safe_action, damping, math.floor(hold_time * rate_hz + 1e-9))
    return _Settings(period, duration, stale_after, realtime, safe, tree_of(robot), robot)


def _loop(
    controller: object,
    read_state: Callable[[], State],
    write_effort: Callable[[np.ndarray], None],
    should_stop: Callable[[], bool] | None,
    settings: _Settings,
    stats: RunStats,
    start: float,
    collector: LoopCollector,
) -> None:
    """Tick until the duration elapses or ``should_stop()``: read, compute or fail, write.

    Then the garbage collector's turn, and the sleep until the next period.
    """
    freshness = _Freshness(settings.stale_after)
    end = math.inf if settings.duration is None else start + settings.duration
    deadline = start
    while True:
        now = clock.perf_counter()
        if now >= end - 1e-12 or (should_stop is not None and should_stop()):
            break
        tau, velocity, reason = _tick(controller, read_state, settings.tree, freshness, stats, now)
        if reason is None:
            settings.safe.good(tau)
        else:
            tau = settings.safe.effort(velocity)
            stats.failed_ticks += 1
            stats.reasons[reason] = stats.reasons.get(reason, 0) + 1
            if not tau.any():
                stats.zero_ticks += 1
        write_effort(tau)
        done = clock.perf_counter()
        stats.ticks += 1
        stats.tick_times.append(done - now)
        collector.between_ticks()  # after the write: in the slack before the next tick
        deadline += settings.period
        if done > deadline:
            stats.overruns += 1
            deadline = done  # no catching up
        elif settings.realtime:
            clock.sleep(max(min(deadline, end) - clock.perf_counter(), 0.0))


def _tick(
    controller: object,
    read_state: Callable[[], State],
    tree: KinematicTree,
    freshness: _Freshness,
    stats: RunStats,
    now: float,
) -> tuple[np.ndarray | None, np.ndarray | None, str | None]:
    """One tick: ``(efforts, velocity, None)``, or ``(None, checked velocity or None, reason)``.

    The velocity is the reading's when it passed the checks (the safe action may damp it).
    """
    try:
        reading = read_state()
    except Exception as error:  # a driver's failure: this tick sends the safe action
        return None, None, f"read error: {type(error).__name__}"
    q, v, stamp, reason = check_reading(reading)
    if reason is not None:
        return None, None, reason
    if not math.isfinite(stamp):
        return None, None, "non-finite"  # a bad clock never becomes the reference
    if freshness.stale(stamp, now):
        return None, None, "stale"
    q, v, reason = check_state(q, v, tree)
    if reason is not None:
        return None, None, reason
    try:
        output = controller.compute(q, v, stamp)
        tau = check_effort(output, tree.nv)
    except Exception as error:  # any failure of the law
        return None, v, f"controller error: {type(error).__name__}"
    if tau is None:
        return None, v, "bad effort"
    failures = getattr(output, "failures", None)
    if failures:
        _count_attachment_failures(stats, failures)
    return tau, v, None


def _end_safe(
    write_effort: Callable[[np.ndarray], None], nv: int, ending: BaseException | None
) -> None:
    """Write zero effort; if that fails while ``ending`` propagates, note it on ``ending``.

    Raises:
        Exception: The write's error when nothing else is propagating.

    """
    try:
        write_effort(np.zeros(nv))
    except Exception as error:
        if ending is None:
            raise
        ending.add_note(f"run(): the final zero effort could not be written either: {error!r}")


def _robot_of(controller: object, robot: object) -> Robot:
    """The robot whose efforts ``run`` writes: ``robot``, else ``controller.robot``."""
    own = getattr(controller, "robot", None)
    if robot is None:
        if own is None:
            raise InvalidInputError(
                "run(): the efforts' size and order come from the robot: give robot=..., or a "
                f"controller with a robot attribute (a va.Controller, a gait); "
                f"{describe(controller)} has none."
            )
        check_robot(own, "run(): controller.robot")
        return own
    check_robot(robot, "run()")
    if own is not None and getattr(own, "model", None) is not robot.model:
        raise InvalidInputError(
            f"run(): robot is {getattr(robot, 'name', '?')!r} but the controller's robot is "
            f"{getattr(own, 'name', describe(own))!r}; leave robot out to use the controller's."
        )
    return robot


def _count_attachment_failures(stats: RunStats, failures: dict) -> None:
    """Count a controller output's failure records (``ControlOutput.failures``)."""
    for name, failure in failures.items():
        key = f"{name}: {getattr(failure, 'reason', '?')} -> {getattr(failure, 'action', '?')}"
        stats.attachment_failures[key] = stats.attachment_failures.get(key, 0) + 1


__all__ = ["MIN_RATE_HZ", "RunStats", "run"]
