"""Virtual actuators: triads at their frames, the requested, produced and shared wrenches.

Wrenches are along the reference frame's axes, moments about the action frame's origin; a
chain's share is drawn at its reaction frame, its moment about that frame's origin. The produced
wrench is drawn when it differs from the request: orange when adjusted, red when inadmissible.
"""

from __future__ import annotations

import numpy as np

from ..frame_snapshot import Actuator, FrameSnapshot, reactions_of
from ..robot_scene import RobotScene, cross, safe
from .base import Overlay


class WrenchOverlay(Overlay):
    """The actuator of a frame (with its solution or wrench) and the controller's attachments."""

    roots = ("frames", "wrench")

    def draw(self, scene: RobotScene, frame: FrameSnapshot) -> None:
        """Draw ``frame.actuator`` and every attachment of ``frame.output`` that has a wrench.

        Raises:
            FrameNotFoundError: A frame of an actuator is not in the robot.
        """
        actuator, solution = frame.actuator, frame.solution
        if actuator is not None:
            if solution is not None:
                answer = solution.requested, solution.wrench, solution.forces
                self.draw_actuator(scene, "actuator", actuator, *answer, not solution.admissible)
            elif frame.wrench is None:
                self.draw_actuator(scene, "actuator", actuator, None, None, None, False)
            else:
                wrench = frame.wrench
                forces = wrench[None, :] if len(reactions_of(actuator)) == 1 else None
                self.draw_actuator(scene, "actuator", actuator, wrench, wrench, forces, False)
        if frame.output is None:
            return
        output = frame.output
        for name, attachment in frame.attachments():
            solution = output.solutions.get(name)
            requested = np.asarray(output.wrenches[name], dtype=float)
            produced = np.asarray(output.produced.get(name, requested), dtype=float)
            if solution is not None:
                forces, inadmissible = solution.forces, not solution.admissible
            else:  # a serial actuator: one chain carries the whole wrench
                forces, inadmissible = produced[None, :], False
            self.draw_actuator(
                scene, name, attachment.actuator, requested, produced, forces, inadmissible
            )

    @staticmethod
    def draw_actuator(
        scene: RobotScene,
        key: str,
        actuator: Actuator,
        requested: np.ndarray | None,
        produced: np.ndarray | None,
        forces: np.ndarray | None,
        inadmissible: bool,
    ) -> None:
        """Triads of the actuator's frames, then its wrenches under ``wrench/<key>``.

        Args:
            scene: The robot's scene.
            key: Name of the actuator in the scene.
            actuator: The actuator.
            requested: Requested wrench on its axes (None: the triads only).
            produced: Produced wrench (drawn when it differs from the request).
            forces: ``(chains, axes)`` share of each chain (None: not drawn).
            inadmissible: Whether the request was inadmissible.

        Raises:
            FrameNotFoundError: A frame of the actuator is not in the robot.
        """
        data, palette = scene.data, scene.palette
        axes = tuple(actuator.axes)
        reactions = reactions_of(actuator)
        action_id = scene.frame(actuator.action, "action")
        reference_id = scene.frame(actuator.reference, "reference")
        reaction_ids = [scene.frame(r, "reaction") for r in reactions]
        scene.triad("action", actuator.action)
        scene.triad("reference", actuator.reference)
        for reaction in reactions:
            scene.triad("reaction", reaction)
        if requested is None:
            return
        origin = data.oMf[action_id].translation
        rotation = data.oMf[reference_id].rotation
        name = f"wrench/{safe(key)}"
        colors = (palette.requested_force, palette.requested_moment)
        force_drawn, moment_drawn = scene.wrench(
            f"{name}/requested", origin, rotation, axes, requested, colors
        )
        if force_drawn:
            scene.mark("requested_force")
        if moment_drawn:
            scene.mark("requested_moment")
        if produced is not None:
            scale = max(1.0, float(np.max(np.abs(requested))))
            if inadmissible or not np.allclose(produced, requested, rtol=0.0, atol=1e-6 * scale):
                kind = "inadmissible" if inadmissible else "produced"
                colors = (getattr(palette, kind),) * 2
                drawn = scene.wrench(f"{name}/{kind}", origin, rotation, axes, produced, colors)
                if any(drawn):
                    scene.mark(kind)
        if forces is None:
            return
        mask = scene.rotational_mask(axes)
        for reaction, reaction_id, share in zip(reactions, reaction_ids, forces, strict=True):
            force, moment = scene.split(axes, share)
            force_w = rotation @ force
            at = data.oMf[reaction_id].translation
            moment_w = rotation @ moment + cross(origin - at, force_w)  # about the reaction
            moment_w = rotation @ (mask * (rotation.T @ moment_w))  # on the actuator's axes
            share_name = f"{name}/share/{safe(reaction)}"
            force_arrow = force_w * scene.force_scale
            if scene.arrow(f"{share_name}/force", at, force_arrow, palette.share_force, 1, 0.75):
                scene.mark("share_force")
            moment_arrow = moment_w * scene.moment_scale
            if scene.arrow(f"{share_name}/moment", at, moment_arrow, palette.share_moment, 2, 0.75):
                scene.mark("share_moment")
