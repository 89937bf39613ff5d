"""``va.run``'s checks (its arguments, each tick's reading and effort) and its `SafeAction`."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..exceptions import InvalidInputError
from ..kinematics.kernels import finite
from ..kinematics.tree import KinematicTree, tree_of
from ..models.robot import Robot
from ..vocabulary.arguments import as_float_array, check_flag, check_number, check_robot, describe
from .effort_limits import urdf_effort_limits

#: The values of ``run(safe_action=...)``.
SAFE_ACTIONS = ("zero", "hold", "damp")

#: ``run(safe_action="damp")``'s default joint damping [N m s/rad, or N s/m for a prismatic
#: joint], on every velocity entry but a floating base's and the passive joints'.
DEFAULT_DAMPING = 1.0

#: ``run(safe_action="hold")``'s default longest hold [s] (then zero effort).
DEFAULT_HOLD_TIME = 0.1


_ARRAY, _FLOAT = np.ndarray, np.dtype(np.float64)  # the classes of a driver's usual arrays


def _vector(value: object, size: int) -> np.ndarray | None:
    """``value`` as a float64 ``(size,)`` array, or None if it is not ``size`` real numbers."""
    if isinstance(value, np.ndarray) and value.dtype == np.float64:
        if value.shape != (size,):
            return None
        return value if value.flags.c_contiguous else np.ascontiguousarray(value)
    try:
        array = as_float_array(value, "state", f"{size} real numbers")
    except InvalidInputError:
        return None
    return array if array.shape == (size,) else None


def check_state(
    q: object, v: object, tree: KinematicTree
) -> tuple[np.ndarray | None, np.ndarray | None, str | None]:
    """Check a reading's ``q`` and ``v`` against the robot.

    Returns:
        ``(q, v, None)`` (near-unit quaternions normalised), or ``(None, None, reason)``:
        ``"malformed reading"``, ``"non-finite"`` or ``"non-unit quaternion"`` (1e-3 off).
    """
    q_array, v_array = _vector(q, tree.nq), _vector(v, tree.nv)  # contiguous float64 as they are
    if q_array is None or v_array is None:
        return None, None, "malformed reading"
    if not finite(v_array):
        return None, None, "non-finite"
    if not tree.unit_slices:  # no norm to check
        return (q_array, v_array, None) if finite(q_array) else (None, None, "non-finite")
    try:  # finiteness and unit norms in one pass
        return tree.check_configuration(q_array), v_array, None
    except InvalidInputError:
        return None, None, "non-finite" if not finite(q_array) else "non-unit quaternion"


def check_effort(output: object, nv: int) -> np.ndarray | None:
    """A controller's efforts (an array, or an object with ``tau``) as ``(nv,)`` finite floats.

    Returns:
        The efforts, or None (another size, complex, bool or non-numeric entries, NaN, inf).
    """
    tau = getattr(output, "tau", output)
    if tau.__class__ is not _ARRAY or tau.dtype is not _FLOAT:
        try:
            tau = np.asarray(tau)
        except (TypeError, ValueError):
            return None
        if tau.dtype.kind not in "fiu":  # complex, bool, object, str: not efforts
            return None
        tau = tau.astype(np.float64)
    if tau.shape != (nv,):
        return None
    if not tau.flags.c_contiguous:
        tau = np.ascontiguousarray(tau)
    return tau if finite(tau) else None


class SafeAction:
    """The effort ``va.run`` sends on a failed tick.

    Args:
        robot: The robot (size of the efforts, floating base, passive joints, effort limits).
        action: One of `SAFE_ACTIONS`.
        damping: ``"damp"``: a number >= 0 for every entry but a floating base's and the
            passive joints', or ``(nv,)`` numbers >= 0 [N m s/rad, N s/m].
        hold_ticks: ``"hold"``: the most consecutive failed ticks holding the last effort.

    Raises:
        InvalidInputError: A bad ``action`` or ``damping``.
    """

    def __init__(self, robot: Robot, action: object, damping: object, hold_ticks: int) -> None:
        if not isinstance(action, str) or action not in SAFE_ACTIONS:
            raise InvalidInputError(
                f"run(): safe_action must be one of {SAFE_ACTIONS}, got {describe(action)}."
            )
        model = robot.model
        nv = model.nv
        self.action, self.nv, self.hold_ticks = action, nv, hold_ticks
        if np.ndim(damping) == 0:
            gain = check_number(damping, "run(): damping [N m s/rad]", minimum=0.0)
            self.damping = np.full(nv, gain)
            passive = set(getattr(robot, "passive_joints", ()))
            for joint_id in range(1, model.njoints):
                joint = model.joints[joint_id]
                floating = joint_id == 1 and joint.shortname() == "JointModelFreeFlyer"
                if floating or model.names[joint_id] in passive:
                    self.damping[joint.idx_v : joint.idx_v + joint.nv] = 0.0
        else:
            expected = f"a number >= 0 or {nv} numbers >= 0 (one per velocity entry)"
            self.damping = as_float_array(damping, "run(): damping", expected, copy=True)
            bad = self.damping.shape != (nv,) or not np.isfinite(self.damping).all()
            if bad or (self.damping < 0.0).any():
                raise InvalidInputError(f"run(): damping must be {expected}, got {damping!r}.")
        self.limits = urdf_effort_limits(robot)
        self.last: np.ndarray | None = None  # the last good effort ("hold")
        self.failed_ticks = 0  # consecutive

    def good(self, tau: np.ndarray) -> None:
        """A tick sent the controller's ``tau``."""
        self.failed_ticks = 0
        if self.action == "hold":
            self.last = tau.copy()

    def effort(self, v: np.ndarray | None) -> np.ndarray:
        """The effort of a failed tick; ``v``: the tick's checked velocity, or None."""
        self.failed_ticks += 1
        if self.action == "hold" and self.last is not None:
            if self.failed_ticks <= self.hold_ticks:
                return self.last.copy()
        elif self.action == "damp" and v is not None:
            return np.clip(-self.damping * v, -self.limits, self.limits)
        return np.zeros(self.nv)


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
    read_state: Callable[[], tuple]
    write_effort: Callable[[np.ndarray], None]
    should_stop: Callable[[], bool] | None
    sense: Callable[[np.ndarray, np.ndarray, float], object] | None
    after_tick: Callable[..., object] | None  # run_loop's AfterTick
    write_final: Callable[[np.ndarray], None]  # the final zero effort's (default: write_effort)
    estimator: object | None = None  # update(reading, tau) before the controller, or None


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
    sense: object,
    after_tick: object,
    write_final: object,
    estimator: object = None,
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
    for what, hook in ("sense", sense), ("after_tick", after_tick), ("write_final", write_final):
        check_callback(hook, what)
    if estimator is not None and not callable(getattr(estimator, "update", None)):
        raise InvalidInputError(
            f"run(): estimator needs an update(reading, tau) method, got {describe(estimator)}."
        )
    return RunSettings(
        period, duration, stale_after, realtime, safe, tree_of(robot), robot, read_state,
        write_effort, should_stop, sense, after_tick, write_final or write_effort, estimator,
    )  # fmt: skip


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
