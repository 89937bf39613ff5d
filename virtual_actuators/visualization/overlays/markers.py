"""Effort gauges at the joints, support feet, and the legend and state name facing the camera.

A gauge is a sphere of radius ``|tau| / limit`` inside a shell (the effort limit, else
``effort_reference``), on the camera's side of the joint along its axis.
"""

from __future__ import annotations

import meshcat.geometry as mg
import numpy as np

from ...exceptions import InvalidInputError
from ..frame_snapshot import FrameSnapshot
from ..legend import legend_entries
from ..robot_scene import Overlay, RobotScene, safe
from ..shapes import material, text_faces, translation


class EffortOverlay(Overlay):
    """Effort gauges of the frame's joint efforts (a controller's output, else a solution's)."""

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


class SupportOverlay(Overlay):
    """A marker at each of ``frame.support``."""

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


class LegendOverlay(Overlay):
    """The legend of colours and scales at the robot's left: only what has been drawn."""

    def __init__(self) -> None:
        self._shown: frozenset[str] | None = None

    def draw(self, scene: RobotScene, frame: FrameSnapshot) -> None:
        """Lay the legend's lines and colour swatches out again if what was drawn has grown."""
        drawn = frozenset(scene.drawn)
        if drawn == self._shown:
            return
        self._shown, nodes = drawn, scene.nodes
        nodes.remove("hud/legend")
        size = min(1.5, max(0.35, 0.75 * scene.extent))
        spacing = 0.105 * size
        left = -(0.6 * scene.extent + 0.5 * size)
        top = 0.5 * scene.extent
        for k, (color, text) in enumerate(legend_entries(scene, drawn)):
            up = top - k * spacing
            name = f"hud/legend/line_{k:02d}"
            for face, mesh in text_faces(text, size, font_size=24):
                nodes.create(f"{name}/{face}", mesh)
            nodes.place(name, scene.hud_matrix(left, up))
            if color is not None:
                swatch = f"hud/legend/swatch_{k:02d}"
                nodes.create(swatch, mg.Box([0.06 * size] * 3), material(color))
                nodes.place(swatch, scene.hud_matrix(left - 0.56 * size, up))


class StateOverlay(Overlay):
    """The name of the gait's state, at the robot's upper right (inside its box's height)."""

    def draw(self, scene: RobotScene, frame: FrameSnapshot) -> None:
        """Show ``frame.state`` (each name is created once, then shown or hidden)."""
        if frame.state is None:
            return
        nodes = scene.nodes
        name = f"hud/state/{safe(frame.state)}"
        if not nodes.has(name):
            size = min(2.0, max(0.4, 0.8 * scene.extent))
            for face, mesh in text_faces(frame.state, size, font_size=30):
                nodes.create(f"{name}/{face}", mesh)
            nodes.declare(name)
            right, up = 0.3 * scene.extent + 0.4 * size, 0.3 * scene.extent  # beside the body
            nodes.place(name, scene.hud_matrix(right, up))
        nodes.use(name)
