"""Joint effort gauges: a sphere of radius ``|tau| / limit`` inside a shell, at each joint.

The shell (the effort limit, else ``effort_reference``) turns red when the joint saturates;
gauges stand on the camera's side of their joint, along its axis.
"""

from __future__ import annotations

import meshcat.geometry as mg
import numpy as np

from ...exceptions import InvalidInputError
from ..frame_snapshot import FrameSnapshot
from ..robot_scene import RobotScene, safe
from ..shapes import material, translation
from .base import Overlay


class EffortOverlay(Overlay):
    """Effort gauges of the frame's joint efforts (a controller's output, else a solution's)."""

    roots = ("efforts",)

    def draw(self, scene: RobotScene, frame: FrameSnapshot) -> None:
        """Draw a gauge per actuated joint when the frame has efforts.

        Raises:
            InvalidInputError: The efforts are not ``(model.nv,)``.
        """
        tau = frame.tau
        if tau is None:
            return
        tau = np.asarray(tau, dtype=float)
        if tau.shape != (scene.model.nv,):
            raise InvalidInputError(f"tau has shape {tau.shape}, expected ({scene.model.nv},).")
        saturated = frame.saturated
        nodes, data, palette = scene.nodes, scene.data, scene.palette
        radius = scene.sizes["effort"]
        for joint, joint_id, index, limit, axis in scene.effort_joints:
            value = float(tau[index])
            node = f"efforts/{safe(joint)}"
            if not nodes.has(f"{node}/positive/ball"):
                shell = material(palette.effort_limit, 0.22, depthWrite=False)
                saturation = material(palette.saturated, 0.5, depthWrite=False)
                positive, negative = palette.effort_positive, palette.effort_negative
                nodes.create(f"{node}/positive/ball", mg.Sphere(1.0), material(positive))
                nodes.create(f"{node}/negative/ball", mg.Sphere(1.0), material(negative))
                nodes.create(f"{node}/shell/ball", mg.Sphere(radius), shell)
                nodes.create(f"{node}/saturated/ball", mg.Sphere(1.12 * radius), saturation)
                for part in ("", "/positive", "/negative", "/shell", "/saturated"):
                    nodes.declare(node + part)
            placement = data.oMi[joint_id]
            direction = placement.rotation @ axis
            if direction @ scene.view < 0:
                direction = -direction  # put the gauge on the camera's side of the joint
            centre = placement.translation + direction * 1.2 * radius
            reference = limit if limit is not None else scene.effort_reference
            fraction = min(1.0, abs(value) / reference)
            over = limit is not None and abs(value) > limit * (1.0 + 1e-9)
            is_saturated = bool(saturated[index]) if saturated is not None else over
            nodes.use(node)
            nodes.use(f"{node}/shell")
            if limit is None:
                scene.mark("no_limit")
            nodes.place(f"{node}/shell/ball", translation(centre))
            if fraction > 1e-6:
                sign = "positive" if value > 0 else "negative"
                nodes.use(f"{node}/{sign}")
                scene.mark(f"effort_{sign}")
                nodes.place(f"{node}/{sign}/ball", translation(centre, fraction * radius))
            if is_saturated:
                nodes.use(f"{node}/saturated")
                scene.mark("saturated")
                nodes.place(f"{node}/saturated/ball", translation(centre))
