"""The overlay interface: one kind of thing drawn over the robot, frame after frame.

An overlay draws what is there; the dynamic nodes it does not ``use`` in a frame are hidden.
"""

from __future__ import annotations

from abc import ABC, abstractmethod

from ..frame_snapshot import FrameSnapshot
from ..robot_scene import RobotScene


class Overlay(ABC):
    """Something drawn over the robot: subclass it and implement `draw`."""

    def setup(self, scene: RobotScene) -> None:  # noqa: B027 - optional hook
        """Draw what never changes, once, when the overlay joins a viewer (nothing by default)."""

    @abstractmethod
    def draw(self, scene: RobotScene, frame: FrameSnapshot) -> None:
        """Draw one frame: place and ``use`` the overlay's nodes (``scene`` is at ``frame.q``)."""

    def __repr__(self) -> str:
        return f"{type(self).__name__}()"
