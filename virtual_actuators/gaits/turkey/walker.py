"""Turkey walking (VMC 2001, section 5): Spring Turkey's level-ground gait (Table 1's states)."""

from __future__ import annotations

from ...components.walking import DogtrackBunny
from ...control import events
from ...control.plan.memory import Memory
from ...control.state_machine import Context, StateMachine, Transition
from ...models.robot import Robot
from ...vocabulary.constraints import EqualTorque
from ...vocabulary.scalar import maximum, minimum, select
from ...vocabulary.traced import lowerable
from ..base import check_distribution
from ..planar import (
    SIDES,
    SINGLE,
    PlanarBiped,
    biped_states,
    granny_walker,
    lift_profile,
    other,
    smoothstep,
    swing_linkages,
)
from .parameters import TurkeyParameters


class TurkeyWalker(PlanarBiped):
    """Spring Turkey's turkey walking on level ground (VMC section 5, Table 1).

    Args:
        robot: ``spring_turkey`` (or any planar biped on a boom with frames ``body``,
            ``left_foot``, ``right_foot`` and joints ``SIDE_hip``, ``SIDE_knee``).
        parameters: Gait variables and component constants.
        initial: Initial state (the seed starts in single support).

    Raises:
        FrameNotFoundError: The robot lacks the frames above.
        JointNotFoundError: The robot lacks the joints above.
    """

    def __init__(
        self,
        robot: Robot,
        parameters: TurkeyParameters | None = None,
        initial: str = "left_support",
    ) -> None:
        super().__init__(robot)
        self.parameters = p = parameters or TurkeyParameters()
        self.granny = granny_walker(p, p.height, robot)
        self.bunny = DogtrackBunny(p.speed, p.bunny_damping, limit=p.bunny_limit)
        self.swing = swing_linkages(p.swing_stiffness, p.swing_damping, ("x", "z"))
        self._declare_actuators()
        self.memory = Memory(front=0.0, swing_start=(0.0, 0.0), progress_start=0.0, ground=0.0)
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
        self._declare("point", double, rule)

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
            single, buffer, foot = f"{side}_support", f"{side}_support_2", f"{side}_foot"
            over = self._front_is(side, events.ahead_of("body", foot, p.over_distance))
            away = events.ahead_of("body", foot, p.away_distance)
            delay = events.after(p.buffer_delay)
            transitions += [
                Transition("double_support", single, over, f"body nearly over {side} foot"),
                Transition(single, buffer, away, f"body away from {side} foot"),
                Transition(buffer, "double_support", delay, f"delay after {side} support 2"),
            ]
        return StateMachine(states, transitions, initial)

    def _update_ground(self, context: Context, feet: tuple[str, ...]) -> None:
        heights = [context.frame_coordinate(foot, "z") for foot in feet]
        memory = self.memory
        memory.ground = ground = sum(heights) / len(heights) - self.parameters.foot_radius
        self.granny.height = ground + self.parameters.height

    @lowerable
    def _enter_double(self, context: Context) -> None:
        x_left = context.frame_coordinate("left_foot", "x")
        x_right = context.frame_coordinate("right_foot", "x")
        self.memory.front = select(x_left > x_right, 0.0, 1.0)

    @lowerable
    def _update_double(self, context: Context) -> None:
        self._update_ground(context, ("left_foot", "right_foot"))

    @lowerable
    def _enter_single(self, context: Context) -> None:
        stance, swing = SINGLE[context.state]
        coordinate = context.frame_coordinate
        body_x, body_z = coordinate("body", "x"), coordinate("body", "z")
        memory = self.memory
        memory.swing_start = (
            coordinate(f"{swing}_foot", "x") - body_x, coordinate(f"{swing}_foot", "z") - body_z
        )
        memory.progress_start = body_x - coordinate(f"{stance}_foot", "x")

    @lowerable
    def _update_single(self, context: Context) -> None:
        p = self.parameters
        stance, swing = SINGLE[context.state]
        self._update_ground(context, (f"{stance}_foot",))
        if context.state.endswith("_2"):  # the buffer: the swing leg limp
            return
        memory = self.memory
        coordinate = context.frame_coordinate
        body_x, body_z = coordinate("body", "x"), coordinate("body", "z")
        progress = body_x - coordinate(f"{stance}_foot", "x")
        start, (start_x, _) = memory.progress_start, memory.swing_start
        span = maximum(p.away_distance - start, 1e-3)
        phase = minimum(maximum((progress - start) / span, 0.0), 1.0)
        x_rel = start_x + (p.swing_reach - start_x) * smoothstep(1.6 * phase)
        foot_height = lift_profile(phase, p.lift_peak) * p.lift - p.touchdown_depth * phase
        z_rel = memory.ground + p.foot_radius + foot_height - body_z
        self.swing[swing].place((x_rel, z_rel))
