"""The overlay interface: one kind of thing drawn over the robot, frame after frame.

An overlay reads a `FrameSnapshot` and draws on
a `RobotScene` with its primitives (arrows,
triads, spans, markers) or directly into its nodes. Dynamic nodes (declared with
``scene.nodes.declare``) that an overlay does not ``use`` in a frame are hidden at the end of
that frame, so an overlay draws what is there and never hides anything itself.
"""

from __future__ import annotations

from abc import ABC, abstractmethod

from ..frame_snapshot import FrameSnapshot
from ..robot_scene import RobotScene


class Overlay(ABC):
    """Something drawn over the robot: subclass it and implement `draw`.

    Attributes:
        roots: Nodes under which the overlay draws (relative to the viewer's prefix);
            `clear` removes them.
    """

    roots: tuple[str, ...] = ()

    def setup(self, scene: RobotScene) -> None:  # noqa: B027 - optional hook
        """Draw what never changes, once, when the overlay joins a viewer (nothing by default).

        Args:
            scene: The robot's scene.
        """

    @abstractmethod
    def draw(self, scene: RobotScene, frame: FrameSnapshot) -> None:
        """Draw one frame: place and ``use`` the overlay's nodes for ``frame``.

        Args:
            scene: The robot's scene, its kinematics at ``frame.q``.
            frame: What to draw.
        """

    def clear(self, scene: RobotScene) -> None:
        """Delete every node of the overlay (it is created anew if drawn again).

        Args:
            scene: The robot's scene.
        """
        for root in self.roots:
            scene.nodes.remove(root)

    def __repr__(self) -> str:
        return f"{type(self).__name__}(roots={self.roots})"
