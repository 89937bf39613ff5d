"""``va.run``'s arguments checked once before the loop, and the staleness of its readings.

[`check_run`][] turns [`run`][]'s arguments into [`RunSettings`][] (raising
[`InvalidInputError`][virtual_actuators.InvalidInputError] on the first bad one, in the order
of ``run``'s ``Raises:``); [`Freshness`][] tells a stale reading from a fresh one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..exceptions import InvalidInputError
from ..kinematics.tree import KinematicTree, tree_of
from ..models.robot import Robot
from ..vocabulary.arguments import check_flag, check_number, check_robot, describe
from .safe_action import SafeAction

#: The slowest rate ``run`` accepts [Hz] (a period of at most 1000 s).
MIN_RATE_HZ = 1e-3


@dataclass(frozen=True, slots=True)
class RunSettings:
    """[`run`][]'s checked arguments.

    Attributes:
        period: Time between two ticks [s].
        duration: Wall-clock time of the loop [s], or None.
        stale_after: A reading whose stamp did not advance for this long is stale [s].
        realtime: Whether the loop sleeps to hold the rate.
        safe: What a failed tick sends.
        tree: The robot's kinematic tree (the readings' checks).
        robot: The robot whose efforts are written.
    """

    period: float  # [s]
    duration: float | None  # [s]
    stale_after: float  # [s]
    realtime: bool
    safe: SafeAction
    tree: KinematicTree
    robot: Robot


@dataclass(slots=True)
class Freshness:
    """The newest stamp read and when it arrived (``perf_counter`` time) [s].

    Attributes:
        stale_after: A reading whose stamp did not advance for this long is stale [s].
        last_stamp: The newest stamp read, None before the first.
        last_fresh: When it was read [s].
    """

    stale_after: float
    last_stamp: float | None = None
    last_fresh: float = 0.0

    def stale(self, stamp: float, now: float) -> bool:
        """Whether the stamps have not advanced for ``stale_after`` at ``now`` (``stamp`` read)."""
        if self.last_stamp is None or stamp > self.last_stamp:
            self.last_stamp, self.last_fresh = stamp, now
        return now - self.last_fresh > self.stale_after


def check_run(
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
) -> RunSettings:
    """[`run`][]'s arguments checked.

    Raises:
        InvalidInputError: The first bad argument, in the order of ``run``'s ``Raises:``.
    """
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
    check_callback(should_stop, "should_stop", "(returning True to stop)")
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
    robot = robot_of(controller, robot)
    hold_time = check_number(hold_time, "run(): hold_time [s]", minimum=0.0)
    safe = SafeAction(robot, safe_action, damping, math.floor(hold_time * rate_hz + 1e-9))
    return RunSettings(period, duration, stale_after, realtime, safe, tree_of(robot), robot)


def check_callback(callback: object, what: str, returning: str = "") -> None:
    """Refuse an optional callback of ``run`` that is neither None nor callable.

    Raises:
        InvalidInputError: ``callback`` is not callable (naming ``what``).
    """
    if callback is not None and not callable(callback):
        raise InvalidInputError(
            f"run(): {what} must be callable{f' {returning}' if returning else ''} or None, "
            f"got {describe(callback)}."
        )


def robot_of(controller: object, robot: object) -> Robot:
    """The robot whose efforts ``run`` writes: ``robot``, else ``controller.robot``.

    Raises:
        InvalidInputError: Neither is a robot, or ``robot`` is not the controller's.
    """
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


__all__ = ["MIN_RATE_HZ", "Freshness", "RunSettings", "check_callback", "check_run", "robot_of"]
