"""Turkey walking (VMC 2001, section 5): Spring Turkey's level-ground gait (Table 1's states)."""

from __future__ import annotations

from dataclasses import dataclass

from ...control import events
from ...control.plan.memory import Memory
from ...control.state_machine import Context, StateMachine, Transition
from ...models.robot import Robot
from ...vocabulary.constraints import EqualTorque
from ...vocabulary.scalar import maximum, minimum, select
from ...vocabulary.traced import lowerable
from ..planar import (
    SIDES,
    SINGLE,
    PlanarBiped,
    biped_states,
    lift_profile,
    other,
    smoothstep,
)


@dataclass
class TurkeyParameters:
    """Gait variables and virtual component constants of turkey walking (SI units).

    Attributes:
        speed: Dogtrack bunny speed [m/s].
        height: Granny walker height set point, hip above the ground [m].
        pitch: Granny walker pitch set point [rad].
        stiffness_z: [N/m].
        damping_z: [N s/m].
        stiffness_pitch: [N m/rad].
        damping_pitch: [N m s/rad].
        bunny_damping: Dogtrack bunny damper [N s/m].
        bunny_limit: Largest bunny force [N].
        min_normal_force: Least normal force of each foot in double support [N].
        weight: Feed-forward on z [N]; None: total mass times g.
        over_distance: "Body nearly over the foot": body x minus front foot x above this [m].
        away_distance: "Body away from the stance foot": body x minus stance foot x above this
            [m].
        swing_reach: Swing foot x relative to the body at the end of the swing [m].
        lift: Swing foot lift above the ground [m].
        lift_peak: Phase of the swing (0 to 1) at which the foot is highest.
        swing_stiffness: Swing-leg linkage springs (x, z) [N/m].
        swing_damping: Swing-leg linkage dampers (x, z) [N s/m].
        touchdown_depth: How far below the ground the swing set point ends [m].
        buffer_delay: Time the swing leg stays limp in the buffer states [s].
        foot_radius: Height of the foot frame above the ground when in contact [m].
        distribution: ``"partitioned"`` (the seed's matched hip torques) or ``"qp"`` (the same
            with friction pyramids and least normal forces as inequalities).
        friction: Friction coefficient assumed by ``distribution="qp"``.
    """

    speed: float = 0.5
    height: float = 0.54
    pitch: float = 0.0
    stiffness_z: float = 1500.0
    damping_z: float = 150.0
    stiffness_pitch: float = 200.0
    damping_pitch: float = 20.0
    bunny_damping: float = 80.0
    bunny_limit: float = 60.0
    min_normal_force: float = 10.0
    weight: float | None = None
    over_distance: float = -0.075
    away_distance: float = 0.075
    swing_reach: float = 0.19
    lift: float = 0.05
    lift_peak: float = 0.35
    swing_stiffness: tuple[float, float] = (400.0, 600.0)
    swing_damping: tuple[float, float] = (20.0, 25.0)
    touchdown_depth: float = 0.02
    buffer_delay: float = 0.04
    foot_radius: float = 0.02
    distribution: str = "partitioned"
    friction: float = 0.6


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
        self._components(p.height, ("x", "z"), limit=p.bunny_limit)
        cones = {"friction": p.friction, "min_normal": p.min_normal_force}
        hips = {"design": [EqualTorque("left_hip", "right_hip")]}  # point feet, matched hip torques
        self._declare("point", hips, cones, {"unilateral": {"z": p.min_normal_force}})
        self.memory = Memory(front=0.0, swing_start=(0.0, 0.0), progress_start=0.0, ground=0.0)
        self._finish(self._machine(initial))

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
        self.memory.ground = ground = sum(heights) / len(heights) - self.parameters.foot_radius
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
        self.memory.swing_start = (
            coordinate(f"{swing}_foot", "x") - body_x, coordinate(f"{swing}_foot", "z") - body_z
        )
        self.memory.progress_start = body_x - coordinate(f"{stance}_foot", "x")

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
