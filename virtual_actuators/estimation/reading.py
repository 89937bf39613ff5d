"""What a robot measures in one period: its encoders, its IMU and its contact switches."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..exceptions import InvalidInputError


def _vector(value: object, field: str, size: int | None) -> np.ndarray:
    """``value`` as a read-only finite float64 vector of ``size`` entries (a copy)."""
    try:
        array = np.array(value, dtype=float)
    except (TypeError, ValueError) as error:
        raise InvalidInputError(
            f"SensorReading.{field} is not an array of numbers: {error}"
        ) from None
    if array.ndim != 1 or (size is not None and array.shape[0] != size):
        expected = f"({size},)" if size is not None else "(n,)"
        raise InvalidInputError(
            f"SensorReading.{field} has shape {array.shape}; expected {expected}."
        )
    bad = np.flatnonzero(~np.isfinite(array))
    if bad.size:
        raise InvalidInputError(
            f"SensorReading.{field} holds a non-finite value at index {int(bad[0])} "
            f"({array[bad[0]]}); every entry must be finite."
        )
    array.setflags(write=False)
    return array


@dataclass(frozen=True)
class SensorReading:
    """One reading of a robot's sensors: only what a real robot measures.

    The constructor checks every field and keeps read-only copies of the arrays. Whether the
    joint names belong to a robot and whether the time advances is checked by the estimator
    that takes the reading (`LeggedEstimator.update`).

    Attributes:
        time: When the sensors were read [s].
        joint_names: The 1-DoF joints the encoders measure (actuated and passive), in the order
            of the arrays below.
        joint_position: ``(n,)`` encoder positions [rad or m].
        joint_velocity: ``(n,)`` encoder velocities [rad/s or m/s].
        joint_effort: ``(n,)`` efforts applied during the last period [N m or N].
        gyro: ``(3,)`` angular velocity of the IMU frame, in its own axes [rad/s].
        accelerometer: ``(3,)`` specific force of the IMU frame (its acceleration minus
            gravity: ``(0, 0, +9.81)`` at rest), in its own axes [m/s^2].
        contacts: Contact switches, frame name -> closed, or None when the robot has none.

    Raises:
        InvalidInputError: A field is not finite, has the wrong size or type (the message names
            the field), or two joints share a name.
    """

    time: float
    joint_names: tuple[str, ...]
    joint_position: np.ndarray
    joint_velocity: np.ndarray
    joint_effort: np.ndarray
    gyro: np.ndarray
    accelerometer: np.ndarray
    contacts: dict[str, bool] | None = None

    def __post_init__(self) -> None:
        if isinstance(self.time, bool) or not isinstance(self.time, (int, float, np.number)):
            raise InvalidInputError(
                f"SensorReading.time must be a number of seconds, not {type(self.time).__name__}."
            )
        if not math.isfinite(float(self.time)):
            raise InvalidInputError(f"SensorReading.time must be finite, not {self.time}.")
        object.__setattr__(self, "time", float(self.time))
        names = self.joint_names
        if isinstance(names, str) or not all(isinstance(name, str) for name in names):
            raise InvalidInputError(
                "SensorReading.joint_names must be a sequence of joint names (str)."
            )
        names = tuple(names)
        if len(set(names)) != len(names):
            twice = sorted({name for name in names if names.count(name) > 1})
            raise InvalidInputError(f"SensorReading.joint_names names {twice} more than once.")
        object.__setattr__(self, "joint_names", names)
        for field in ("joint_position", "joint_velocity", "joint_effort"):
            object.__setattr__(self, field, _vector(getattr(self, field), field, len(names)))
        for field in ("gyro", "accelerometer"):
            object.__setattr__(self, field, _vector(getattr(self, field), field, 3))
        if self.contacts is not None:
            if not isinstance(self.contacts, dict) or not all(
                isinstance(frame, str) and isinstance(closed, (bool, np.bool_))
                for frame, closed in self.contacts.items()
            ):
                raise InvalidInputError(
                    "SensorReading.contacts must be None or a dict frame name (str) -> bool."
                )
            object.__setattr__(
                self, "contacts", {frame: bool(closed) for frame, closed in self.contacts.items()}
            )
