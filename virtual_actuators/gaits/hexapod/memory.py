"""The hexapod walker's memory, and the walker's inputs and state read from it."""

from __future__ import annotations

import math

import numpy as np

from ...control.plan.memory import Memory
from ...exceptions import InvalidInputError

#: ``memory.support``: 0.0 for tripod a, 1.0 for b.
SUPPORT = ("a", "b")

__all__ = ["SUPPORT", "WalkerState", "walker_memory"]


def walker_memory(ground: float) -> Memory:
    """The walker's memory at rest, its ground plane at height ``ground`` (body axes) [m]."""
    zeros = (0.0, 0.0)
    return Memory(
        command=(0.0, 0.0, 0.0), setpoint=zeros, acceleration=zeros, body_velocity=zeros,
        filtered=zeros, filter_time=0.0, target_time=0.0, plane=(0.0, 0.0, ground), phase=0.0,
        ground=0.0, support=0.0, lift_off=(0.0,) * 9, targets=(0.0,) * 9, rates=(0.0,) * 9,
        pendulum=0.0,
    )  # fmt: skip


class WalkerState:
    """The walker's inputs and state, read from and written to its ``memory`` (a mixin)."""

    memory: Memory
    _command = (0.0, 0.0, 0.0)  # the command last written into the memory

    def set_command(self, velocity: tuple[float, float] | np.ndarray, yaw_rate: float) -> None:
        """Set the body velocity ``(vx, vy)`` in the heading frame [m/s] and the yaw rate [rad/s].

        Raises:
            InvalidInputError: Values that are not finite.
        """
        vx, vy = velocity
        vx, vy, yaw_rate = float(vx), float(vy), float(yaw_rate)
        if not (math.isfinite(vx) and math.isfinite(vy) and math.isfinite(yaw_rate)):
            raise InvalidInputError(
                f"set_command: velocity and yaw rate must be finite, got {velocity}, {yaw_rate}."
            )
        command = (vx, vy, yaw_rate)
        if command != self._command:  # the same command is not written again (a tick's cost)
            self.memory.command = self._command = command

    @property
    def velocity(self) -> np.ndarray:
        """Commanded body velocity in the heading frame ``(vx, vy)`` [m/s]."""
        return np.array(self.memory.command[:2])

    @property
    def yaw_rate(self) -> float:
        """Commanded yaw rate [rad/s]."""
        return self.memory.command[2]

    @property
    def velocity_setpoint(self) -> np.ndarray:
        """The command, acceleration-limited [m/s]."""
        return np.array(self.memory.setpoint)

    @property
    def phase(self) -> float:
        """Swing progress, 0 to 1."""
        return self.memory.phase

    @phase.setter
    def phase(self, value: float) -> None:
        self.memory.phase = value

    @property
    def support(self) -> str:
        """The support tripod of the last stance (``"a"`` or ``"b"``)."""
        return SUPPORT[int(self.memory.support)]

    @support.setter
    def support(self, value: str) -> None:
        self.memory.support = float(SUPPORT.index(value))

    @property
    def pendulum_angle(self) -> float:
        """The pendulum's angle from the vertical, in the heading x-z plane [rad]."""
        return self.memory.pendulum
