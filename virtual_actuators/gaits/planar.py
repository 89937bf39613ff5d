"""What the planar bipeds (turkey, flamingo) share, and the swing profiles every gait uses."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
import pinocchio as pin

from ..actuators import ParallelVirtualActuator, VirtualActuator
from ..components.walking import DogtrackBunny, GrannyWalker, SwingLegLinkage
from ..control.state_machine import Context, Event, State
from ..exceptions import InvalidInputError
from ..models.robot import Robot
from ..vocabulary.axes import resolve_frame, resolve_joint
from ..vocabulary.scalar import cos, logical_and, maximum, minimum, select, sin
from ..vocabulary.traced import Sym, lowerable
from .base import Gait, check_distribution

SIDES = ("left", "right")
PLANAR_AXES = ("x", "z", "ry")


def other(side: str) -> str:
    """The other leg."""
    return "right" if side == "left" else "left"


#: Per single-support state (``SIDE_support``, ``SIDE_support_2``): ``(stance side, swing side)``.
SINGLE = {f"{side}_support{end}": (side, other(side)) for side in SIDES for end in ("", "_2")}


def smoothstep(s: float) -> float:
    """``3 s^2 - 2 s^3`` on [0, 1], clipped: a set point that starts and ends at rest."""
    s = minimum(maximum(s, 0.0), 1.0)
    return s * s * (3.0 - 2.0 * s)


def lift_profile(phase: float, peak: float) -> float:
    """Swing foot height, 0 at both ends and 1 at ``peak``: a quarter sine up, a cosine down."""
    phase = minimum(maximum(phase, 0.0), 1.0)
    if isinstance(phase, Sym):  # both quarters, then the one the phase is in
        rising = sin(0.5 * math.pi * phase / peak)
        falling = cos(0.5 * math.pi * (phase - peak) / (1.0 - peak))
        return select(phase < peak, rising, falling)
    if phase < peak:
        return math.sin(0.5 * math.pi * phase / peak)
    return math.cos(0.5 * math.pi * (phase - peak) / (1.0 - peak))


def planar_leg_ik(dx: float, dz: float, thigh: float, shin: float) -> tuple[float, float]:
    """Hip and knee angles that put a planar two-link leg's end at ``(dx, dz)`` from the hip.

    Joints turn about +y, the knee bends positively (it points forward), the body is upright.

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
    ground: float = 0.0,
) -> np.ndarray:
    """A standing configuration of a planar biped on a boom at a given hip height.

    Args:
        robot: A planar biped with joints ``boom_x``, ``boom_z``, ``boom_pitch``,
            ``SIDE_hip``, ``SIDE_knee`` (and optionally ``SIDE_ankle``, set so the foot is flat).
        height: Hip height above the foot frames (``SIDE_foot``, ankle or point foot) [m].
        feet: Foot frame x relative to the hip, per side, e.g. ``{"left": 0.1, "right": -0.1}``.
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
        end = data.oMf[resolve_frame(model, f"{side}_foot", "foot")].translation
        thigh, shin = np.linalg.norm(knee - hip), np.linalg.norm(end - knee)
        hip_angle, knee_angle = planar_leg_ik(dx, -height, thigh, shin)
        q[index(f"{side}_hip")], q[index(f"{side}_knee")] = hip_angle, knee_angle
        if f"{side}_ankle" in model.names:
            q[index(f"{side}_ankle")] = -(hip_angle + knee_angle)
    return q


class PlanarBiped(Gait):
    """A planar biped's gait on `biped_states`, its front foot in ``memory.front`` (0: left)."""

    step_states = ("left_support", "right_support")

    def _components(self, height: float, axes: Sequence[str], **bunny: Any) -> None:
        """The granny walker, the dogtrack bunny and a ``SIDE_swing_linkage`` per side.

        The granny walker holds ``height`` and ``parameters.pitch``, the weight fed forward on z
        (``parameters.weight``, or the robot's mass times g when None [N]); ``bunny``: further
        arguments of the bunny; ``axes``: the swing linkages'.
        """
        p = self.parameters
        weight = self.robot.mass * 9.81 if p.weight is None else p.weight
        stiffness, damping = (p.stiffness_z, p.stiffness_pitch), (p.damping_z, p.damping_pitch)
        self.granny = GrannyWalker(
            height, stiffness=stiffness, damping=damping, pitch=p.pitch, weight=weight
        )
        self.bunny = DogtrackBunny(p.speed, p.bunny_damping, **bunny)
        gains = p.swing_stiffness, p.swing_damping
        self.swing = {
            side: SwingLegLinkage(*gains, axes=axes, name=f"{side}_swing_linkage") for side in SIDES
        }

    def _declare(
        self,
        contact: str,
        double: Mapping[str, Any],
        cones: Mapping[str, Any],
        partitioned: Mapping[str, Any],
        ankles: bool = False,
    ) -> None:
        """Add ``double`` (both feet, x yielding), ``SIDE_stance`` (x free) and ``SIDE_swing``.

        The double support carries the granny walker and the bunny, a stance the granny walker;
        ``contact`` is the feet's kind, ``double`` further arguments of the double support's
        actuator, ``cones`` more of them on the QP (``parameters.distribution``), ``partitioned``
        the arguments of its ``controller.add`` off the QP; ``ankles``: limp in support.

        Raises:
            InvalidInputError: ``parameters.distribution`` is not one of `DISTRIBUTIONS`.
            FrameNotFoundError: The robot lacks ``body`` or ``SIDE_foot``.
            JointNotFoundError: The robot lacks a joint named above.
        """
        robot, controller, swing = self.robot, self.controller, self.swing
        qp = check_distribution(self.parameters.distribution)
        double, rule = ({**double, **cones}, {"method": "qp"}) if qp else (double, partitioned)
        body = [self.granny, self.bunny]

        def support(sides: Sequence[str]) -> ParallelVirtualActuator:
            feet = [f"{side}_foot" for side in sides]
            limp = {"unactuated": [f"{side}_ankle" for side in sides]} if ankles else {}
            extra = double if len(sides) == 2 else {}
            return ParallelVirtualActuator(
                robot, "body", feet, "world", PLANAR_AXES, contact=contact, **limp, **extra
            )

        controller.add("double", support(SIDES), body, yield_axes=("x",), **rule)
        for side in SIDES:
            controller.add(f"{side}_stance", support((side,)), [body[0]], free=("x",))
            axes = swing[side].axes
            actuator = VirtualActuator(robot, f"{side}_foot", "body", "world", axes)
            controller.add(f"{side}_swing", actuator, [swing[side]])

    def _front_is(self, side: str, event: Event) -> Event:
        """``event``, but only while ``side`` is the front foot (``self.memory.front``: 0 left)."""
        index = float(SIDES.index(side))

        @lowerable
        def front_is(context: Context) -> object:
            if isinstance(context, Context):
                return self.memory.front == index and event(context)
            return logical_and(self.memory.front == index, context.event(event))

        return front_is


Hook = Callable[[Context], None]


def biped_states(
    double: tuple[Hook, Hook],
    single: tuple[Hook, Hook],
    limp: Mapping[str, tuple[str, ...]],
    landing_swings: bool = False,
) -> list[State]:
    """``double_support``, then ``SIDE_support`` and ``SIDE_support_2`` per side.

    Args:
        double: The double support's ``(on_enter, on_update)``.
        single: ``SIDE_support``'s ``(on_enter, on_update)``; ``SIDE_support_2`` continues the
            same swing (``on_update`` only).
        limp: Limp joints per state name (a state not listed has none).
        landing_swings: ``SIDE_support_2`` keeps the swing leg's linkage on.

    Returns:
        The five states, in that order.
    """
    enter, update = single
    states = [_state("double_support", ("double",), SIDES, limp, *double)]
    for side in SIDES:
        stance, swing = f"{side}_stance", f"{other(side)}_swing"
        landing = (stance, swing) if landing_swings else (stance,)
        states += [
            _state(f"{side}_support", (stance, swing), (side,), limp, enter, update),
            _state(f"{side}_support_2", landing, (side,), limp, None, update),
        ]
    return states


def _state(
    name: str,
    active: tuple[str, ...],
    sides: Sequence[str],
    limp: Mapping[str, tuple[str, ...]],
    enter: Hook | None,
    update: Hook,
) -> State:
    """State ``name`` on the feet of ``sides``, limp on ``limp.get(name, ())``."""
    feet = tuple(f"{side}_foot" for side in sides)
    return State(name, active, feet, limp=limp.get(name, ()), on_enter=enter, on_update=update)
