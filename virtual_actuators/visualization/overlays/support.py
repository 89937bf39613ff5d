"""Support feet: a translucent sphere at each support frame of the frame (the state's first)."""

from __future__ import annotations

import meshcat.geometry as mg

from ..frame_snapshot import FrameSnapshot
from ..robot_scene import RobotScene, safe
from ..shapes import material
from .base import Overlay


class SupportOverlay(Overlay):
    """A marker at each of ``frame.support``."""

    roots = ("support",)

    def draw(self, scene: RobotScene, frame: FrameSnapshot) -> None:
        """Mark the support frames.

        Raises:
            FrameNotFoundError: A support frame is not in the robot.
        """
        for name in frame.support:
            frame_id = scene.frame(name, "support")
            scene.mark("support")
            scene.marker(
                f"support/{safe(name)}",
                lambda: (
                    mg.Sphere(scene.sizes["support"]),
                    material(scene.palette.support, 0.45, depthWrite=False),
                ),
                scene.data.oMf[frame_id].translation,
            )
