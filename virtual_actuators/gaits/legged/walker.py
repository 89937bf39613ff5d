"""A gait for any robot with two or more legs: the hexapod's design (VAC 1996, section 4).

States ``stand``, then ``swing_k`` and ``double_k`` per swing group of the pattern.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from ...actuators import ParallelVirtualActuator, VirtualActuator
from ...components.gains import joint_gains
from ...components.gravity import GravityCompensation
from ...components.posture import Posture
from ...components.springs import SpringDamper
from ...control import events
from ...control.plan.memory import Memory
from ...control.state_machine import State, StateMachine, Transition
from ...exceptions import InvalidInputError
from ...kinematics.snapshot import Snapshot
from ...models.feet import find_feet
from ...models.robot import Robot
from ...models.standing import standing_pose, upper_joints
from ..base import Gait
from ..guidance import checked_command
from .body import BodyModel
from .hooks import WalkerHooks
from .parameters import GRAVITY, LeggedParameters, derive_gains, leg_mass
from .patterns import GaitPattern, named_pattern

#: Time constant of the low-pass filter on the swing set points' velocity [s].
RATE_FILTER = 0.02


class LeggedWalker(WalkerHooks, Gait):
    """Walk any legged robot with a pattern, from a velocity and yaw-rate command.

    Args:
        robot: A floating-base robot.
        feet: Foot frames (default: found on the robot, see ``va.find_feet``).
        pattern: ``"trot"``, ``"pace"``, ``"walk"``, ``"tripod"`` or a [`GaitPattern`][].
        parameters: Choices and dimensionless gains (default [`LeggedParameters`][]).
        body: The body frame (default: the floating base's).

    Attributes:
        feet: The foot frames.
        groups: Its swing groups, in cycle order.
        gains: The physical gains as derived (`LeggedGains`), before the control rate's bound.
        tick_rates: Each state's per-tick rate of its derived gains before that bound.
        nominal: ``(len(feet), 2)`` the stance relative to the centre of mass, heading frame.
        stand_height: The body's origin above its feet when standing [m].
        swing_time: [s].
        memory: What the walker carries from tick to tick (a [`Memory`][virtual_actuators.Memory]).

    Raises:
        InvalidInputError: A robot without a floating base, fewer than two feet, or a body
            frame not on the floating base.
        FrameNotFoundError: A foot or body frame the robot lacks (or no feet found).
    """

    def __init__(
        self,
        robot: Robot,
        feet: Sequence[str] | None = None,
        pattern: str | GaitPattern = "trot",
        parameters: LeggedParameters | None = None,
        body: str | None = None,
    ) -> None:
        super().__init__(robot)
        self.parameters = p = parameters or LeggedParameters()
        if not robot.floating_base:
            raise InvalidInputError(f"LeggedWalker: robot {robot.name!r} has no floating base.")
        found = find_feet(robot) if feet is None or body is None else None
        self.feet = tuple(found.feet if feet is None else feet)
        self.body_frame = found.body if body is None else body
        if len(self.feet) < 2:
            raise InvalidInputError(f"LeggedWalker needs two or more feet, got {self.feet}.")
        self.contact_frames = self.feet
        self._stance(p)
        if isinstance(pattern, str):
            pattern = named_pattern(pattern, self.feet, self.nominal)
        if set(pattern.feet) != set(self.feet):
            raise InvalidInputError(
                f"LeggedWalker: the pattern's feet {pattern.feet} are not the walker's {self.feet}."
            )
        self.groups = pattern.groups()
        self.nominal = self.nominal * np.array((1.0, pattern.width))
        scale = self.gains.time_scale
        self.swing_time = (pattern.swing_time if p.swing_time is None else p.swing_time) * scale
        self.double_time = p.double_support_time * scale
        stance_time = len(self.groups) * (self.swing_time + self.double_time) - self.swing_time
        #: per foot k ``foot_k``: its lift-off point, last set point and its velocity [m, m/s]
        self.memory = Memory(
            command=(0.0, 0.0), yaw_command=0.0, setpoint=(0.0, 0.0), error_integral=(0.0, 0.0),
            yaw_integral=0.0, last_time=0.0, started=0.0, swung_at=0.0,
            **{f"foot_{k}": (0.0,) * 9 for k in range(len(self.feet))},
        )  # fmt: skip
        self._declare()
        g = self.gains
        self._shape = (self.swing_time, stance_time, g.time_scale * p.placement_gain,
                       p.reach * g.height, p.lift * g.height, p.lift_peak,
                       p.touchdown_depth * g.height, RATE_FILTER)  # fmt: skip
        self._nominal = tuple(tuple(row) for row in self.nominal.tolist())
        self.step_states = tuple(f"swing_{k}" for k in range(len(self.groups)))
        self._swinging = dict(zip(self.step_states, self.groups, strict=True))
        self._finish(self._machine())
        self._support = {state.name: tuple(state.support) for state in self.machine.states}
        self.tick_rates = dict(
            zip(self.machine.names, self._bound_gains(p.control_rate), strict=True)
        )

    def _stance(self, p: LeggedParameters) -> None:
        """Nominal stance, standing height and gains from the standing pose."""
        robot, model = self.robot, self.robot.model
        frame = model.frames[model.getFrameId(self.body_frame)]
        turn = frame.placement.rotation
        self._to_body = None if np.array_equal(turn, np.eye(3)) else turn.T.copy()
        if frame.parentJoint != 1:
            raise InvalidInputError(
                f"LeggedWalker: the body frame {self.body_frame!r} must be on the floating base."
            )
        q0 = self.initial_configuration()
        snapshot = Snapshot(robot, q0)
        rotation = snapshot.frame_rotation(self.body_frame)
        feet = np.array([snapshot.frame_position(f) for f in self.feet])
        com = robot.center_of_mass(q0)
        yaw = math.atan2(rotation[1, 0], rotation[0, 0])
        heading = np.array(((math.cos(yaw), math.sin(yaw)), (-math.sin(yaw), math.cos(yaw))))
        relative = (feet[:, :2] - com[:2]) @ heading.T
        self.nominal = relative - relative.mean(axis=0)
        self.stand_height = float(snapshot.frame_position(self.body_frame)[2] - feet[:, 2].mean())
        if self.stand_height <= 0.0:
            raise InvalidInputError(
                f"LeggedWalker: the body of {robot.name!r} is not above its feet when standing."
            )
        # a floor of 5 % of the robot for massless links
        legs = tuple(max(leg_mass(robot, f), 0.05 * robot.mass) for f in self.feet)
        self.gains = derive_gains(p, robot, q0, legs, self.stand_height)

    def _declare(self) -> None:
        """``support_k`` (all feet but group k), ``support_all`` and ``swing_F`` per foot."""
        p, robot, c, g = self.parameters, self.robot, self.controller, self.gains
        self.body = BodyModel(robot.mass, g, p.give_way or ("x", "y"))
        weight = robot.mass * GRAVITY
        min_normal = p.min_normal * weight / len(self.feet)
        if p.distribution == "qp":
            point = {"friction": p.friction, "min_normal": min_normal, "torque_limits": True}
            rule = {"method": "qp", "yield_axes": p.give_way}
        else:
            yielding = p.give_way or ("x", "y")  # the scaling rule needs axes to scale
            point, rule = {}, {"unilateral": {"z": min_normal}, "yield_axes": yielding}
        sets = {
            f"support_{k}": [f for f in self.feet if f not in group]
            for k, group in enumerate(self.groups)
        }
        sets["support_all"] = list(self.feet)
        for name, feet in sets.items():
            actuator = ParallelVirtualActuator(
                robot, self.body_frame, feet, "world", contact="point", **point
            )
            c.add(name, actuator, [self.body], **rule)
        upper = upper_joints(robot, self.feet)  # an arm, a head: held where they stand
        self._posture: tuple[str, ...] = ("posture", "upper_gravity") if upper else ()
        if upper:  # the arm's weight held by its joints, carried by the legs (the body model)
            w, q0 = 2.0 * math.pi * p.posture_frequency, self.initial_configuration()
            held = joint_gains(robot, upper, w, p.posture_damping_ratio, q0)
            c.add("posture", Posture(upper, held.stiffness, held.damping))
            c.add("upper_gravity", GravityCompensation(robot, links=upper, joints=upper))
        self.swing = {}
        for k, foot in enumerate(self.feet):
            spring = SpringDamper(
                ("x", "y", "z"), g.swing_stiffness[k], g.swing_damping[k], name=f"swing_{foot}"
            )
            self.swing[foot] = spring
            leg = VirtualActuator(robot, foot, self.body_frame, "world", ("x", "y", "z"))
            c.add(f"swing_{foot}", leg, [spring])

    def _machine(self) -> StateMachine:
        """``stand``, then ``swing_k`` and ``double_k`` for each group in turn."""
        n = len(self.groups)
        hold = self._posture
        states = [State("stand", ("support_all", *hold), self.feet, on_update=self._update)]
        transitions = [Transition("stand", "swing_0", events.after(self.parameters.stand_time))]
        for k, group in enumerate(self.groups):
            support = tuple(f for f in self.feet if f not in group)
            states += [
                State(
                    f"swing_{k}",
                    (f"support_{k}", *(f"swing_{f}" for f in group), *hold),
                    support,
                    on_enter=self._enter_swing,
                    on_update=self._update,
                ),
                State(f"double_{k}", ("support_all", *hold), self.feet, on_update=self._update),
            ]
            transitions += [
                Transition(
                    f"swing_{k}",
                    f"double_{k}",
                    events.when(self._landing(group)),
                    f"{'+'.join(group)} down",
                ),
                Transition(
                    f"double_{k}",
                    f"swing_{(k + 1) % n}",
                    events.after(self.double_time),
                    "double support time",
                ),
            ]
        return StateMachine(states, transitions, "stand")

    def set_command(self, velocity: Sequence[float], yaw_rate: float) -> None:
        """Body velocity ``(vx, vy)`` in the heading frame [m/s] and the yaw rate [rad/s].

        Raises:
            InvalidInputError: Values that are not finite.
        """
        vx, vy, yaw_rate = checked_command(velocity, yaw_rate)
        self.memory.command, self.memory.yaw_command = (vx, vy), yaw_rate

    @property
    def velocity(self) -> tuple[float, float]:
        """The command ``(vx, vy)`` in the heading frame [m/s]."""
        return self.memory.command

    @property
    def yaw_rate(self) -> float:
        """The commanded yaw rate [rad/s]."""
        return self.memory.yaw_command

    def initial_configuration(self) -> np.ndarray:
        """The SRDF's standing pose, else one built from the legs (``va.standing_pose``)."""
        return standing_pose(self.robot, self.feet)

    def nominal_height(self) -> float:
        """The body's standing height above its feet [m]."""
        return self.stand_height
