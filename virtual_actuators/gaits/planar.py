"""What the planar bipeds (turkey, flamingo) share, and the swing profiles every gait uses.

Side names and axes, the swing foot's lift and set-point profiles, and the standing pose of a
planar biped on a boom (two-link leg inverse kinematics).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
import pinocchio as pin

from ..exceptions import InvalidInputError
from ..models.robot import Robot
from ..vocabulary.frames import resolve_frame, resolve_joint

SIDES = ("left", "right")
PLANAR_AXES = ("x", "z", "ry")


def other(side: str) -> str:
    """The other leg."""
    return "right" if side == "left" else "left"


def smoothstep(s: float) -> float:
    """``3 s^2 - 2 s^3`` on [0, 1], clipped: a set point that starts and ends at rest."""
    s = min(max(s, 0.0), 1.0)
    return s * s * (3.0 - 2.0 * s)


def lift_profile(phase: float, peak: float) -> float:
    """Swing foot height over the swing, 0 at both ends and 1 at ``peak`` (a phase in (0, 1)).

    A quarter sine up to the peak, a quarter cosine down after it: an early peak clears the
    ground quickly after lift-off and leaves a long, gentle descent.
    """
    phase = min(max(phase, 0.0), 1.0)
    if phase < peak:
        return math.sin(0.5 * math.pi * phase / peak)
    return math.cos(0.5 * math.pi * (phase - peak) / (1.0 - peak))



def planar_leg_ik(dx: float, dz: float, thigh: float, shin: float) -> tuple[float, float]:
    """Hip and knee angles that put a planar two-link leg's end at ``(dx, dz)`` from the hip.

    Joints turn about +y (a positive angle swings the distal link backward), the knee bends
    positively (it points forward), the body is upright.

    Args:
        dx: Foot x minus hip x [m].
        dz: Foot z minus hip z [m] (negative below the hip).
        thigh: Hip-to-knee length [m].
        shin: Knee-to-foot length [m].

    Returns:
        ``(hip, knee)`` [rad].

    Raises:
        InvalidInputError: The point is out of reach.

    """
    u, w = -dx, -dz
    cos_knee = (u * u + w * w - thigh**2 - shin**2) / (2.0 * thigh * shin)
    if not -1.0 - 1e-12 <= cos_knee <= 1.0 + 1e-12:
        raise InvalidInputError(
            f"Foot offset ({dx:.3f}, {dz:.3f}) m is out of reach of a {thigh:.3f} + {shin:.3f} m "
            "leg."
        )
    knee = math.acos(min(1.0, max(-1.0, cos_knee)))  # rounding at full extension
    hip = math.atan2(u, w) - math.atan2(shin * math.sin(knee), thigh + shin * math.cos(knee))
    return hip, knee


def planar_standing_configuration(
    robot: Robot,
    height: float,
    feet: Mapping[str, float],
    foot_frame: str = "{side}_foot",
    ground: float = 0.0,
) -> np.ndarray:
    """A standing configuration of a planar biped on a boom at a given hip height.

    Args:
        robot: A planar biped with joints ``boom_x``, ``boom_z``, ``boom_pitch``,
            ``SIDE_hip``, ``SIDE_knee`` (and optionally ``SIDE_ankle``, set so the foot is flat).
        height: Hip height above the foot frames [m].
        feet: Foot frame x relative to the hip, per side, e.g. ``{"left": 0.1, "right": -0.1}``.
        foot_frame: Name pattern of the frame at the end of the shin (ankle or point foot).
        ground: Height of the foot frames [m].

    Returns:
        ``q`` of size ``nq`` (Pinocchio convention).

    Raises:
        JointNotFoundError: A joint above is missing.
        InvalidInputError: A foot is out of reach.

    """
    model = robot.model
    q = robot.neutral()
    data = pin.Data(model)
    pin.framesForwardKinematics(model, data, q)

    def index(joint: str) -> int:
        return model.joints[resolve_joint(model, joint)].idx_q

    q[index("boom_z")] = ground + height
    q[index("boom_pitch")] = 0.0
    for side, dx in feet.items():
        hip = data.oMi[resolve_joint(model, f"{side}_hip")].translation
        knee = data.oMi[resolve_joint(model, f"{side}_knee")].translation
        end = data.oMf[resolve_frame(model, foot_frame.format(side=side), "foot")].translation
        thigh, shin = np.linalg.norm(knee - hip), np.linalg.norm(end - knee)
        hip_angle, knee_angle = planar_leg_ik(dx, -height, thigh, shin)
        q[index(f"{side}_hip")], q[index(f"{side}_knee")] = hip_angle, knee_angle
        if f"{side}_ankle" in model.names:
            q[index(f"{side}_ankle")] = -(hip_angle + knee_angle)
    return q
