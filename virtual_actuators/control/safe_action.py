"""What ``va.run`` checks each tick, and the effort a failed tick sends (`SafeAction`)."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..exceptions import InvalidInputError
from ..kinematics.kernels import finite
from ..kinematics.tree import KinematicTree
from ..models.robot import Robot
from ..vocabulary.arguments import as_float_array, check_number, describe
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


class Reading(NamedTuple):
    """A driver's ``(q, v, stamp)`` reading, unpacked (`check_reading`)."""

    q: object  # the configuration as read (checked by check_state)
    v: object  # the velocity as read
    stamp: float  # the time stamp as a float (NaN when malformed)
    reason: str | None  # "malformed reading" (then q and v are None), else None


def check_reading(reading: object) -> Reading:
    """Unpack a ``(q, v, stamp)`` reading; the arrays are checked by `check_state`."""
    try:
        q, v, stamp = reading
        if isinstance(stamp, (str, bytes)):
            raise TypeError
        stamp = float(stamp)
    except (TypeError, ValueError, OverflowError):
        return Reading(None, None, math.nan, "malformed reading")
    return Reading(q, v, stamp, None)


def check_state(
    q: object, v: object, tree: KinematicTree
) -> tuple[np.ndarray | None, np.ndarray | None, str | None]:
    """Check a reading's ``q`` and ``v`` against the robot.

    Returns:
        ``(q, v, None)`` (near-unit quaternions normalised), or ``(None, None, reason)``:
        ``"malformed reading"``, ``"non-finite"`` or ``"non-unit quaternion"`` (1e-3 off).
    """
    nq, nv = tree.nq, tree.nv
    if (  # a driver's contiguous float64 vectors of the right sizes, as they are (every tick's)
        q.__class__ is _ARRAY and v.__class__ is _ARRAY and q.dtype is _FLOAT
        and v.dtype is _FLOAT and q.shape == (nq,) and v.shape == (nv,)
        and q.flags.c_contiguous and v.flags.c_contiguous
    ):  # fmt: skip
        q_array, v_array = q, v
    else:
        q_array, v_array = _vector(q, nq), _vector(v, nv)
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


__all__ = [
    "DEFAULT_DAMPING", "DEFAULT_HOLD_TIME", "SAFE_ACTIONS", "Reading", "SafeAction",
    "check_effort", "check_reading", "check_state",
]  # fmt: skip
