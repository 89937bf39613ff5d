"""The 1996 hexapod's tripod gait (VAC 1996, section 4), on the library's controller.

States ``tripod_a``, ``double_b``, ``tripod_b``, ``double_a``; the hexapod tutorial describes them.
"""

from __future__ import annotations

import numpy as np

from ...actuators import ParallelVirtualActuator, VirtualActuator
from ...components.springs import SpringDamper
from ...control import events
from ...control.plan.memory import Memory
from ...control.state_machine import Context, State, StateMachine, Transition
from ...kinematics.snapshot import Snapshot
from ...models.robot import Robot
from ...vocabulary.scalar import (
    asin,
    atan2,
    cos,
    dot,
    hypot,
    logical_and,
    logical_or,
    maximum,
    minimum,
    select,
    sin,
)  # fmt: skip
from ...vocabulary.traced import lowerable
from ..base import Gait, as_floats
from ..guidance import checked_command
from .body import HeadingAttitude, HeadingDamper
from .footholds import ground_velocity, tripod_setpoints
from .parameters import HexapodParameters
from .pendulum import PendulumModel, pendulum_lqr

LEGS = (1, 2, 3, 4, 5, 6)
TRIPODS = {"a": (1, 3, 5), "b": (2, 4, 6)}
OTHER = {"a": "b", "b": "a"}
PENDULUM_JOINT = "pendulum_joint"


class HexapodWalker(Gait):
    """The hexapod's tripod gait with the seed's three inputs.

    Args:
        robot: ``hexapod`` or ``hexapod_pendulum`` (frames ``body``, ``foot_1`` ... ``foot_6``;
            a ``pendulum_joint`` about the body's y axis is balanced).
        parameters: Gait variables and component constants.

    Attributes:
        memory: What the gait carries from tick to tick (a compiled plan's registers).
        pendulum: The pendulum's linear model, or None without a pendulum.

    Raises:
        FrameNotFoundError: The robot lacks the frames above.
        InvalidInputError: Bad parameters.
    """

    step_states = ("tripod_a", "tripod_b")
    contact_frames = tuple(f"foot_{i}" for i in LEGS)
    _command = (0.0, 0.0, 0.0)  # the command last written into the memory

    def __init__(self, robot: Robot, parameters: HexapodParameters | None = None) -> None:
        super().__init__(robot)
        self.parameters = p = parameters or HexapodParameters()
        model = robot.model
        weight = robot.mass * 9.81  # [N]
        self.height = SpringDamper(
            ("z",), p.stiffness_z, p.damping_z, setpoint=p.height, force=weight, name="height"
        )
        self.attitude = HeadingAttitude(p.stiffness_attitude, p.damping_attitude, name="attitude")
        self.planar = HeadingDamper(p.damping_xy, name="planar")
        self.swing = {
            i: SpringDamper(("x", "y", "z"), p.swing_stiffness, p.swing_damping, name=f"swing_{i}")
            for i in LEGS
        }
        self._declare_actuators()
        self._standing()
        zeros, ground = (0.0, 0.0), float(self.nominal[:, 2].mean())  # the ground, body axes [m]
        self.memory = Memory(
            command=(0.0, 0.0, 0.0), setpoint=zeros, acceleration=zeros, body_velocity=zeros,
            filtered=zeros, filter_time=0.0, target_time=0.0, plane=(0.0, 0.0, ground), phase=0.0,
            lift_off=(0.0,) * 9, targets=(0.0,) * 9, rates=(0.0,) * 9, pendulum=0.0,
        )  # fmt: skip
        self.pendulum: PendulumModel | None = None
        self._pendulum_index: tuple[int, int] | None = None
        if model.existJointName(PENDULUM_JOINT):
            self.pendulum, gain, self._pendulum_index = pendulum_lqr(
                model, PENDULUM_JOINT, p.pendulum_weights, p.pendulum_effort
            )
            self._gain = tuple(gain[0].tolist())  # the LQR's (1, 3) gain
            self.planar.damping = np.array((0.0, self.planar.damping[1]))  # x: the LQR's
        self._finish(self._machine(p.double_support_time))

    def set_command(self, velocity: tuple[float, float] | np.ndarray, yaw_rate: float) -> None:
        """Set the body velocity ``(vx, vy)`` in the heading frame [m/s] and the yaw rate [rad/s].

        Raises:
            InvalidInputError: Values that are not finite.
        """
        command = checked_command(velocity, yaw_rate)
        if command != self._command:  # the same command is not written again (a tick's cost)
            self.memory.command = self._command = command

    @property
    def velocity(self) -> np.ndarray:
        """Commanded body velocity in the heading frame ``(vx, vy)`` [m/s]."""
        return np.array(self.memory.command[:2])

    @property
    def yaw_rate(self) -> float:
        """Commanded yaw rate [rad/s]."""
        return self.memory.command[2]

    @property
    def pendulum_angle(self) -> float:
        """The pendulum's angle from the vertical, in the heading x-z plane [rad]."""
        return self.memory.pendulum

    def _declare_actuators(self) -> None:
        """``support_a``, ``support_b``, ``support_all`` (point feet) and ``swing_1`` ... ``6``."""
        p, robot, c = self.parameters, self.robot, self.controller
        if p.distribution == "qp":
            point = {"friction": p.friction, "min_normal": p.min_normal, "torque_limits": True}
            rule = {"method": "qp"}
        else:
            point, rule = {}, {"unilateral": {"z": p.min_normal}, "yield_axes": ("x", "y")}
        body = [self.height, self.planar, self.attitude]
        for name, legs in {**TRIPODS, "all": LEGS}.items():
            feet = [f"foot_{i}" for i in legs]
            actuator = ParallelVirtualActuator(robot, "body", feet, contact="point", **point)
            c.add(f"support_{name}", actuator, body, **rule)
        for i in LEGS:
            leg = VirtualActuator(robot, f"foot_{i}", "body", "body", ("x", "y", "z"))
            c.add(f"swing_{i}", leg, [self.swing[i]])

    def _standing(self) -> None:
        """The feet's nominal places and whether the body is the free flyer's frame."""
        model = self.robot.model
        standing = Snapshot(self.robot, self.initial_configuration())
        body_position = standing.frame_position("body")
        #: Feet relative to the body when standing (body axes) [m], row i - 1 for leg i
        self.nominal = np.array(
            [standing.frame_position(f"foot_{i}") - body_position for i in LEGS]
        )
        self.foot_radius = float(self.parameters.height + self.nominal[:, 2].mean())  # [m]
        self._nominal = tuple(tuple(row) for row in self.nominal.tolist())
        self._rows = {name: tuple(leg - 1 for leg in legs) for name, legs in TRIPODS.items()}
        frame = model.frames[model.getFrameId("body")]
        #: the body frame is the free flyer's (its velocity is read from v directly)
        self._body_is_root = (
            frame.parentJoint == 1 and model.joints[1].nq == 7 and frame.placement.isIdentity()
        )

    def _machine(self, double_support_time: float) -> StateMachine:
        """The four states (a tripod's stance, then a double support, per tripod)."""
        states, transitions = [], []
        for name, legs in TRIPODS.items():
            other = OTHER[name]
            states += [
                State(
                    f"tripod_{name}",
                    (f"support_{name}", *(f"swing_{i}" for i in TRIPODS[other])),
                    tuple(f"foot_{i}" for i in legs),
                    on_enter=self._enter_tripod,
                    on_update=self._update_tripod,
                ),
                State(
                    f"double_{name}",
                    ("support_all",),
                    tuple(f"foot_{i}" for i in LEGS),
                    on_update=self._update_double,
                ),
            ]
            transitions += [
                Transition(
                    f"tripod_{name}",
                    f"double_{other}",
                    events.when(self._stance_over),
                    f"tripod {other} down or the body a step over tripod {name}",
                ),
                Transition(
                    f"double_{name}",
                    f"tripod_{name}",
                    events.after(double_support_time),
                    "double support time",
                ),
            ]
        return StateMachine(states, transitions, "double_a")

    @lowerable
    def _stance_over(self, context: Context) -> object:
        """The body has travelled a step, or the swing feet have all touched down."""
        phase = self.memory.phase
        switches = context.contacts
        down = phase >= self.parameters.touchdown_phase
        for i in TRIPODS[OTHER[context.state[-1]]]:
            down = logical_and(down, switches.get(f"foot_{i}", 0.0))
        return logical_or(phase >= 1.0, down)

    def _body_state(self, context: Context) -> object:
        """Update the heading inputs, measured velocity and pendulum; the body's height [m]."""
        memory, p = self.memory, self.parameters
        r = as_floats(context.frame_rotation("body"))
        position = as_floats(context.frame_position("body"))
        yaw = atan2(r[1][0], r[0][0])
        pitch = asin(maximum(-1.0, minimum(1.0, -r[2][0])))
        c, s = cos(yaw), sin(yaw)
        velocity = context.v
        if self._body_is_root:  # v[:3] is the body's velocity in body axes
            u, v, w = velocity[0], velocity[1], velocity[2]
            world_x = r[0][0] * u + r[0][1] * v + r[0][2] * w
            world_y = r[1][0] * u + r[1][1] * v + r[1][2] * w
        else:
            world_x, world_y, _ = as_floats(context.frame_velocity("body"))
        vx, vy = c * world_x + s * world_y, -s * world_x + c * world_y  # heading frame
        memory.body_velocity = (vx, vy)
        now = context.time
        dt = maximum(now - memory.filter_time, 0.0)
        memory.filter_time = now
        blend = minimum(1.0, dt / p.velocity_filter)
        fx, fy = memory.filtered
        memory.filtered = (fx + blend * (vx - fx), fy + blend * (vy - fy))
        # the set point follows the command at a bounded acceleration
        (cx, cy, yaw_rate), (sx, sy) = memory.command, memory.setpoint
        ax, ay = memory.acceleration
        changed = logical_or(cx != sx, cy != sy)
        ex, ey = cx - sx, cy - sy
        size, most = hypot(ex, ey), p.acceleration * dt
        near = size <= most
        scale = select(near, 1.0, most / select(near, 1.0, size))
        sx, sy = select(changed, sx + scale * ex, sx), select(changed, sy + scale * ey, sy)
        moved = dt > 0.0
        step = select(moved, dt, 1.0)
        ax = select(moved, select(changed, scale * ex / step, 0.0), ax)
        ay = select(moved, select(changed, scale * ey / step, 0.0), ay)
        memory.setpoint, memory.acceleration = (sx, sy), (ax, ay)
        self.planar.velocity = (sx, sy)
        self.planar.yaw = yaw
        self.attitude.yaw_rate = yaw_rate
        if self._pendulum_index is not None:  # the LQR: the planar damper's force along the heading
            omega = (velocity[3], velocity[4], velocity[5])  # the free flyer's, body axes
            world = [dot(row, omega) for row in r[:2]]
            iq, iv = self._pendulum_index
            memory.pendulum = angle = context.q[iq] + pitch
            rate = context.v[iv] + (-s * world[0] + c * world[1])
            error = (angle, rate, memory.body_velocity[0] - memory.setpoint[0])
            self.planar.force = (-dot(self._gain, error), 0.0)
        return position[2]

    def _feet(self, context: Context) -> list:
        """The six feet relative to the body, body axes: ``(foot - body) @ rotation`` [m]."""
        r = as_floats(context.frame_rotation("body"))
        bx, by, bz = as_floats(context.frame_position("body"))
        feet = []
        for i in LEGS:
            x, y, z = as_floats(context.frame_position(f"foot_{i}"))
            dx, dy, dz = x - bx, y - by, z - bz
            feet.append(tuple(dx * r[0][j] + dy * r[1][j] + dz * r[2][j] for j in range(3)))
        return feet

    @lowerable
    def _update_double(self, context: Context) -> None:
        self._body_state(context)

    @lowerable
    def _enter_tripod(self, context: Context) -> None:
        """The swing tripod lifts off: its feet, and their velocity relative to the body."""
        support = context.state[-1]
        memory = self.memory
        self._body_state(context)
        feet = self._feet(context)
        rows = self._rows[OTHER[support]]
        memory.lift_off = memory.targets = tuple(v for r in rows for v in feet[r])
        memory.target_time = context.time
        memory.phase = 0.0
        # the lifting feet leave the ground at its velocity relative to the body
        ground = ground_velocity(memory.filtered, memory.command[2], self._nominal)
        rates = [(-ground[r][0], -ground[r][1], 0.0) for r in rows]
        memory.rates = tuple(v for rate in rates for v in rate)
        for rate, i in zip(rates, TRIPODS[OTHER[support]], strict=True):
            self.swing[i].velocity_setpoint = rate

    @lowerable
    def _update_tripod(self, context: Context) -> None:
        """The ground plane, the phase and the swing set points (`tripod_setpoints`)."""
        support = context.state[-1]
        height = self._body_state(context)
        memory, p = self.memory, self.parameters
        now = context.time
        motion = (height, *memory.filtered, *memory.setpoint, *memory.acceleration,
                  memory.command[2], context.time_in_state, now - memory.target_time)  # fmt: skip
        rows = self._rows[support], self._rows[OTHER[support]]
        plane, phase, targets, rates, ground = tripod_setpoints(
            p, self._feet(context), *rows, self._nominal, motion, self.foot_radius, memory
        )
        memory.target_time = now
        memory.plane, memory.phase, memory.targets, memory.rates = plane, phase, targets, rates
        self.height.setpoint = ground + p.height
        for k, i in enumerate(TRIPODS[OTHER[support]]):
            self.swing[i].setpoint = targets[3 * k : 3 * k + 3]
            self.swing[i].velocity_setpoint = rates[3 * k : 3 * k + 3]
