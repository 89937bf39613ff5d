"""The 1996 hexapod's tripod gait (VAC 1996, section 4), on the library's controller.

"Movements in the z, roll, and pitch directions were position controlled to a constant desired
value using a virtual spring-damper system. A virtual damper was used in the x, y, and yaw
directions in order to velocity control the movements in these directions. A different set of
virtual spring-damper mechanisms were used to position control the legs of the swing tripod.
The swing and support tripods were cycled by a state machine which changed states based on the
distance between the body and the tripods."

=============  ========================================  =====================================
state          active attachments                        left when
=============  ========================================  =====================================
``tripod_a``   body on feet 1, 3, 5; legs 2, 4, 6 swing   the swing feet have all touched down
                                                          (contact switches, from half the
                                                          swing on) or the support feet are
                                                          half a step behind their nominal
                                                          places (or a time limit)
``double_b``   body on all six feet                      after ``double_support_time``
``tripod_b``   body on feet 2, 4, 6; legs 1, 3, 5 swing   as ``tripod_a``
``double_a``   body on all six feet                      after ``double_support_time``
=============  ========================================  =====================================

The body's virtual components (`body`) act in its heading
frame; its wrench is distributed over the support feet by a
[`ParallelVirtualActuator`][] (point feet; ``distribution="qp"`` with
friction pyramids and a least normal force, or ``"partitioned"``, the minimum-norm split with the
normal forces kept up by scaling the horizontal request). Each swing foot has a spring-damper
relative to the body (a serial [`VirtualActuator`][] from the body to the
foot, body axes) whose set point lifts the foot and carries it to where it lands: its nominal
place plus half the distance the body travels over the tripod stance, plus what it travels in
a double support (so that the support tripod's stance is centred under the body). The three
inputs are the body velocity in the heading frame and the yaw rate
(`HexapodWalker.set_command`); the velocity set point follows them at a bounded
acceleration.

Contacts (measured per foot from MuJoCo): a tripod carries the body with a static margin of
only ``0.075 m - step / 2`` (the centre of mass crosses that close to the triangle's edge at
either end of a stance), so the gait keeps every support foot loaded and inside MuJoCo's friction
cone by construction:

* the tripod's stance is centred under the body (the landing place leads by the double
  support's travel too) and ends when its feet are half a step behind their nominal places,
  however far they started (the first stance starts from the standing pose);
* a swing tripod whose three contact switches close ends the stance at once (before, its feet
  were pressed 1 cm into the ground by their springs for ~10 ms, carrying up to 19 N outside the
  distribution, and the support tripod's rear foot went to 0 N);
* all six feet share the body during ``double_support_time``;
* the velocity set point is acceleration-limited (a step to 0.8 m/s asked 120 N of a body whose
  feet can give 19 N) and the feet land ``height / g`` times that acceleration further back
  (where the centre of pressure goes);
* the QP keeps ``min_normal`` on every support foot, and its pyramid
  ``|f_x|, |f_y| <= mu f_z`` fits inside MuJoCo's pyramidal cone
  (``|f_t1| + |f_t2| <= 1.0 f_n`` whatever the contact's tangent axes) for ``mu <= 0.5``.
"""

from __future__ import annotations

import math

import numpy as np

from ...actuators import ParallelVirtualActuator, VirtualActuator
from ...components.springs import SpringDamper
from ...control import events
from ...control.state_machine import Context, State, StateMachine, Transition
from ...exceptions import InvalidInputError
from ...kinematics.snapshot import Snapshot
from ...models.robot import Robot
from ..base import Gait
from .body import (
    HeadingAttitude,
    HeadingDamper,
    PendulumModel,
    pendulum_lqr,
)
from .footholds import ground_velocity
from .kernel import SHAPE, TRIPOD_SETPOINTS
from .parameters import HexapodParameters

LEGS = (1, 2, 3, 4, 5, 6)
TRIPODS = {"a": (1, 3, 5), "b": (2, 4, 6)}
OTHER = {"a": "b", "b": "a"}
PENDULUM_JOINT = "pendulum_joint"

__all__ = ["LEGS", "TRIPODS", "HexapodWalker"]


class HexapodWalker(Gait):
    """The hexapod's tripod gait with the seed's three inputs.

    Args:
        robot: ``hexapod`` or ``hexapod_pendulum`` (frames ``body``, ``foot_1`` ... ``foot_6``;
            with a joint ``pendulum_joint`` about the body's y axis, the walker balances it).
        parameters: Gait variables and component constants.

    Attributes:
        velocity: Commanded body velocity in the heading frame ``(vx, vy)`` [m/s].
        yaw_rate: Commanded yaw rate [rad/s].
        pendulum: The pendulum's linear model, or None without a pendulum.
        gain: The pendulum's LQR gain ``(1, 3)``, or None.

    Raises:
        FrameNotFoundError: The robot lacks the frames above.
        InvalidInputError: Bad parameters.

    """

    step_states = ("tripod_a", "tripod_b")
    contact_frames = tuple(f"foot_{i}" for i in LEGS)

    def __init__(self, robot: Robot, parameters: HexapodParameters | None = None) -> None:
        super().__init__(robot)
        self.parameters = p = parameters or HexapodParameters()
        model = robot.model
        self.velocity = np.zeros(2)
        self.velocity_setpoint = np.zeros(2)  # the command, acceleration-limited [m/s]
        self.yaw_rate = 0.0
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
        self.ground = 0.0  # ground height under the body [m]
        self.support = "a"
        self.phase = 0.0  # swing progress, 0 to 1
        #: the tripod kernel's state: the ground plane (a, b, c), the phase, the ground height
        self._state = np.array((0.0, 0.0, float(self.nominal[:, 2].mean()), 0.0, 0.0))
        #: per swing foot: its lift-off point, last set point and its velocity [m, m/s]
        self._swing = np.zeros((3, 9))
        self._shape = np.array(
            [getattr(self if name == "foot_radius" else p, name) for name in SHAPE]
        )
        self._target_time = 0.0
        self._velocity_body = (0.0, 0.0)  # measured, heading frame [m/s]
        self._velocity_filtered = (0.0, 0.0)  # low-passed, for foot placement [m/s]
        self._setpoint = (0.0, 0.0)  # velocity_setpoint as floats [m/s]
        self._acceleration = (0.0, 0.0)  # of the velocity set point [m/s^2]
        self._filter_time = 0.0
        self.pendulum: PendulumModel | None = None
        self.gain: np.ndarray | None = None
        self.pendulum_angle = 0.0  # from the vertical, in the heading x-z plane [rad]
        self._pendulum_index = None
        if model.existJointName(PENDULUM_JOINT):
            self.pendulum, self.gain, self._pendulum_index = pendulum_lqr(
                model, PENDULUM_JOINT, p.pendulum_weights, p.pendulum_effort
            )
            self.planar.damping = np.array((0.0, self.planar.damping[1]))  # x: the LQR's
        self._finish(self._machine(p.double_support_time))

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
        """The feet's nominal places and the frames `_body_state` reads."""
        model = self.robot.model
        standing = Snapshot(self.robot, self.initial_configuration())
        body_position = standing.frame_position("body")
        #: Feet relative to the body when standing (body axes) [m], row i - 1 for leg i
        self.nominal = np.array(
            [standing.frame_position(f"foot_{i}") - body_position for i in LEGS]
        )
        self.foot_radius = float(self.parameters.height + self.nominal[:, 2].mean())  # [m]
        self._body_frame = model.getFrameId("body")
        self._foot_frames = [model.getFrameId(f"foot_{i}") for i in LEGS]
        self._nominal = self.nominal.tolist()
        self._rows = {name: tuple(leg - 1 for leg in legs) for name, legs in TRIPODS.items()}
        #: the tripod kernel's rows: the support tripod's feet, then the swing tripod's
        self._kernel_rows = {
            name: np.array(self._rows[name] + self._rows[OTHER[name]], dtype=np.int64)
            for name in TRIPODS
        }
        self._nominal_feet = np.ascontiguousarray(self.nominal, dtype=float)
        self._table_rows = None  # the kinematics' frame-table rows (cached on first use)
        self._feet_rows = np.zeros(6, dtype=int)
        self._body_row = 0
        self._frame_rows = np.zeros(7, dtype=np.int64)  # the body's row, then the feet's
        frame = model.frames[self._body_frame]
        #: the body frame is the free flyer's (its velocity is read from v directly)
        self._body_is_root = (
            frame.parentJoint == 1 and model.joints[1].nq == 7 and frame.placement.isIdentity()
        )

    def _machine(self, double_support_time: float) -> StateMachine:
        """The four states (a tripod's stance, then a double support, per tripod)."""
        states, transitions = [], []
        for name, legs in TRIPODS.items():
            other = "b" if name == "a" else "a"
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
            swing_feet = tuple(f"foot_{i}" for i in TRIPODS[other])
            transitions += [
                Transition(
                    f"tripod_{name}",
                    f"double_{other}",
                    events.when(lambda context, feet=swing_feet: self._stance_over(context, feet)),
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

    # --- inputs --------------------------------------------------------------------------------

    def set_command(self, velocity: tuple[float, float] | np.ndarray, yaw_rate: float) -> None:
        """Set the three inputs: body velocity in the heading frame and the yaw rate.

        Args:
            velocity: ``(vx, vy)`` [m/s] along and across the heading.
            yaw_rate: [rad/s].

        Raises:
            InvalidInputError: Values that are not finite.

        """
        vx, vy = velocity
        vx, vy, yaw_rate = float(vx), float(vy), float(yaw_rate)
        if not (math.isfinite(vx) and math.isfinite(vy) and math.isfinite(yaw_rate)):
            raise InvalidInputError(
                f"set_command: velocity and yaw rate must be finite, got {velocity}, {yaw_rate}."
            )
        if [vx, vy] != self.velocity.tolist():
            self.velocity = np.array((vx, vy))
        self.yaw_rate = yaw_rate

    # --- pendulum ------------------------------------------------------------------------------

    def _balance(self, context: Context, pitch: float, pitch_rate: float) -> None:
        iq, iv = self._pendulum_index
        self.pendulum_angle = float(context.q[iq]) + pitch
        rate = float(context.v[iv]) + pitch_rate
        error = (self.pendulum_angle, rate, self._velocity_body[0] - self.velocity_setpoint[0])
        self.planar.force = np.array((-float(self.gain[0] @ np.array(error)), 0.0))

    # --- per-tick updates ----------------------------------------------------------------------

    def _stance_over(self, context: Context, swing_feet: tuple[str, ...]) -> bool:
        """The body has travelled a step, or the swing feet have all touched down."""
        if self.phase >= 1.0:
            return True
        contacts = context.contacts
        if contacts is None or self.phase < self.parameters.touchdown_phase:
            return False
        for foot in swing_feet:  # all(...), without a generator per tick
            if not contacts.get(foot, False):
                return False
        return True

    def _body_state(self, context: Context) -> float:
        """Heading inputs, measured velocity, pendulum; the body's height.

        Returns:
            The body's height [m].

        """
        snapshot = context.snapshot
        table = snapshot.frame_table
        rows = snapshot.tree.frame_tables[0]
        if rows is not self._table_rows:  # the frames' rows in the kinematics' frame table
            self._table_rows = rows
            self._feet_rows = np.array([rows[f] for f in self._foot_frames])
            self._body_row = rows[self._body_frame]
            self._frame_rows = np.array([self._body_row, *self._feet_rows], dtype=np.int64)
        body = table[self._body_row]
        rotation, position = body[:9].reshape(3, 3), body[9:]
        r = rotation.tolist()
        yaw = math.atan2(r[1][0], r[0][0])
        pitch = math.asin(max(-1.0, min(1.0, -r[2][0])))
        c, s = math.cos(yaw), math.sin(yaw)
        if self._body_is_root:  # v[:3] is the body's velocity in body axes
            u, v, w = context.v[:3].tolist()
            world_x = r[0][0] * u + r[0][1] * v + r[0][2] * w
            world_y = r[1][0] * u + r[1][1] * v + r[1][2] * w
        else:
            world_x, world_y, _ = snapshot.frame_velocity(self._body_frame).tolist()
        vx, vy = c * world_x + s * world_y, -s * world_x + c * world_y  # heading frame
        self._velocity_body = (vx, vy)
        dt = max(context.time - self._filter_time, 0.0)
        self._filter_time = context.time
        p = self.parameters
        blend = min(1.0, dt / p.velocity_filter)
        fx, fy = self._velocity_filtered
        self._velocity_filtered = (fx + blend * (vx - fx), fy + blend * (vy - fy))
        cx, cy = self.velocity.tolist()
        sx, sy = self._setpoint
        if (cx, cy) != (sx, sy):  # the set point follows the command at a bounded acceleration
            ex, ey = cx - sx, cy - sy
            size, most = math.hypot(ex, ey), p.acceleration * dt
            scale = 1.0 if size <= most else most / size
            self._setpoint = (sx + scale * ex, sy + scale * ey)
            self.velocity_setpoint = np.array(self._setpoint)
            self.planar.velocity = self.velocity_setpoint
            if dt > 0.0:
                self._acceleration = (scale * ex / dt, scale * ey / dt)
        elif dt > 0.0:
            self._acceleration = (0.0, 0.0)
        self.planar.yaw = yaw
        self.attitude.yaw_rate = self.yaw_rate
        if self._pendulum_index is not None:
            world_omega = rotation @ context.v[3:6]  # free-flyer angular velocity: body axes
            self._balance(context, pitch, -s * world_omega[0] + c * world_omega[1])
        return float(position[2])

    def _update_double(self, context: Context) -> None:
        self._body_state(context)

    def _enter_tripod(self, context: Context) -> None:
        self.support = context.state[-1]
        self._body_state(context)
        table = context.snapshot.frame_table  # the feet relative to the body, body axes
        body = table[self._body_row]
        feet = (table[self._feet_rows, 9:] - body[9:]) @ body[:9].reshape(3, 3)
        rows = self._rows[OTHER[self.support]]
        swing = self._swing
        swing[:, :3] = swing[:, 3:6] = feet[list(rows)]  # lift-off: the last set point
        self._target_time = context.time
        self.phase = self._state[3] = 0.0
        # the lifting feet leave the ground at its velocity relative to the body
        ground = ground_velocity(self._velocity_filtered, self.yaw_rate, self._nominal)
        swing[:, 6:] = [(-ground[r][0], -ground[r][1], 0.0) for r in rows]
        for k, i in enumerate(TRIPODS[OTHER[self.support]]):
            self.swing[i].velocity_setpoint = swing[k, 6:]

    def _update_tripod(self, context: Context) -> None:
        """The ground plane, the phase and the swing set points (`kernel`), one call."""
        height = self._body_state(context)
        now = context.time
        fx, fy = self._velocity_filtered
        motion = np.array((height, fx, fy, *self._setpoint, *self._acceleration, self.yaw_rate,
                           context.time_in_state, now - self._target_time))  # fmt: skip
        swing, state = self._swing, self._state
        TRIPOD_SETPOINTS(context.snapshot.frame_table, self._frame_rows,
                         self._kernel_rows[self.support], self._nominal_feet, motion,
                         self._shape, swing, state)  # fmt: skip
        self._target_time = now
        _, _, _, self.phase, self.ground = state.tolist()
        self.height.setpoint = self.ground + self.parameters.height
        for k, i in enumerate(TRIPODS[OTHER[self.support]]):
            self.swing[i].setpoint = swing[k, 3:6]
            self.swing[i].velocity_setpoint = swing[k, 6:]

    @property
    def plane(self) -> tuple[float, float, float]:
        """The ground plane ``z = a x + b y + c`` through the support feet, body axes."""
        a, b, c = self._state[:3].tolist()
        return a, b, c
