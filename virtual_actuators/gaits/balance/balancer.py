"""Standing balance for any legged robot: the body on its feet, the rest held by a posture."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ...actuators import ParallelVirtualActuator
from ...components.gains import body_gains, gains, joint_gains
from ...components.gravity import GravityCompensation
from ...components.posture import Posture
from ...components.springs import SpringDamper
from ...control.context import Context
from ...control.state_machine import State, StateMachine
from ...kinematics.snapshot import Snapshot
from ...models.feet import body_frame, find_feet
from ...models.robot import Robot
from ...models.soles import find_sole
from ...models.standing import standing_pose, upper_joints
from ...vocabulary.axes import resolve_frame
from ...vocabulary.scalar import clip, maximum, minimum, select, sqrt
from ...vocabulary.traced import lowerable
from ..base import Gait, SizedSlots, sized_slot


@dataclass(frozen=True)
class BalanceParameters:
    """Constants of [`Balancer`][]: frequencies and damping ratios, not raw gains.

    Every stiffness and damping comes from the robot's own inertia
    ([`gains`][virtual_actuators.components.gains]), so the same figures hold any robot.

    Attributes:
        body_frequency: Natural frequency of the body's translations [rad/s].
        tilt_frequency: Natural frequency of the body's rotations [rad/s].
        tilt_about_feet: Roll and pitch gains from the inertia about the feet instead of the
            centroidal inertia; None: on point feet, not on flat soles.
        body_damping: Damping ratio of the body's translations and rotations.
        posture_frequency: Natural frequency of the posture's joints [rad/s].
        posture_damping: Damping ratio of the posture.
        friction: Friction coefficient of the contact QP's cones.
        sole_margin: Fraction of each sole that the centre of pressure may use.
        support_margin: Fraction of the support's half extents that the body's request's
            centre of pressure may use.
        min_normal: Least normal force of a contact, as a fraction of its share of the weight.
        yield_weight: Weight of the body's moments against its horizontal forces when both give
            way (smaller: the body tilts more and drifts less).
        height_ratio: Hip-to-foot height of a generated standing pose
            ([`standing_pose`][virtual_actuators.models.standing.standing_pose]).
        push_duration: How long a ``--push`` lasts [s].
        control_rate: The controller's rate [Hz], which bounds the gains.
    """

    body_frequency: float = 2.0 * math.pi * 1.0
    tilt_frequency: float = 2.0 * math.pi * 1.5
    tilt_about_feet: bool | None = None
    body_damping: float = 1.0
    posture_frequency: float = 2.0 * math.pi * 3.0
    posture_damping: float = 1.0
    friction: float = 0.6
    sole_margin: float = 0.9
    support_margin: float = 0.9
    min_normal: float = 0.05
    yield_weight: float = 1.0
    height_ratio: float = 0.9
    push_duration: float = 0.1
    control_rate: float = 1000.0


#: Axes of the body actuator, world-aligned.
BODY_AXES = ("x", "y", "z", "rx", "ry", "rz")


def support_limited(
    wrench: Sequence, lever: Sequence, reach: Sequence, friction: object, moment_weight: object
) -> list:
    """``wrench`` moved to the nearest one the support holds; floats or traced.

    Its centre of pressure is kept within ``reach`` of the support's centre and its horizontal
    force within ``friction`` times the vertical one; force and moment share each change (least
    squares, weighted 1 : ``moment_weight``).

    Args:
        wrench: ``(6,)`` force and moment on the body, world axes, about its origin [N, N m].
        lever: The body's origin minus the support's centre, world axes [m].
        reach: The support's half extents along world x, y, margins taken [m].
        friction: Largest horizontal over vertical force [-].
        moment_weight: The moments' weight against the forces' in the shared change [-].

    Returns:
        The limited wrench ``(6,)``.
    """
    fx, fy, fz, mx, my, mz = wrench
    lx, ly, lz = lever
    normal = maximum(fz, 0.0)
    horizontal = sqrt(fx * fx + fy * fy)
    over = horizontal > friction * normal
    scale = select(over, friction * normal / maximum(horizontal, 1e-300), 1.0)
    fx, fy = select(over, fx * scale, fx), select(over, fy * scale, fy)
    about_x = mx + (ly * fz - lz * fy)  # the moment about the support's centre
    about_y = my + (lz * fx - lx * fz)
    bound_x, bound_y = reach[1] * normal, reach[0] * normal  # |M_x| by y, |M_y| by x
    miss_x = about_x - clip(about_x, -bound_x, bound_x)
    miss_y = about_y - clip(about_y, -bound_y, bound_y)
    # M_x moves with -height F_y, M_y with +height F_x: each miss shared, weighted
    spread = lz * lz + 1.0 / moment_weight
    share_x, share_y = miss_x / spread, miss_y / spread
    fy = select(miss_x != 0.0, fy - share_x * -1.0 * lz, fy)
    mx = select(miss_x != 0.0, mx - share_x / moment_weight, mx)
    fx = select(miss_y != 0.0, fx - share_y * 1.0 * lz, fx)
    my = select(miss_y != 0.0, my - share_y / moment_weight, my)
    return [fx, fy, fz, mx, my, mz]


class SupportedSpring(SizedSlots, SpringDamper):
    """The body's spring-damper, its request kept within what the support can produce.

    Args:
        axes: The body's six axes.
        stiffness: Per axis [N/m, N m/rad].
        damping: Per axis [N s/m, N m s/rad].
        name: Label used in reports.
    """

    SIZES = {"lever": 3, "reach": 2, "friction": 1, "moment_weight": 1}
    SLOTS = (*SpringDamper.SLOTS, *SIZES)
    FINITE = False  # the reach and the friction are unbounded until the first tick

    def __init__(
        self, axes: Sequence[str], stiffness: object, damping: object, name: str | None = None
    ) -> None:
        super().__init__(axes, stiffness, damping, name=name)
        self.lever = np.zeros(3)
        self.reach = np.full(2, np.inf)
        self.friction = np.inf
        self.moment_weight = 1.0

    lever = sized_slot("lever", "The body's origin minus the support's centre, world axes [m].")
    reach = sized_slot("reach", "The support's half extents along world x, y, margins taken [m].")
    friction = sized_slot("friction", "Largest horizontal over vertical force [-].", scalar=True)
    moment_weight = sized_slot(
        "moment_weight", "The moments' weight against the forces' [-].", scalar=True
    )

    def compute_wrench(self, position: np.ndarray, velocity: np.ndarray, time: float) -> np.ndarray:
        """The spring-damper's wrench, then limited (`support_limited`)."""
        wrench = np.asarray(super().compute_wrench(position, velocity, time), dtype=float)
        limited = support_limited(
            wrench.tolist(), self._lever.tolist(), self._reach.tolist(),
            float(self._friction[0]), float(self._moment_weight[0]),
        )  # fmt: skip
        return np.array(limited)

    def traced_wrench(self, slots, position: tuple, velocity: tuple, time: object) -> list:
        """The spring-damper's traced wrench, then limited (a plan's ops)."""
        wrench = super().traced_wrench(slots, position, velocity, time)
        return support_limited(
            wrench, slots["lever"], slots["reach"], slots["friction"][0],
            slots["moment_weight"][0],
        )  # fmt: skip


class Balancer(Gait):
    """A legged robot standing on all its feet.

    Args:
        robot: A floating-base legged robot (sole frames are added to its model for flat feet).
        parameters: The constants.
        feet: Foot frames (default: found on the robot).

    Attributes:
        tick_rate: The derived gains' per-tick rate before the control rate's bound.

    Raises:
        FrameNotFoundError: No feet found, or a name in ``feet`` that is not a frame (with
            close matches).
        SingularConfigurationError: No standing pose can be built.
    """

    def __init__(
        self,
        robot: Robot,
        parameters: BalanceParameters | None = None,
        feet: tuple[str, ...] | None = None,
    ) -> None:
        parameters = parameters or BalanceParameters()
        if feet is None:
            found = find_feet(robot)
            body, feet = found.body, found.feet
        else:
            body, feet = body_frame(robot.model, True), tuple(feet)
            for foot in feet:
                resolve_frame(robot.model, foot, "foot")
        self.parameters, self.body, self.feet = parameters, body, tuple(feet)
        self.flat = len(feet) == 2
        self.contacts, soles = self._contact_frames(robot, feet) if self.flat else (feet, None)
        # the centre of mass over the soles' centres (robots without a standing pose)
        self.q0 = standing_pose(robot, self.contacts, parameters.height_ratio)
        super().__init__(robot)
        self.contact_frames = self.contacts
        self.soles = soles or {}
        self._weight = robot.mass * 9.81  # [N]
        self.spring = self._body(soles)
        active = ["body", *self._posture(feet), "gravity"]
        self.gravity = GravityCompensation(robot)
        self.controller.add("gravity", self.gravity)  # in the sum, before the clip
        signs = ((1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0))
        self._corners = tuple(  # each support frame's sole corners (x, y) in its own axes [m]
            tuple((sx * hx, sy * hy) for sx, sy in signs)
            for hx, hy in (self.soles.get(frame, (0.0, 0.0)) for frame in self.contacts)
        )
        # the base's weight is the feet's to carry: its efforts are zero (a limp free flyer)
        base = (robot.model.names[1],) if robot.floating_base else ()
        stand = State("stand", active=active, support=self.contacts, on_update=self._update,
                      limp=base)  # fmt: skip
        self._finish(StateMachine([stand], [], "stand"))
        (self.tick_rate,) = self._bound_gains(parameters.control_rate)

    def _body(self, soles: dict[str, tuple[float, float]] | None) -> SupportedSpring:
        """The body actuator on the contact QP with its spring-damper; returns the spring."""
        robot, parameters = self.robot, self.parameters
        actuator = ParallelVirtualActuator(
            robot,
            self.body,
            list(self.contacts),
            "world",
            BODY_AXES,
            contact="flat" if self.flat else "point",
            friction=parameters.friction,
            min_normal=parameters.min_normal * self._weight / len(self.contacts),
            torque_limits=True,
            soles=soles,
            weights={"rx": parameters.yield_weight, "ry": parameters.yield_weight},
        )
        damping_ratio, q0 = parameters.body_damping, self.q0
        move = body_gains(robot, parameters.body_frequency, damping_ratio, BODY_AXES, q0)
        tilt = body_gains(robot, parameters.tilt_frequency, damping_ratio, BODY_AXES, q0)
        stiffness = np.concatenate((move.stiffness[:3], tilt.stiffness[3:]))
        damping = np.concatenate((move.damping[:3], tilt.damping[3:]))
        about_feet = parameters.tilt_about_feet
        if about_feet or (about_feet is None and not self.flat):  # the inertia about the feet
            data = robot.model.createData()
            pin.framesForwardKinematics(robot.model, data, q0)
            ids = (robot.model.getFrameId(frame) for frame in self.contacts)
            lowest = min(float(data.oMf[i].translation[2]) for i in ids)  # [m]
            height = float(robot.center_of_mass(q0)[2] - lowest)
            pendulum = gains(robot.mass * height**2, parameters.tilt_frequency, damping_ratio)
            stiffness[3:5] += pendulum.stiffness
            damping[3:5] += pendulum.damping
        spring = SupportedSpring(BODY_AXES, stiffness, damping, name="body")
        spring.friction = 0.9 * parameters.friction
        spring.moment_weight = parameters.yield_weight
        self.controller.add("body", actuator, [spring], method="qp")
        return spring

    def _posture(self, feet: tuple[str, ...]) -> list[str]:
        """A posture on every driven joint off the legs; the attachments' names."""
        robot, parameters = self.robot, self.parameters
        upper = upper_joints(robot, feet)
        if not upper:
            return []
        frequency, ratio = parameters.posture_frequency, parameters.posture_damping
        gains = joint_gains(robot, upper, frequency, ratio, self.q0)
        self.controller.add("posture", Posture(upper, gains.stiffness, gains.damping))
        return ["posture"]

    @lowerable
    def _update(self, context: Context) -> None:
        """The weight at the centre of mass as the spring's feed-forward; the support's figures."""
        bx, by, bz = context.frame_position(self.body)
        cx, cy, _ = context.center_of_mass()
        lx, ly, weight = cx - bx, cy - by, self._weight
        self.spring.force = (0.0, 0.0, weight, ly * weight, -lx * weight, 0.0)  # lever x weight
        self._support(context, (bx, by, bz))

    def _support(self, context: Context, body: tuple) -> None:
        """The spring's support figures: lever from the feet's centre, half extents (x, y)."""
        xs, ys, z_sum = [], [], 0.0
        for frame, corners in zip(self.contacts, self._corners, strict=True):
            rotation, (ox, oy, oz) = context.placement(frame)
            (r00, r01, _), (r10, r11, _), (r20, r21, _) = rotation
            for hx, hy in corners:  # a corner (hx, hy, 0) in the frame's axes, to the world
                xs.append(r00 * hx + r01 * hy + ox)
                ys.append(r10 * hx + r11 * hy + oy)
                z_sum = z_sum + (r20 * hx + r21 * hy + oz)
        low_x, high_x, low_y, high_y = xs[0], xs[0], ys[0], ys[0]
        for x, y in zip(xs[1:], ys[1:], strict=True):
            low_x, high_x = minimum(low_x, x), maximum(high_x, x)
            low_y, high_y = minimum(low_y, y), maximum(high_y, y)
        centre = (0.5 * (low_x + high_x), 0.5 * (low_y + high_y), z_sum / len(xs))
        self.spring.lever = tuple(b - c for b, c in zip(body, centre, strict=True))
        margin = self.parameters.support_margin
        self.spring.reach = (0.5 * (high_x - low_x) * margin, 0.5 * (high_y - low_y) * margin)

    def _contact_frames(
        self, robot: Robot, feet: tuple[str, ...]
    ) -> tuple[tuple[str, ...], dict[str, tuple[float, float]]]:
        """A frame at the centre of each sole (added to the model), with its half sizes."""
        model, names, soles = robot.model, [], {}
        for foot in feet:
            sole = find_sole(robot, foot)
            name = f"{foot}_sole_centre"
            if not model.existFrame(name):
                parent = model.frames[model.getFrameId(foot)]
                centre = pin.SE3(np.eye(3), np.array([*sole.centre, sole.height]))
                placement = parent.placement * centre
                kind = pin.FrameType.OP_FRAME
                model.addFrame(
                    pin.Frame(name, parent.parentJoint, model.getFrameId(foot), placement, kind)
                )
            halves = 0.5 * (np.array(sole.upper) - np.array(sole.lower))
            soles[name] = tuple(float(h) * self.parameters.sole_margin for h in halves)
            names.append(name)
        robot.caches.clear()  # the kinematic tree is rebuilt with the new frames
        return tuple(names), soles

    def initial_configuration(self) -> np.ndarray:
        """The standing pose (the SRDF's, or built from the legs)."""
        return self.q0.copy()

    def nominal_height(self) -> float:
        """The body's height above the feet in the standing pose [m]."""
        return float(self.q0[2])

    def start(self, q: np.ndarray) -> None:
        """Hold the body's pose and the posture found at ``q`` (the simulation's start)."""
        sensor = self.controller.attachments["body"].sensor
        snapshot = Snapshot(self.robot, q)
        self.spring.setpoint = sensor.position(snapshot)
        self.controller.reset(self.machine.current.active, snapshot, 0.0)
