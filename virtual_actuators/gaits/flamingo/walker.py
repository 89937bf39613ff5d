"""Blind walking over unknown slopes (VMC 2001, section 6): Spring Flamingo.

The robot knows nothing of the terrain: heel and toe switches and the joint angles give it the
global slope at every touchdown (the bipeds tutorial describes the gait).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...control import events
from ...control.plan.memory import Memory
from ...control.state_machine import Context, StateMachine, Transition
from ...models.robot import Robot
from ...vocabulary.constraints import EqualTorque
from ...vocabulary.scalar import atan2, clip, logical_and, logical_or, maximum, minimum, select, tan
from ...vocabulary.traced import lowerable
from ..planar import (
    PLANAR_AXES,
    SIDES,
    SINGLE,
    PlanarBiped,
    biped_states,
    lift_profile,
    other,
    planar_standing_configuration,
    smoothstep,
)


@dataclass
class FlamingoParameters:
    """Gait variables (the seed's Table 2) and component constants, SI units.

    The defaults are the seed's except ``stance_slope``, ``swing_time``, ``push_speed`` and
    ``step_length``, which hold 0.3 to 0.5 m/s on both profiles; `seed` gives the seed's set.

    Attributes:
        speed: Desired horizontal hip speed ``xdot_d`` [m/s].
        pitch: Desired body pitch ``theta_d`` [rad].
        step_length: Desired step length ``s_l`` [m].
        transition_distance: ``l_t``: double support ends this far behind the front ankle [m].
        lift: Swing lift ``h_l`` above the global slope [m].
        k_height: Fraction of the height limit used as the hip height set point.
        leg_length: ``l1 + l2``, hip to ankle [m].
        stiffness_z, damping_z: Granny walker on height [N/m], [N s/m].
        min_lift: The granny walker's z force stays above this fraction of the weight (its
            spring-damper part saturated at ``(1 - min_lift) * weight`` both ways).
        stiffness_pitch, damping_pitch: Granny walker on pitch [N m/rad], [N m s/rad].
        bunny_damping: ``b_x`` [N s/m] (Table 2's "2" read as 200).
        level_single_support: Hold the height set point in single support (climb in double
            support) instead of following the global slope.
        height_rate: Fastest change of the height set point [m/s].
        equal_hip_torques: Double support with matched hip torques (eq. 12); False: the
            minimum-norm distribution.
        min_normal_force: Least force of each foot in double support, normal to its sole [N].
        friction: Friction coefficient of the feet's cones about their soles' normals.
        swing_time: Planned duration of the swing [s].
        lift_peak: Phase of the swing (0 to 1) at which the foot is highest above its path.
        swing_stiffness: Swing linkage (x, z, pitch) [N/m, N/m, N m/rad].
        swing_damping: Swing linkage (x, z, pitch) [N s/m, N s/m, N m s/rad].
        min_speed: Double support ends only if the hip, vaulting over the front ankle as a
            linear inverted pendulum (``xdot^2 - g / h * d^2``), would pass it this fast [m/s].
        max_overspeed: While the hip is behind the front ankle, double support also waits
            until that vault speed is at most ``speed`` plus this [m/s]; None: no bound.
        step_gain: The touchdown target moves ``step_gain * (xdot - speed)`` beyond the step
            length (clipped to -40 % / +60 % of it) [s].
        swing_hip_travel: The swing's progress is at most the hip's displacement since
            lift-off over this distance [m] (None: time only).
        push_speed: Speed of the swing set point going down after the swing time [m/s].
        weight: Feed-forward on z [N]; None: total mass times g.
        stance_slope: At lift-off, take the stance sole's slope as the global slope when it
            is lower; False: the seed's global slope only.
        distribution: ``"partitioned"`` (minimum-norm, the bunny's force scaled into the
            cones) or ``"qp"`` (cones and least normal force as inequalities; x gives way).
        sole_normals: The cones' normals are the feet frames' z axes; False: world z.
        qp_min_normal_force: ``distribution="qp"``: each foot's least normal force [N] (None:
            ``min_normal_force``).
        qp_friction: ``distribution="qp"``: the QP's cone coefficient (None: ``friction``).
    """

    speed: float = 0.4
    pitch: float = 0.0
    step_length: float = 0.32
    transition_distance: float = 0.08
    lift: float = 0.07
    k_height: float = 0.85
    leg_length: float = 0.84
    stiffness_z: float = 5000.0
    damping_z: float = 200.0
    min_lift: float = 0.3
    stiffness_pitch: float = 500.0
    damping_pitch: float = 20.0
    bunny_damping: float = 200.0
    equal_hip_torques: bool = False
    level_single_support: bool = False
    height_rate: float = 0.3
    min_normal_force: float = 10.0
    friction: float = 0.6
    swing_time: float = 0.34
    lift_peak: float = 0.35
    swing_stiffness: tuple[float, float, float] = (600.0, 800.0, 20.0)
    swing_damping: tuple[float, float, float] = (30.0, 40.0, 1.0)
    min_speed: float = 0.1
    swing_hip_travel: float | None = 0.12
    max_overspeed: float | None = 0.05
    step_gain: float = 0.5
    push_speed: float = 0.8
    weight: float | None = None
    stance_slope: bool = True
    distribution: str = "partitioned"
    sole_normals: bool = True
    qp_min_normal_force: float | None = 25.0
    qp_friction: float | None = 0.45

    @classmethod
    def seed(cls, **changes: object) -> FlamingoParameters:
        """The seed's Table 2 values and its global slope only (0.28 m steps, 0.4 s swings)."""
        seed = {"step_length": 0.28, "swing_time": 0.4, "push_speed": 0.3, "stance_slope": False}
        return cls(**{**seed, **changes})

    def hip_height(self, slope: float) -> float:
        """Hip height set point ``k_height * h_limit`` above the global slope [m].

        ``h_limit`` is the smaller of eq. 15, the back leg at the transition plane ``r = s_l -
        l_t`` behind the hip: ``sqrt(L^2 - r^2) - r tan(beta)``, and eq. 16, the swing leg
        touching down ``r1 = s_l / 2`` ahead of the hip: ``sqrt(L^2 - r1^2) + r1 tan(beta)``.
        """
        length = self.leg_length
        r = self.step_length - self.transition_distance
        r1 = 0.5 * self.step_length
        upslope = math.sqrt(length**2 - r**2) - r * tan(slope)
        downslope = math.sqrt(length**2 - r1**2) + r1 * tan(slope)
        return self.k_height * minimum(upslope, downslope)


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
        self._components(self.memory.hip_height, PLANAR_AXES)
        self.granny.limit = ((1.0 - p.min_lift) * self.granny.force[0], np.inf)  # [N]
        double = {  # flat feet over limp ankles
            "design": [EqualTorque("left_hip", "right_hip")] if p.equal_hip_torques else [],
            "normals": "frames" if p.sole_normals else None,
        }
        cones = {
            "friction": p.friction if p.qp_friction is None else p.qp_friction,
            "min_normal": p.min_normal_force if p.qp_min_normal_force is None
            else p.qp_min_normal_force,
        }  # fmt: skip
        limits = {"friction": p.friction, "min_normal": p.min_normal_force}
        self._declare("flat", double, cones, limits, ankles=True)
        self._finish(self._machine(initial))

    @property
    def slope(self) -> float:
        """The global slope estimate [rad]."""
        return self.memory.slope

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
        self.granny.height = current + clip(target - current, -step, step)
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
            step = p.step_length
            target_x = target_x + clip(p.step_gain * (xdot - p.speed), -0.4 * step, 0.6 * step)
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
