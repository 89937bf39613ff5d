"""A fixed-rate control loop for real hardware: ``va.run(controller, read_state, write_effort)``.

Every reading and every effort is checked, a failed tick sends the safe action, and the loop
always ends by writing zero effort; the contract is in docs/reference/control.md.
"""

from __future__ import annotations

import math
import re
import time as clock
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..core import kernel
from ..estimation.reading import SensorReading
from ..exceptions import InvalidInputError
from ..models.robot import Robot
from .gc_policy import LoopCollector, check_gc_policy
from .safe_action import (
    DEFAULT_DAMPING,
    DEFAULT_HOLD_TIME,
    RunSettings,
    check_effort,
    check_run,
    check_state,
)

State = tuple[np.ndarray, np.ndarray, float]

_ARRAY, _FLOAT = np.ndarray, np.dtype(np.float64)  # the classes of a driver's usual arrays
#: ``(q, v, bounds)``: the unit-norm error of ``q``, -1 if ``q`` or ``v`` is not finite.
_READING_ERROR = kernel("reading_error", None)

#: The field a rejected SensorReading's message names first.
_FIELD = re.compile(r"SensorReading(?:\.(\w+)| at)")

#: Tick durations kept for the statistics (the last ones: memory stays bounded on long runs).
TICK_HISTORY = 100_000


@dataclass
class RunStats:
    """What a [`run`][] did.

    Attributes:
        ticks: Ticks run.
        overruns: Ticks that took longer than the period.
        failed_ticks: Ticks that sent the safe action instead of the controller's effort.
        zero_ticks: Ticks that sent zero effort (a failed tick whose safe action gave zero).
        reasons: Failed ticks per reason (``"stale"``, ``"controller error: ConstraintError"``).
        attachment_failures: Ticks in which a [`Controller`][]'s failure policy fired, per
            ``"attachment: reason -> action"``.
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
    sense: Callable[[np.ndarray, np.ndarray, float], object] | None = None,
    after_tick: AfterTick | None = None,
    write_final: Callable[[np.ndarray], None] | None = None,
    estimator: object | None = None,
) -> RunStats:
    """Run ``controller`` at ``rate_hz`` until ``duration`` elapses or ``should_stop()``.

    Args:
        controller: Has ``compute(q, v, time)`` returning efforts or an object with ``tau``.
        read_state: Returns ``(q, v, stamp)``: configuration, velocity, reading time [s].
        write_effort: Sends ``(nv,)`` efforts, in the robot's `velocity_names` order.
        rate_hz: Control rate [Hz], at least `MIN_RATE_HZ`.
        duration: Wall-clock time of the loop [s] (None: until ``should_stop``).
        stale_after: A reading whose stamp did not advance this long is stale [s] (default:
            three periods).
        realtime: Sleep to hold the rate (False: ticks back to back, e.g. on a simulation).
        should_stop: Polled every tick; True ends the loop.
        robot: The robot whose efforts are written (default: ``controller.robot``).
        safe_action: What a failed tick sends: ``"zero"``, ``"hold"`` or ``"damp"``.
        damping: ``"damp"``'s joint damping [N m s/rad, N s/m]: one number for every entry
            but a floating base's and the passive joints' (default 1), or ``(nv,)`` numbers.
        hold_time: ``"hold"``'s longest run of failed ticks holding the last good effort [s].
        gc_policy: ``"between-ticks"`` (see [`gc_policy`][]) or ``"python"`` (left alone).
        sense: ``sense(q, v, stamp)`` on a checked reading: ``compute``'s fourth argument.
        after_tick: ``after_tick(q, v, stamp, output, tau)`` after each write (``q``, ``v``
            None when the reading failed, ``output`` None on a failed tick).
        write_final: Writes the final zero effort (default: ``write_effort``).
        estimator: ``update(reading, tau)`` returning ``q``, ``v``, ``time`` (a
            ``va.estimation.LeggedEstimator``): a [`SensorReading`][virtual_actuators.SensorReading]
            from ``read_state`` goes through it, with the last effort written, before the
            controller; one it rejects fails the tick (``"bad sensor reading: FIELD"``).

    Returns:
        The [`RunStats`][].

    Raises:
        InvalidInputError: A bad rate, duration, stale time, ``realtime``, ``safe_action``,
            ``damping``, ``hold_time`` or ``gc_policy``; a controller without ``compute``;
            callbacks that are not callable; neither ``duration`` nor ``should_stop``; no
            robot (neither ``robot`` nor ``controller.robot``) or not the controller's; an
            ``estimator`` without ``update``.
        KeyboardInterrupt: Ctrl-C, re-raised after the final zero effort (so are the errors
            of ``write_effort``, ``should_stop`` and ``after_tick``, and exceptions that are
            not `Exception`; if the final write fails too, a note on the error says so).
    """
    settings = check_run(
        controller, read_state, write_effort, rate_hz, duration, stale_after, realtime,
        should_stop, robot, safe_action, damping, hold_time, sense, after_tick, write_final,
        estimator,
    )  # fmt: skip
    collector = LoopCollector(check_gc_policy(gc_policy, "run()"))
    warm_up_driven(controller, settings.robot)
    stats = RunStats()
    with collector:
        _loop_then_zero(controller, settings, stats, collector)
    return stats


def _loop_then_zero(
    controller: object, settings: RunSettings, stats: RunStats, collector: LoopCollector
) -> None:
    """`_loop`, then the final zero effort whatever ended it (Ctrl-C included)."""
    start, ending = clock.perf_counter(), None
    try:
        _loop(controller, settings, stats, start, collector)
    except BaseException as error:
        ending = error
        raise
    finally:  # whatever ended the loop (Ctrl-C included): motors to zero
        try:
            settings.write_final(np.zeros(settings.tree.nv))
        except Exception as write_error:  # raised unless it would hide what ended the loop
            if ending is None:
                raise
            ending.add_note(
                f"run(): the final zero effort could not be written either: {write_error!r}"
            )
        stats.wall_time = clock.perf_counter() - start


#: ``run``'s ``after_tick(q, v, stamp, output, tau)``.
AfterTick = Callable[[np.ndarray | None, np.ndarray | None, float, object, np.ndarray], object]


def _loop(
    controller: object, settings: RunSettings, stats: RunStats, start: float, gc: LoopCollector
) -> None:
    """Tick until the end: read, compute or fail, write, ``after_tick``, collect, sleep."""
    end = math.inf if settings.duration is None else start + settings.duration - 1e-12
    deadline, period, realtime, safe = start, settings.period, settings.realtime, settings.safe
    should_stop, write_effort, after_tick = (
        settings.should_stop, settings.write_effort, settings.after_tick
    )
    perf_counter, append = clock.perf_counter, stats.tick_times.append
    between_ticks = gc.between_ticks if gc.active else None
    failures_seen = stats.attachment_failures
    tick = _Tick(controller, settings)
    hold = safe.action == "hold"
    while True:
        now = perf_counter()
        if now >= end or (should_stop is not None and should_stop()):
            break
        tau, q, v, stamp, output, reason = tick(now)
        if reason is None:
            if hold:
                safe.good(tau)
            else:
                safe.failed_ticks = 0
            failures = getattr(output, "failures", None)
            for name, failure in failures.items() if failures else ():
                why, action = getattr(failure, "reason", "?"), getattr(failure, "action", "?")
                key = f"{name}: {why} -> {action}"
                failures_seen[key] = failures_seen.get(key, 0) + 1
        else:
            tau = safe.effort(v)
            stats.failed_ticks += 1
            stats.reasons[reason] = stats.reasons.get(reason, 0) + 1
            if not tau.any():
                stats.zero_ticks += 1
        write_effort(tau)
        tick.last_tau = tau
        done = perf_counter()
        stats.ticks += 1
        append(done - now)
        if after_tick is not None:
            after_tick(q, v, stamp, output, tau)
        if between_ticks is not None:  # after the write: in the slack before the next tick
            between_ticks()
        deadline += period
        if done > deadline:
            stats.overruns += 1
            deadline = done  # no catching up
        elif realtime:
            clock.sleep(max(min(deadline, end) - perf_counter(), 0.0))


def warm_up_driven(controller: object, robot: Robot) -> None:
    """Warm up what a loop drives before its clock starts (``va.run``'s first step)."""
    for owner in (controller, getattr(controller, "controller", None)):
        model = getattr(getattr(owner, "robot", None), "model", None)
        if callable(getattr(owner, "warm_up", None)) and model is robot.model:  # a gait too
            owner.warm_up(robot.neutral())
            return


class _Tick:
    """One tick: ``(efforts, q, v, stamp, output, None)``, or None efforts and a reason last.

    ``q`` and ``v`` are None unless the reading passed its checks (the safe action may damp ``v``).
    """

    __slots__ = (
        "bounds", "compute", "estimator", "fresh", "last", "last_tau", "nv", "q_shape",
        "read_state", "sense", "stale_after", "tree", "v_shape",
    )  # fmt: skip

    def __init__(self, controller: object, settings: RunSettings) -> None:
        self.compute, self.read_state, self.sense = (
            controller.compute, settings.read_state, settings.sense
        )
        tree = self.tree = settings.tree
        self.nv, self.stale_after = tree.nv, settings.stale_after
        self.last, self.fresh = None, 0.0  # the newest stamp read, and when it came [s]
        self.q_shape, self.v_shape = (tree.nq,), (tree.nv,)
        self.bounds = tree.unit_bounds
        self.estimator, self.last_tau = settings.estimator, np.zeros(tree.nv)

    def __call__(self, now: float) -> tuple:
        try:
            reading = self.read_state()
        except Exception as error:  # a driver's failure: this tick sends the safe action
            return None, None, None, math.nan, None, f"read error: {type(error).__name__}"
        if self.estimator is not None and isinstance(reading, SensorReading):
            try:
                estimate = self.estimator.update(reading, self.last_tau)
            except InvalidInputError as error:  # the estimator as it was: the safe action
                named = _FIELD.match(str(error))
                return None, None, None, math.nan, None, (
                    f"bad sensor reading: {named.group(1) if named else 'estimate'}"
                )
            reading = (estimate.q, estimate.v, estimate.time)
        try:  # a (q, v, stamp) reading; q and v are checked below
            q, v, stamp = reading
            if stamp.__class__ is not float:
                if isinstance(stamp, (str, bytes)):
                    raise TypeError
                stamp = float(stamp)
        except (TypeError, ValueError, OverflowError):
            return None, None, None, math.nan, None, "malformed reading"
        if not math.isfinite(stamp):
            return None, None, None, stamp, None, "non-finite"  # a bad clock: never the reference
        if self.last is None or stamp > self.last:
            self.last, self.fresh = stamp, now
        elif now - self.fresh > self.stale_after:  # the stamps did not advance for stale_after
            return None, None, None, stamp, None, "stale"
        if not (  # a driver's contiguous float64 arrays of the right sizes: one compiled pass
            q.__class__ is _ARRAY and v.__class__ is _ARRAY and q.dtype is _FLOAT
            and v.dtype is _FLOAT and q.shape == self.q_shape and v.shape == self.v_shape
            and q.flags.c_contiguous and v.flags.c_contiguous and _READING_ERROR is not None
            and 0.0 <= _READING_ERROR(q, v, self.bounds) <= 1e-12
        ):  # fmt: skip
            q, v, reason = check_state(q, v, self.tree)
            if reason is not None:
                return None, None, None, stamp, None, reason
        sense = self.sense
        try:
            if sense is None:
                output = self.compute(q, v, stamp)
            else:
                try:
                    sensed = sense(q, v, stamp)
                except Exception as error:  # the sensing's failure: the safe action
                    return None, q, v, stamp, None, f"sense error: {type(error).__name__}"
                output = self.compute(q, v, stamp, sensed)
            tau = check_effort(output, self.nv)
        except Exception as error:  # any failure of the law
            return None, q, v, stamp, None, f"controller error: {type(error).__name__}"
        if tau is None:
            return None, q, v, stamp, None, "bad effort"
        return tau, q, v, stamp, output, None
