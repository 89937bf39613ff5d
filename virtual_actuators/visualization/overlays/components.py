"""Virtual components of attachments: springs (coils), dampers (dashpots), set points (spheres).

Each is drawn from its reaction-side anchor to the action frame, on its translational axes; a
damper alone ends on its set point or, without one, lies `VELOCITY_DAMPER_LENGTH` robot sizes
along its first axis.
"""

from __future__ import annotations

from collections.abc import Callable

import meshcat.geometry as mg
import numpy as np

from ...components.base import Component
from ...control import Attachment
from ..frame_snapshot import FrameSnapshot
from ..robot_scene import RobotScene, cross, safe
from ..shapes import coil_mesh, material
from .base import Overlay

#: Length of a velocity damper's dashpot, relative to the robot's size.
VELOCITY_DAMPER_LENGTH = 0.7


def parameter(component: Component, attribute: str, size: int) -> np.ndarray:
    """A per-axis parameter as ``size`` floats: zeros if missing, else its first on every axis."""
    value = getattr(component, attribute, None)
    if value is None:
        return np.zeros(size)
    array = np.asarray(value, dtype=float)
    if array.shape != (size,):
        array = np.full(size, float(array.reshape(-1)[0]) if array.size else 0.0)
    return array


class ComponentOverlay(Overlay):
    """The components of every attachment of the frame's controller output."""

    roots = ("components",)

    def draw(self, scene: RobotScene, frame: FrameSnapshot) -> None:
        """Draw the components of ``frame.attachments()``.

        Raises:
            FrameNotFoundError: A sensor frame is not in the robot.
        """
        for key, attachment in frame.attachments():
            self.draw_attachment(scene, key, attachment)

    @staticmethod
    def draw_attachment(scene: RobotScene, key: str, attachment: Attachment) -> None:
        """Draw the components of one attachment under ``components/<key>``.

        Raises:
            FrameNotFoundError: A sensor frame is not in the robot.
        """
        sensor = attachment.sensor
        data, palette, sizes = scene.data, scene.palette, scene.sizes
        action = data.oMf[scene.frame(sensor.action, "action")].translation
        reaction = data.oMf[scene.frame(sensor.reaction, "reaction")].translation
        rotation = data.oMf[scene.frame(sensor.reference, "reference")].rotation
        for index, component in enumerate(attachment.components):
            axes = tuple(component.axes)
            picks = [(i, "xyz".index(a)) for i, a in enumerate(axes) if a in ("x", "y", "z")]
            if not picks:
                continue  # rotational components show through the moment arrows
            columns = [i for i, _ in picks]
            directions = rotation[:, [k for _, k in picks]]  # (3, t) world directions
            relative = directions.T @ (action - reaction)  # sensor reading on these axes [m]
            anchor = action - directions @ relative
            stiffness = parameter(component, "stiffness", len(axes))[columns]
            damping = parameter(component, "damping", len(axes))[columns]
            setpoint = getattr(component, "setpoint", None)
            target = None
            if setpoint is not None and np.shape(setpoint) == (len(axes),):
                target = action + directions @ (np.asarray(setpoint, float)[columns] - relative)
            spring, damper = bool(np.any(stiffness > 0)), bool(np.any(damping > 0))
            if damper and not spring:
                if target is not None:  # its other end moves with its set point (the bunny)
                    anchor = target
                else:  # a velocity damper acts on the body alone: drawn there
                    anchor = action - directions[:, 0] * VELOCITY_DAMPER_LENGTH * scene.extent
            name = f"components/{safe(key)}/{index}"
            offset = np.zeros(3)
            if spring and damper:
                side = cross(action - anchor, scene.view)
                norm = np.linalg.norm(side)
                if norm > 1e-9:
                    offset = side / norm * 1.3 * sizes["coil"]
            if spring:
                scene.span(
                    f"{name}/spring",
                    anchor + offset,
                    action + offset,
                    lambda: coil_mesh(radius=sizes["coil"]),
                    palette.spring,
                )
                scene.mark("spring")
                if target is not None:
                    scene.mark("setpoint")
                    scene.marker(
                        f"{name}/setpoint",
                        lambda: (mg.Sphere(sizes["setpoint"]), material(palette.setpoint)),
                        target,
                    )
            if damper:
                draw_dashpot(scene, f"{name}/damper", anchor - offset, action - offset)


def draw_dashpot(scene: RobotScene, name: str, start: np.ndarray, end: np.ndarray) -> None:
    """A dashpot from ``start`` (the housing's closed end) to ``end`` (the rod's end)."""
    length = float(np.linalg.norm(end - start))
    if length < 1e-9:
        return
    axis = (end - start) / length
    radius = scene.sizes["damper"]
    color = scene.palette.damper
    housing_end = start + 0.6 * (end - start)
    piston = start + 0.45 * (end - start)
    thickness = min(0.3 * radius, 0.05 * length)

    def cylinder(scale: float) -> Callable[[], mg.Cylinder]:
        return lambda: mg.Cylinder(1.0, scale * radius)

    scene.span(f"{name}/housing", start, housing_end, cylinder(1.0), color, 0.35)
    scene.span(f"{name}/cap", start, start + axis * thickness, cylinder(1.0), color)
    scene.span(f"{name}/piston", piston - axis * thickness, piston, cylinder(0.85), color)
    scene.span(f"{name}/rod", piston, end, cylinder(0.25), color)
    scene.mark("damper")
