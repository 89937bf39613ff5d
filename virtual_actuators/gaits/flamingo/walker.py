"""Blind walking over unknown slopes (VMC 2001, section 6): Spring Flamingo.

The robot knows nothing of the terrain: heel and toe switches and the joint angles give it the
global slope at every touchdown (the bipeds tutorial describes the gait).
"""

from __future__ import annotations

import numpy as np

from ...components.walking import DogtrackBunny
from ...control import events
from ...control.plan.memory import Memory
from ...control.state_machine import Context, StateMachine, Transition
from ...models.robot import Robot
from ...vocabulary.constraints import EqualTorque
from ...vocabulary.scalar import atan2, clip, logical_and, logical_or, maximum, minimum, select, tan
from ...vocabulary.traced import lowerable
from ..base import check_distribution
from ..planar import (
    PLANAR_AXES,
    SIDES,
    SINGLE,
    PlanarBiped,
    biped_states,
    granny_walker,
    lift_profile,
    other,
    planar_standing_configuration,
    smoothstep,
    swing_linkages,
)
from .parameters import FlamingoParameters


class FlamingoWalker(PlanarBiped):
    """Spring Flamingo's blind slope walking (VMC section 6).

    States: ``double_support``; ``SIDE_support`` (single support on SIDE, the other leg swings);
    ``SIDE_support_2`` (landing: a switch of the swing foot closed, its ankle goes limp).

    Args:
        robot: ``spring_flamingo`` (frames ``body``, ``SIDE_foot``, ``SIDE_heel``, ``SIDE_toe``;
            joints ``SIDE_hip``, ``SIDE_knee``, ``SIDE_ankle``).
        parameters: Gait variables and component constants.
        initial: Initial state.

    Raises:
        FrameNotFoundError: The robot lacks the frames above.
        JointNotFoundError: The robot lacks the joints above.
    """

    contact_frames = ("left_heel", "left_toe", "right_heel", "right_toe")
    foot_contacts = {f"{side}_foot": (f"{side}_heel", f"{side}_toe") for side in SIDES}

    def __init__(
        self,
        robot: Robot,
        parameters: FlamingoParameters | None = None,
        initial: str = "double_support",
    ) -> None:
        super().__init__(robot)
        self.parameters = p = parameters or FlamingoParameters()
        self.memory = Memory(
            slope=0.0, slope_origin=(0.0, 0.0), hip_height=p.hip_height(0.0), height_time=0.0,
            front=0.0, swing_start=(0.0, 0.0), swing_target_x=0.0, swing_started=0.0,
            swing_hip_x=0.0,
        )  # fmt: skip
        self.granny = granny_walker(p, self.memory.hip_height, robot)
        self.granny.limit = ((1.0 - p.min_lift) * self.granny.force[0], np.inf)  # [N]
        self.bunny = DogtrackBunny(p.speed, p.bunny_damping)
        self.swing = swing_linkages(p.swing_stiffness, p.swing_damping, PLANAR_AXES)
        self._declare_actuators()
        self._finish(self._machine(initial))

    @property
    def slope(self) -> float:
        """The global slope estimate [rad]."""
        return self.memory.slope

    def _declare_actuators(self) -> None:
        """``double`` on both flat feet over limp ankles, ``SIDE_stance``, ``SIDE_swing``."""
        p = self.parameters
        qp = check_distribution(p.distribution)
        cones = {
            "friction": p.friction if p.qp_friction is None else p.qp_friction,
            "min_normal": p.min_normal_force if p.qp_min_normal_force is None
            else p.qp_min_normal_force,
            "normals": "frames" if p.sole_normals else None,
        }  # fmt: skip
        double = {
            "design": [EqualTorque("left_hip", "right_hip")] if p.equal_hip_torques else [],
            **(cones if qp else {"normals": cones["normals"]}),  # the controller's cones too
        }
        limits = {"friction": p.friction, "min_normal": p.min_normal_force}
        rule = {"method": "qp"} if qp else limits
        self._declare("flat", double, rule, ankles=True)

    def _machine(self, initial: str) -> StateMachine:
        """Double support, single support and its landing per side (section 6.2)."""
        p = self.parameters
        ankles = tuple(f"{side}_ankle" for side in SIDES)
        limp = {"double_support": ankles}
        for side in SIDES:
            limp |= {f"{side}_support": (f"{side}_ankle",), f"{side}_support_2": ankles}
        states = biped_states(
            (self._enter_double, self._update_height),
            (self._enter_single, self._update_single),
            limp,
            landing_swings=True,
        )
        transitions = []
        for side in SIDES:
            single, landing, swing = f"{side}_support", f"{side}_support_2", other(side)
            switches = (f"{swing}_heel", f"{swing}_toe")
            down, early = events.contact(*switches), events.contact(*switches, require_all=False)
            ahead = events.ahead_of(f"{swing}_foot", f"{side}_foot", 0.0)
            hip_over = events.ahead_of("body", f"{side}_foot", -p.transition_distance)
            start = self._front_is(side, events.all_of(hip_over, self._can_vault(side)))
            landed = events.all_of(down, events.after(0.5 * p.swing_time), ahead)
            lands_early = events.all_of(early, events.after(0.3 * p.swing_time), ahead)
            transitions += [
                Transition("double_support", single, start, f"hip within l_t of the {side} ankle"),
                Transition(single, "double_support", landed, f"{swing} heel and toe down"),
                Transition(single, landing, lands_early, f"{swing} foot lands early"),
                Transition(landing, "double_support", down, f"{swing} heel and toe down"),
            ]
        return StateMachine(states, transitions, initial)

    def initial_configuration(self, stance: float = 0.15) -> np.ndarray:
        """Standing at the level-ground hip height, left ankle ``stance`` ahead, right behind."""
        return planar_standing_configuration(
            self.robot, self.parameters.hip_height(0.0), {"left": stance, "right": -stance}
        )

    def slope_height(self, x: float) -> float:
        """Height of the global slope line at ``x`` [m] (a float, or traced)."""
        origin_x, origin_z = self.memory.slope_origin
        return origin_z + (x - origin_x) * tan(self.memory.slope)

    def _set_slope(self, back: tuple, front: tuple, when: object = 1.0) -> None:
        """The global slope through two ankles ``(x, y, z)`` if ``when`` (kept if one above)."""
        memory = self.memory
        dx = front[0] - back[0]
        new = logical_and(when, abs(dx) >= 1e-3)
        slope = clip(atan2(front[2] - back[2], dx), -0.6, 0.6)
        ox, oz = memory.slope_origin
        memory.hip_height = select(new, self.parameters.hip_height(slope), memory.hip_height)
        memory.slope = select(new, slope, memory.slope)
        memory.slope_origin = (select(new, back[0], ox), select(new, back[2], oz))

    @lowerable
    def _update_height(self, context: Context) -> None:
        p, memory = self.parameters, self.memory
        if context.state != "double_support" and p.level_single_support:
            self.granny.velocity_setpoint = (0.0, 0.0)
            memory.height_time = context.time
            return
        target = self.slope_height(context.frame_coordinate("body", "x")) + memory.hip_height
        step = p.height_rate * maximum(context.time - memory.height_time, 0.0)
        current = self.granny.height
        self.granny.height = current + minimum(maximum(target - current, -step), step)
        memory.height_time = context.time
        xdot = context.frame_velocity("body")[0]
        self.granny.velocity_setpoint = (xdot * tan(memory.slope), 0.0)

    def _can_vault(self, side: str) -> events.Event:
        """The hip vaults over ``side``'s ankle at ``sqrt(xdot^2 - (g / h) d^2) >= min_speed``."""
        foot, p = f"{side}_foot", self.parameters

        @lowerable
        def event(context: Context) -> object:
            body_x, _, body_z = context.frame_position("body")
            ankle_x, _, ankle_z = context.frame_position(foot)
            xdot = context.frame_velocity("body")[0]
            behind = ankle_x - body_x
            height = maximum(body_z - ankle_z, 0.3)
            ahead = maximum(behind, 0.0)
            vault = xdot * xdot - 9.81 / height * (ahead * ahead)
            fast = logical_and(xdot > 0.0, vault >= p.min_speed * p.min_speed)
            if p.max_overspeed is None:
                return fast
            most = p.speed + p.max_overspeed
            return logical_and(fast, logical_or(behind <= 0.0, vault <= most * most))

        return event

    @lowerable
    def _enter_double(self, context: Context) -> None:
        left = tuple(context.frame_position("left_foot"))
        right = tuple(context.frame_position("right_foot"))
        left_ahead = left[0] > right[0]
        self.memory.front = select(left_ahead, 0.0, 1.0)
        pairs = list(zip(left, right, strict=True))
        back = tuple(select(left_ahead, b, a) for a, b in pairs)
        front = tuple(select(left_ahead, a, b) for a, b in pairs)
        self._set_slope(back, front)
        self._update_height(context)

    @lowerable
    def _enter_single(self, context: Context) -> None:
        stance, swing = SINGLE[context.state]
        memory, p = self.memory, self.parameters
        memory.swing_started = context.time  # support_2 continues the same swing
        ankle_x, _, ankle_z = context.frame_position(f"{swing}_foot")
        stance_x, _, stance_z = context.frame_position(f"{stance}_foot")
        memory.swing_start = (ankle_x, ankle_z)
        memory.swing_hip_x = context.frame_coordinate("body", "x")
        memory.swing_target_x = stance_x + p.step_length
        memory.slope_origin = (stance_x, stance_z)
        if p.stance_slope:
            sole_slope = -context.frame_pitch(f"{stance}_foot")  # toe up: positive [rad]
            steeper = sole_slope < memory.slope
            slope = maximum(sole_slope, -0.6)
            memory.hip_height = select(steeper, p.hip_height(slope), memory.hip_height)
            memory.slope = select(steeper, slope, memory.slope)

    @lowerable
    def _update_single(self, context: Context) -> None:
        p, memory = self.parameters, self.memory
        stance, swing = SINGLE[context.state]
        self._update_height(context)
        coordinate = context.frame_coordinate
        body_x, body_z = coordinate("body", "x"), coordinate("body", "z")
        start_x, start_z = memory.swing_start
        elapsed = context.time - memory.swing_started
        phase = elapsed / p.swing_time
        reach = phase
        if p.swing_hip_travel is not None:
            reach = minimum(phase, (body_x - memory.swing_hip_x) / p.swing_hip_travel)
        target_x = memory.swing_target_x
        if p.step_gain:
            # longer steps when too fast, shorter when too slow (Raibert-like)
            xdot = context.frame_velocity("body")[0]
            target_x = target_x + minimum(
                maximum(p.step_gain * (xdot - p.speed), -0.4 * p.step_length),
                0.6 * p.step_length,
            )
        x_target = start_x + (target_x - start_x) * (smoothstep(reach))
        surface = self.slope_height(x_target)
        start_height = start_z - self.slope_height(start_x)
        lift = p.lift * lift_profile(phase, p.lift_peak)
        swinging = surface + (1.0 - smoothstep(phase)) * start_height + lift
        # swing time expired: push down through the virtual surface (Fig. 13)
        late = phase > 1.0
        z_target = select(late, surface - p.push_speed * (elapsed - p.swing_time), swinging)
        ankle = tuple(context.frame_position(f"{swing}_foot"))
        below = logical_and(late, ankle[2] < self.slope_height(ankle[0]))
        self._set_slope(tuple(context.frame_position(f"{stance}_foot")), ankle, below)
        # the foot parallel to the global slope: its pitch relative to the body
        body_pitch = context.frame_pitch("body")
        self.swing[swing].place((x_target - body_x, z_target - body_z, -memory.slope - body_pitch))
