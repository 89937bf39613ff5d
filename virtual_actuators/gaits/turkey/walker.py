"""Turkey walking (VMC 2001, section 5): Spring Turkey's level-ground gait.

The seed's algorithm, with its Table 1 state machine:

==================  ===============================  ===========================================
state               entered when                     virtual components
==================  ===============================  ===========================================
double_support      delay after left/right_support_2 granny walker, dogtrack bunny
left_support        body nearly over the left foot   granny walker, swing-leg linkage (right leg)
left_support_2      body away from the left foot     granny walker; right leg limp
right_support       body nearly over the right foot  granny walker, swing-leg linkage (left leg)
right_support_2     body away from the right foot    granny walker; left leg limp
==================  ===============================  ===========================================

The granny walker (spring-dampers on height and pitch) is on the body in every state. In double
support the body is held by both legs with matched hip torques (VMC eq. 12-14) and the dogtrack
bunny (a damper toward the desired speed) pushes it along x. In single support the stance foot is
a point contact, so the body actuator controls height and pitch while x is left free (VMC eq.
5-7). The swing-leg linkage mirrors the stance leg while lifting the foot, and sets it down
about a stride ahead; in the buffer states the swing leg is limp for a short delay so that it
falls to the ground (the turkey has no foot switches). Foot placement is never used for speed.
"""

from __future__ import annotations

import numpy as np

from ...components.walking import DogtrackBunny
from ...control import events
from ...control.state_machine import Context, StateMachine, Transition
from ...models.robot import Robot
from ...vocabulary.constraints import EqualTorque
from ..base import Gait, check_distribution
from ..planar import (
    SIDES,
    biped_states,
    biped_weight,
    declare_biped,
    granny_walker,
    lift_profile,
    other,
    smoothstep,
    swing_linkages,
)
from .parameters import TurkeyParameters


class TurkeyWalker(Gait):
    """Spring Turkey's turkey walking on level ground (VMC section 5, Table 1).

    Args:
        robot: ``spring_turkey`` (or any planar biped on a boom with frames ``body``,
            ``left_foot``, ``right_foot`` and joints ``SIDE_hip``, ``SIDE_knee``).
        parameters: Gait variables and component constants.
        initial: Initial state (the seed starts in single support and gives a small push).

    Raises:
        FrameNotFoundError: The robot lacks the frames above.
        JointNotFoundError: The robot lacks the joints above.

    """

    step_states = ("left_support", "right_support")

    def __init__(
        self,
        robot: Robot,
        parameters: TurkeyParameters | None = None,
        initial: str = "left_support",
    ) -> None:
        super().__init__(robot)
        self.parameters = p = parameters or TurkeyParameters()
        weight = biped_weight(robot, p.weight)  # [N]
        self.granny = granny_walker(p, p.height, weight)
        self.bunny = DogtrackBunny(p.speed, p.bunny_damping, limit=p.bunny_limit)
        self.swing = swing_linkages(p.swing_stiffness, p.swing_damping, ("x", "z"))
        self._declare_actuators()
        self.front = "left"  # foot ahead in double support
        self._swing_start = np.zeros(2)  # swing foot relative to the body at lift-off [m]
        self._progress_start = 0.0  # body x minus stance x at lift-off [m]
        self.ground = 0.0  # ground height estimate under the stance foot [m]
        self._finish(self._machine(initial))

    def _declare_actuators(self) -> None:
        """``double`` on both point feet (matched hip torques), ``SIDE_stance``, ``SIDE_swing``."""
        p = self.parameters
        qp = check_distribution(p.distribution)
        double = {
            "design": [EqualTorque("left_hip", "right_hip")],
            **({"friction": p.friction, "min_normal": p.min_normal_force} if qp else {}),
        }
        rule = {"method": "qp"} if qp else {"unilateral": {"z": p.min_normal_force}}
        declare_biped(self.controller, [self.granny, self.bunny], self.swing, "point", double, rule)

    def _machine(self, initial: str) -> StateMachine:
        """Table 1: double support, then single support and its buffer per side."""
        p = self.parameters
        limp = {f"{s}_support_2": (f"{other(s)}_hip", f"{other(s)}_knee") for s in SIDES}
        states = biped_states(
            (self._enter_double, self._update_double),
            (self._enter_single, self._update_single),
            limp,
        )
        transitions = []
        for side in SIDES:
            transitions += [
                Transition(
                    "double_support",
                    f"{side}_support",
                    self._front_is(side, events.ahead_of("body", f"{side}_foot", p.over_distance)),
                    f"body nearly over {side} foot",
                ),
                Transition(
                    f"{side}_support",
                    f"{side}_support_2",
                    events.ahead_of("body", f"{side}_foot", p.away_distance),
                    f"body away from {side} foot",
                ),
                Transition(
                    f"{side}_support_2",
                    "double_support",
                    events.after(p.buffer_delay),
                    f"delay after {side} support 2",
                ),
            ]
        return StateMachine(states, transitions, initial)

    # --- memory --------------------------------------------------------------------------------

    def memory(self) -> dict[str, float]:
        """What the gait carries from tick to tick besides its machine's state, as floats.

        The front foot (0 left, 1 right), the swing foot's start relative to the body and the
        progress at lift-off, the ground estimate, the granny walker's height set point, the
        bunny's start and set point, and each swing-leg linkage's set point (``SIDE_swing_x``,
        ``SIDE_swing_z``): what a native tick (`native.NativeTick`) keeps in the compiled core.
        """
        bunny = self.bunny
        memory = {
            "front": float(SIDES.index(self.front)),
            "swing_start_x": float(self._swing_start[0]),
            "swing_start_z": float(self._swing_start[1]),
            "progress_start": float(self._progress_start),
            "ground": float(self.ground),
            "granny_height": self.granny.height,
            "bunny_start_position": float(bunny.start_position),
            "bunny_start_time": float(bunny.start_time),
            "bunny_setpoint": bunny.setpoint.item(0),
        }
        for side in SIDES:
            x, z = self.swing[side].setpoint.tolist()
            memory[f"{side}_swing_x"], memory[f"{side}_swing_z"] = x, z
        return memory

    def restore(self, memory: dict[str, float]) -> None:
        """Take up a `memory` (its set points placed without moving their velocity set points).

        Raises:
            InvalidInputError: A set point that is not a finite number.

        """
        self.front = SIDES[int(memory["front"])]
        self._swing_start = np.array([memory["swing_start_x"], memory["swing_start_z"]])
        self._progress_start = memory["progress_start"]
        self.ground = memory["ground"]
        self.granny.height = memory["granny_height"]
        bunny = self.bunny
        bunny.start_position = memory["bunny_start_position"]
        bunny.start_time = memory["bunny_start_time"]
        bunny.setpoint = memory["bunny_setpoint"]
        for side in SIDES:
            self.swing[side].setpoint = (memory[f"{side}_swing_x"], memory[f"{side}_swing_z"])

    # --- events and state callbacks ------------------------------------------------------------

    def stance_side(self) -> str:
        """The stance leg in single support (the left one in double support)."""
        return self.state.split("_")[0] if self.state != "double_support" else "left"

    def _update_ground(self, context: Context, feet: tuple[str, ...]) -> None:
        heights = [context.frame_coordinate(foot, "z") for foot in feet]
        self.ground = sum(heights) / len(heights) - self.parameters.foot_radius
        self.granny.height = self.ground + self.parameters.height

    def _enter_double(self, context: Context) -> None:
        x_left = context.frame_position("left_foot")[0]
        x_right = context.frame_position("right_foot")[0]
        self.front = "left" if x_left > x_right else "right"

    def _update_double(self, context: Context) -> None:
        self._update_ground(context, _FEET)

    def _enter_single(self, context: Context) -> None:
        stance, swing, _, _ = _SINGLE[context.state]
        body = context.frame_position("body")
        self._swing_start = (context.frame_position(f"{swing}_foot") - body)[[0, 2]]
        self._progress_start = float(body[0] - context.frame_position(f"{stance}_foot")[0])

    def _update_single(self, context: Context) -> None:
        p = self.parameters
        _, swing, stance_foot, buffer = _SINGLE[context.state]
        self._update_ground(context, stance_foot)
        if buffer:
            return
        coordinate = context.frame_coordinate
        body_x, body_z = coordinate("body", "x"), coordinate("body", "z")
        progress = body_x - coordinate(stance_foot[0], "x")
        span = max(p.away_distance - self._progress_start, 1e-3)
        phase = min(max((progress - self._progress_start) / span, 0.0), 1.0)
        x_rel = self._swing_start[0] + (p.swing_reach - self._swing_start[0]) * smoothstep(
            1.6 * phase
        )
        foot_height = lift_profile(phase, p.lift_peak) * p.lift - p.touchdown_depth * phase
        z_rel = self.ground + p.foot_radius + foot_height - body_z
        self.swing[swing].place((x_rel, z_rel))


#: Both feet (double support's ground estimate).
_FEET = tuple(f"{side}_foot" for side in SIDES)
#: Per single-support state: stance side, swing side, ``(stance foot,)``, whether the buffer.
_SINGLE = {
    f"{side}_support{end}": (side, other(side), (f"{side}_foot",), end == "_2")
    for side in SIDES
    for end in ("", "_2")
}
