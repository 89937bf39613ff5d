"""``va.run``'s arguments checked once before the loop: [`check_run`][]."""

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
    """[`run`][]'s checked arguments."""

    period: float  # time between two ticks [s]
    duration: float | None  # wall-clock time of the loop [s]
    stale_after: float  # a reading whose stamp did not advance this long is stale [s]
    realtime: bool  # whether the loop sleeps to hold the rate
    safe: SafeAction  # what a failed tick sends
    tree: KinematicTree  # the robot's kinematic tree (the readings' checks)
    robot: Robot  # the robot whose efforts are written


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


__all__ = ["MIN_RATE_HZ", "RunSettings", "check_callback", "check_run", "robot_of"]
