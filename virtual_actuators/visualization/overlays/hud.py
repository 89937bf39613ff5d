"""Text beside the robot, facing the camera: the legend (once) and the gait's state name."""

from __future__ import annotations

import meshcat.geometry as mg

from ..frame_snapshot import FrameSnapshot
from ..legend import legend_entries
from ..robot_scene import RobotScene, safe
from ..shapes import material, text_faces
from .base import Overlay


class LegendOverlay(Overlay):
    """The legend of colours and scales at the robot's left: only what has been drawn."""

    roots = ("hud/legend",)

    def __init__(self) -> None:
        self._shown: frozenset[str] | None = None

    def draw(self, scene: RobotScene, frame: FrameSnapshot) -> None:
        """Lay the legend out again if the set of drawn things has grown."""
        drawn = frozenset(scene.drawn)
        if drawn == self._shown:
            return
        self._shown = drawn
        scene.nodes.remove("hud/legend")
        self.layout(scene, drawn)

    @staticmethod
    def layout(scene: RobotScene, drawn: frozenset[str]) -> None:
        """Draw the legend's lines and colour swatches for the ``drawn`` keys."""
        scales = scene.force_scale, scene.moment_scale, scene.effort_reference
        entries = legend_entries(scene.palette, *scales, drawn)
        size = min(1.5, max(0.35, 0.75 * scene.extent))
        spacing = 0.105 * size
        left = -(0.6 * scene.extent + 0.5 * size)
        top = 0.5 * scene.extent
        nodes = scene.nodes
        for k, (color, text) in enumerate(entries):
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

    roots = ("hud/state",)

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
