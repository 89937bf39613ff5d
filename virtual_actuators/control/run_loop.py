"""A fixed-rate control loop for real hardware: ``va.run(controller, read_state, write_effort)``.

Each tick reads the robot's state, computes the efforts and writes them, then sleeps until the
next period. Safety first: a reading that is stale (its timestamp did not advance for
``stale_after`` seconds) or not finite, or a controller that raises, sends **zero effort** for that
tick (the reason is counted), and the loop always ends by sending zero effort, whatever ended it
(Ctrl-C included). With :class:`~virtual_actuators.simulation.hardware.MujocoHardware` that last
zero command steps the simulation one more period. A tick that takes longer than the period is
an overrun: the loop does not try to catch up (the next tick starts at once), and counts it.

The callbacks are plain functions, so any driver fits: ``read_state() -> (q, v, stamp)`` with
``stamp`` the time the reading was taken [s] (any clock, increasing), and ``write_effort(tau)``.
:class:`~virtual_actuators.simulation.hardware.MujocoHardware` implements both on a MuJoCo
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
from ..vocabulary.frames import check_number, describe

State = tuple[np.ndarray, np.ndarray, float]

#: Tick durations kept for the statistics (the last ones: memory stays bounded on long runs).
TICK_HISTORY = 100_000


@dataclass
class RunStats:
    """What a :func:`run` did.

    Attributes:
        ticks: Ticks run.
        overruns: Ticks that took longer than the period.
        zero_ticks: Ticks that sent zero effort (stale, non-finite or failed).
        reasons: Why, per kind: ``{"stale": n, "non-finite": n, "error: ...": n}``.
        tick_times: Duration of the last :data:`TICK_HISTORY` ticks, read to write [s].
        wall_time: Duration of the loop [s].

    """

    ticks: int = 0
    overruns: int = 0
    zero_ticks: int = 0
    reasons: dict[str, int] = field(default_factory=dict)
    tick_times: deque[float] = field(default_factory=lambda: deque(maxlen=TICK_HISTORY))
    wall_time: float = 0.0

    def summary(self) -> str:
        """One line: ticks, rate, overruns and the tick-time percentiles."""
        times = np.array(self.tick_times) * 1e6 if self.tick_times else np.zeros(1)
        rate = self.ticks / self.wall_time if self.wall_time > 0 else 0.0
        return (
            f"{self.ticks} ticks at {rate:.0f} Hz, {self.overruns} overruns, "
            f"{self.zero_ticks} zero-effort ticks, tick median {np.median(times):.0f} us, "
            f"p99 {np.percentile(times, 99):.0f} us, max {times.max():.0f} us"
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
) -> RunStats:
    """Run ``controller`` at ``rate_hz`` until ``duration`` elapses or ``should_stop()``.

    Args:
        controller: Anything with ``compute(q, v, time)`` (``time``: the reading's stamp)
            returning efforts or an object with ``tau`` (a
            :class:`~virtual_actuators.Controller`, a gait, your own class).
        read_state: Returns ``(q, v, stamp)``: configuration, velocity, time of the reading [s].
        write_effort: Sends ``(nv,)`` efforts to the motors.
        rate_hz: Control rate [Hz].
        duration: Wall-clock time of the loop [s] (None: until ``should_stop``). On a
            simulation run with ``realtime=False``, stop on the simulated time with
            ``should_stop`` instead.
        stale_after: A reading whose stamp did not advance for this long is stale [s]
            (default: three periods).
        realtime: Sleep to hold the rate (False: run ticks back to back, e.g. on a simulation).
        should_stop: Polled every tick; True ends the loop.

    Returns:
        The :class:`RunStats`.

    Raises:
        InvalidInputError: A bad rate, duration or stale time, a controller without
            ``compute``, callbacks that are not callable, or neither ``duration`` nor
            ``should_stop``.

    """
    rate_hz = check_number(rate_hz, "run(): rate_hz [Hz]", minimum=0.0)
    if rate_hz <= 0.0:
        raise InvalidInputError("run(): rate_hz must be > 0.")
    period = 1.0 / rate_hz
    stale_after = 3.0 * period if stale_after is None else stale_after
    stale_after = check_number(stale_after, "run(): stale_after [s]", minimum=0.0)
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

    stats = RunStats()
    last_stamp, last_fresh = None, None
    size = None  # efforts per command, from the first reading
    start = clock.perf_counter()
    deadline = start
    try:
        while True:
            now = clock.perf_counter()
            if duration is not None and now - start >= duration - 1e-12:
                break
            if should_stop is not None and should_stop():
                break
            q, v, stamp = read_state()
            if size is None:
                size = len(v)
            tau, reason = None, None
            try:
                stamp = float(stamp)
            except (TypeError, ValueError):
                stamp = math.nan
            if not math.isfinite(stamp):
                reason = "non-finite"  # a bad clock never becomes the reference
            else:
                if last_stamp is None or stamp > last_stamp:
                    last_stamp, last_fresh = stamp, now
                if now - last_fresh > stale_after:
                    reason = "stale"
                elif not (_finite(q) and _finite(v)):
                    reason = "non-finite"
            if reason is None:
                try:
                    output = controller.compute(q, v, stamp)
                    tau = np.asarray(getattr(output, "tau", output), dtype=float)
                    if tau.shape != (size,) or not _finite(tau):
                        tau, reason = None, "bad effort (shape or non-finite)"
                except Exception as error:  # any failure of the law: this tick sends zero
                    tau, reason = None, f"error: {type(error).__name__}"
            if tau is None:
                tau = np.zeros(size)
                stats.zero_ticks += 1
                stats.reasons[reason] = stats.reasons.get(reason, 0) + 1
            write_effort(tau)
            done = clock.perf_counter()
            stats.ticks += 1
            stats.tick_times.append(done - now)
            deadline += period
            if done > deadline:
                stats.overruns += 1
                deadline = done  # no catching up
            elif realtime:
                clock.sleep(max(deadline - clock.perf_counter(), 0.0))
    finally:
        if size is not None:  # whatever ended the loop (Ctrl-C included): motors to zero
            write_effort(np.zeros(size))
        stats.wall_time = clock.perf_counter() - start
    return stats


def _finite(values: object) -> bool:
    """Whether ``values`` are real numbers, all finite (False for anything malformed)."""
    try:
        array = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        return False
    return bool(math.isfinite(float(array.sum())) or np.isfinite(array).all())


__all__ = ["RunStats", "run"]
