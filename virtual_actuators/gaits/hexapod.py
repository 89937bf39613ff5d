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
``tripod_a``   body on feet 1, 3, 5; legs 2, 4, 6 swing   the body has travelled a step over
                                                          the support tripod (or a time limit)
``double_b``   body on all six feet                      after ``double_support_time``
``tripod_b``   body on feet 2, 4, 6; legs 1, 3, 5 swing   as ``tripod_a``
``double_a``   body on all six feet                      after ``double_support_time``
=============  ========================================  =====================================

The body's virtual components (:mod:`~virtual_actuators.gaits.hexapod_body`) act in its heading
frame; its wrench is distributed over the support feet by a
:class:`~virtual_actuators.ParallelVirtualActuator` (point feet; ``distribution="qp"`` with
friction pyramids and a least normal force, or ``"partitioned"``, the minimum-norm split with the
normal forces kept up by scaling the horizontal request). Each swing foot has a spring-damper
relative to the body (a serial :class:`~virtual_actuators.VirtualActuator` from the body to the
foot, body axes) whose set point lifts the foot and carries it to where it lands: its nominal
place plus half the distance the body travels over a stance. The three inputs are the body
velocity in the heading frame and the yaw rate (:meth:`HexapodWalker.set_command`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..actuators import ParallelVirtualActuator, VirtualActuator
from ..components.springs import SpringDamper
from ..control import events
from ..control.state_machine import Context, State, StateMachine, Transition
from ..exceptions import InvalidInputError
from ..kinematics.snapshot import Snapshot
from ..robots.robot import Robot
from .base import Gait
from .hexapod_body import (
    HeadingAttitude,
    HeadingDamper,
    PendulumModel,
    lqr_gain,
    pendulum_model,
    yaw_pitch_roll,
)
from .turkey import lift_profile, smoothstep

LEGS = (1, 2, 3, 4, 5, 6)
TRIPODS = {"a": (1, 3, 5), "b": (2, 4, 6)}
OTHER = {"a": "b", "b": "a"}
PENDULUM_JOINT = "pendulum_joint"
DISTRIBUTIONS = ("qp", "partitioned")


@dataclass
class HexapodParameters:
    """Gait variables and virtual component constants (SI units).

    Defaults start from the public reproduction's constants (IHMC "agileHexapod": height 0.13 m,
    x, y damping 30, yaw damping 8, lift 0.05 m, 0.05 s double support), made stiffer where the
    seed's 0.8 m/s needs it.

    Attributes:
        height: Body height set point above the ground under the support feet [m].
        stiffness_z: [N/m].
        damping_z: [N s/m].
        stiffness_attitude: Roll, pitch springs [N m/rad].
        damping_attitude: Roll, pitch, yaw dampers [N m s/rad].
        damping_xy: Dampers along and across the heading [N s/m].
        step_length: Distance the body travels over the support tripod per stance, along the
            heading [m].
        step_width: The same across the heading (the legs reach less sideways) [m]; in other
            directions the ellipse of these two axes.
        max_stance_time: A stance ends after this long even if the body has not travelled a
            step (slow walking and turning on the spot still step) [s].
        double_support_time: All six feet support between two tripods [s].
        lift: Swing foot lift [m].
        lift_peak: Phase of the swing (0 to 1) at which the foot is highest.
        swing_stiffness: Swing-foot springs (x, y, z), body axes [N/m].
        swing_damping: Swing-foot dampers (x, y, z) [N s/m].
        touchdown_depth: How far below the support feet's level the swing set point ends [m].
        placement_gain: Raibert term: the landing point moves this many seconds times the
            velocity error (measured minus commanded) further [s].
        velocity_filter: Time constant of the low-pass filters on the measured body velocity
            (foot placement) and on the swing set points' velocity [s].
        distribution: ``"qp"`` or ``"partitioned"``.
        friction: Friction coefficient assumed for the feet (the distribution's cone) [-].
        min_normal: Least normal force of a support foot [N].
        pendulum_weights: LQR state weights (angle, rate, velocity) [1/rad^2, s^2/rad^2, s^2/m^2].
        pendulum_effort: LQR input weight [1/N^2].
        pendulum_fall: A pendulum beyond this angle from the vertical has fallen [rad].

    """

    height: float = 0.13
    stiffness_z: float = 600.0
    damping_z: float = 40.0
    stiffness_attitude: tuple[float, float] = (30.0, 40.0)
    damping_attitude: tuple[float, float, float] = (1.0, 2.0, 8.0)
    damping_xy: tuple[float, float] = (150.0, 150.0)
    step_length: float = 0.12
    step_width: float = 0.07
    max_stance_time: float = 0.35
    double_support_time: float = 0.02
    lift: float = 0.04
    lift_peak: float = 0.4
    swing_stiffness: tuple[float, float, float] = (800.0, 800.0, 800.0)
    swing_damping: tuple[float, float, float] = (12.0, 12.0, 12.0)
    touchdown_depth: float = 0.01
    placement_gain: float = 0.05
    velocity_filter: float = 0.02
    distribution: str = "qp"
    friction: float = 0.8
    min_normal: float = 1.0
    pendulum_weights: tuple[float, float, float] = (100.0, 1.0, 300.0)
    pendulum_effort: float = 0.01
    pendulum_fall: float = 0.6

    def __post_init__(self) -> None:
        if self.distribution not in DISTRIBUTIONS:
            raise InvalidInputError(
                f"distribution must be one of {DISTRIBUTIONS}, got {self.distribution!r}."
            )


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
        mass = float(sum(inertia.mass for inertia in model.inertias))  # [kg]
        self.velocity = np.zeros(2)
        self.yaw_rate = 0.0
        self.height = SpringDamper(
            ("z",), p.stiffness_z, p.damping_z, setpoint=p.height, force=mass * 9.81, name="height"
        )
        self.attitude = HeadingAttitude(p.stiffness_attitude, p.damping_attitude, name="attitude")
        self.planar = HeadingDamper(p.damping_xy, name="planar")
        body = [self.height, self.planar, self.attitude]
        c = self.controller
        supports = {**{name: legs for name, legs in TRIPODS.items()}, "all": LEGS}
        for name, legs in supports.items():
            feet = [f"foot_{i}" for i in legs]
            if p.distribution == "qp":
                actuator = ParallelVirtualActuator(
                    robot,
                    "body",
                    feet,
                    "world",
                    contact="point",
                    friction=p.friction,
                    min_normal=p.min_normal,
                    torque_limits=True,
                )
                c.add(f"support_{name}", actuator, body, method="qp")
            else:
                actuator = ParallelVirtualActuator(robot, "body", feet, "world", contact="point")
                c.add(
                    f"support_{name}",
                    actuator,
                    body,
                    unilateral={"z": p.min_normal},
                    yield_axes=("x", "y"),
                )
        self.swing = {}
        for i in LEGS:
            self.swing[i] = SpringDamper(
                ("x", "y", "z"), p.swing_stiffness, p.swing_damping, name=f"swing_{i}"
            )
            leg = VirtualActuator(robot, f"foot_{i}", "body", "body", ("x", "y", "z"))
            c.add(f"swing_{i}", leg, [self.swing[i]])

        standing = Snapshot(robot, self.initial_configuration())
        body_position = standing.frame_position("body")
        #: Feet relative to the body when standing (body axes) [m], row i - 1 for leg i
        self.nominal = np.array(
            [standing.frame_position(f"foot_{i}") - body_position for i in LEGS]
        )
        self.foot_radius = float(p.height + self.nominal[:, 2].mean())  # foot centre height [m]
        self._body_frame = model.getFrameId("body")
        self._foot_frames = [model.getFrameId(f"foot_{i}") for i in LEGS]
        self._rows = {name: np.array(legs) - 1 for name, legs in TRIPODS.items()}
        self.ground = 0.0  # ground height under the body [m]
        #: ground plane z = a x + b y + c in body axes through the support feet (a, b, c)
        self.plane = np.array((0.0, 0.0, float(self.nominal[:, 2].mean())))
        self.support = "a"
        self.phase = 0.0  # swing progress, 0 to 1
        self._stance_start = np.zeros((3, 3))
        self._swing_start = np.zeros((3, 3))
        self._targets = np.zeros((3, 3))
        self._target_time = 0.0
        self._velocity_body = np.zeros(2)  # measured, heading frame [m/s]
        self._velocity_filtered = np.zeros(2)  # low-passed, for foot placement [m/s]
        self._filter_time = 0.0
        self._rates = np.zeros((3, 3))  # swing set point velocities, low-passed [m/s]
        self.pendulum: PendulumModel | None = None
        self.gain: np.ndarray | None = None
        self.pendulum_angle = 0.0  # from the vertical, in the heading x-z plane [rad]
        self._pendulum_index = None
        if model.existJointName(PENDULUM_JOINT):
            self._design_pendulum()

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
            transitions += [
                Transition(
                    f"tripod_{name}",
                    f"double_{other}",
                    events.when(lambda context: self.phase >= 1.0),
                    f"body a step over tripod {name}",
                ),
                Transition(
                    f"double_{name}",
                    f"tripod_{name}",
                    events.after(p.double_support_time),
                    "double support time",
                ),
            ]
        self._finish(StateMachine(states, transitions, "double_a"))

    # --- inputs --------------------------------------------------------------------------------

    def set_command(self, velocity: tuple[float, float] | np.ndarray, yaw_rate: float) -> None:
        """Set the three inputs: body velocity in the heading frame and the yaw rate.

        Args:
            velocity: ``(vx, vy)`` [m/s] along and across the heading.
            yaw_rate: [rad/s].

        Raises:
            InvalidInputError: Values that are not finite.

        """
        vx, vy = (float(v) for v in velocity)
        yaw_rate = float(yaw_rate)
        if not all(math.isfinite(v) for v in (vx, vy, yaw_rate)):
            raise InvalidInputError(
                f"set_command: velocity and yaw rate must be finite, got {velocity}, {yaw_rate}."
            )
        self.velocity = np.array((vx, vy))
        self.yaw_rate = yaw_rate

    # --- pendulum ------------------------------------------------------------------------------

    def _design_pendulum(self) -> None:
        """The LQR of the pendulum from the robot's own inertias (the controller's model)."""
        p, model = self.parameters, self.robot.model
        joint = model.getJointId(PENDULUM_JOINT)
        inertia = model.inertias[joint]
        com = float(np.linalg.norm(inertia.lever))
        about_pivot = float(inertia.inertia[1, 1]) + inertia.mass * com**2  # about y [kg m^2]
        total = float(sum(i.mass for i in model.inertias))
        self.pendulum = pendulum_model(total - inertia.mass, inertia.mass, com, about_pivot)
        self.gain = lqr_gain(
            self.pendulum.a,
            self.pendulum.b,
            np.diag(p.pendulum_weights),
            np.array([[p.pendulum_effort]]),
        )
        self._pendulum_index = (model.joints[joint].idx_q, model.joints[joint].idx_v)
        self.planar.damping = np.array((0.0, self.planar.damping[1]))  # x belongs to the LQR

    def _balance(self, context: Context, pitch: float, pitch_rate: float) -> None:
        iq, iv = self._pendulum_index
        self.pendulum_angle = float(context.q[iq]) + pitch
        rate = float(context.v[iv]) + pitch_rate
        error = np.array((self.pendulum_angle, rate, self._velocity_body[0] - self.velocity[0]))
        self.planar.force = np.array((-float(self.gain[0] @ error), 0.0))

    # --- per-tick updates ----------------------------------------------------------------------

    def _body_state(self, context: Context) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Heading inputs, measured velocity, pendulum; body position, rotation, feet.

        Returns:
            Body position [m], rotation, and the six feet relative to the body in body axes
            ``(6, 3)`` [m].

        """
        snapshot = context.snapshot
        table = snapshot.frame_table
        rows = snapshot.tree.frame_tables[0]
        body = table[rows[self._body_frame]]
        rotation, position = body[:9].reshape(3, 3), body[9:]
        feet = (table[[rows[f] for f in self._foot_frames], 9:] - position) @ rotation
        yaw, pitch, _ = yaw_pitch_roll(rotation)
        c, s = math.cos(yaw), math.sin(yaw)
        velocity = snapshot.frame_velocity(self._body_frame)
        vx = c * velocity[0] + s * velocity[1]
        vy = -s * velocity[0] + c * velocity[1]
        self._velocity_body = np.array((vx, vy))
        dt = context.time - self._filter_time
        self._filter_time = context.time
        blend = min(1.0, max(dt, 0.0) / self.parameters.velocity_filter)
        self._velocity_filtered += blend * (self._velocity_body - self._velocity_filtered)
        self.planar.yaw = yaw
        self.planar.velocity = self.velocity
        self.attitude.yaw_rate = self.yaw_rate
        if self._pendulum_index is not None:
            world_omega = rotation @ context.v[3:6]  # free-flyer angular velocity: body axes
            self._balance(context, pitch, -s * world_omega[0] + c * world_omega[1])
        return position, rotation, feet

    def _set_ground(self, position: np.ndarray, stance: np.ndarray) -> None:
        """Ground plane through the support tripod (body axes); the height set point from it."""
        (x1, y1, z1), (x2, y2, z2), (x3, y3, z3) = stance.tolist()
        ux, uy, uz, vx, vy, vz = x2 - x1, y2 - y1, z2 - z1, x3 - x1, y3 - y1, z3 - z1
        nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx  # normal
        if abs(nz) > 1e-9:  # else the feet are in a line: keep the previous plane
            a, b = -nx / nz, -ny / nz
            self.plane = np.array((a, b, z1 - a * x1 - b * y1))
        self.ground = float(position[2] + self.plane[2]) - self.foot_radius
        self.height.setpoint = self.ground + self.parameters.height

    def _update_double(self, context: Context) -> None:
        self._body_state(context)

    def _enter_tripod(self, context: Context) -> None:
        self.support = context.state[-1]
        _, _, feet = self._body_state(context)
        self._stance_start = feet[self._rows[self.support]]
        self._swing_start = feet[self._rows[OTHER[self.support]]]
        self._targets = self._swing_start.copy()
        self._target_time = context.time
        self.phase = 0.0
        self._rates[:] = 0.0
        for i in TRIPODS[OTHER[self.support]]:
            self.swing[i].velocity_setpoint = 0.0

    def _strides(self, dx: np.ndarray, dy: np.ndarray) -> np.ndarray:
        """Horizontal displacements in strides: the ellipse of axes step length and width is 1."""
        p = self.parameters
        return np.sqrt((dx / p.step_length) ** 2 + (dy / p.step_width) ** 2)

    def _landing(self, nominal: np.ndarray) -> np.ndarray:
        """Where the swing feet land relative to the body (body axes) [m].

        Half a stance's travel ahead of their nominal place (the support feet then end half a
        stance behind theirs), with the body's measured velocity and the commanded yaw rate,
        plus the Raibert term; within 0.6 strides of the nominal place.
        """
        p = self.parameters
        vx, vy = self._velocity_filtered
        w = self.yaw_rate
        sx = vx - w * nominal[:, 1]  # velocity over the ground of the nominal foot points
        sy = vy + w * nominal[:, 0]
        rate = float(np.max(self._strides(sx, sy)))  # strides per second
        stance = p.max_stance_time if rate * p.max_stance_time <= 1.0 else 1.0 / rate
        ex, ey = p.placement_gain * (self._velocity_filtered - self.velocity)
        ox, oy = 0.5 * stance * sx + ex, 0.5 * stance * sy + ey
        factor = np.minimum(1.0, 0.6 / np.maximum(self._strides(ox, oy), 1e-9))
        landing = nominal.copy()
        landing[:, 0] += ox * factor
        landing[:, 1] += oy * factor
        return landing

    def _update_tripod(self, context: Context) -> None:
        p = self.parameters
        position, rotation, feet = self._body_state(context)
        stance = feet[self._rows[self.support]]
        swing_rows = self._rows[OTHER[self.support]]
        self._set_ground(position, stance)
        moved = stance - self._stance_start
        drift = float(np.max(self._strides(moved[:, 0], moved[:, 1])))
        progress = max(drift, context.time_in_state / p.max_stance_time)
        self.phase = max(self.phase, min(progress, 1.0))
        landing = self._landing(self.nominal[swing_rows])
        reach = smoothstep(min(1.0, 1.25 * self.phase))
        start = self._swing_start
        targets = start + (landing - start) * reach
        a, b, c = self.plane
        ground = a * targets[:, 0] + b * targets[:, 1] + c  # under the feet, body axes [m]
        start_height = start[:, 2] - (a * start[:, 0] + b * start[:, 1] + c)
        targets[:, 2] = (
            ground
            + (1.0 - smoothstep(self.phase)) * start_height
            + p.lift * lift_profile(self.phase, p.lift_peak)
            - p.touchdown_depth * self.phase
        )
        dt = context.time - self._target_time
        if dt > 0.0:
            blend = min(1.0, dt / p.velocity_filter)
            self._rates += blend * ((targets - self._targets) / dt - self._rates)
        self._targets, self._target_time = targets, context.time
        for k, i in enumerate(TRIPODS[OTHER[self.support]]):
            self.swing[i].setpoint = targets[k]
            self.swing[i].velocity_setpoint = self._rates[k]
