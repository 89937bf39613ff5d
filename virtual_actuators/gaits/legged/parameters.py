"""A legged gait's dimensionless choices and the physical-unit gains derived from them."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...components.gains import body_gains, gains
from ...models.robot import Robot
from ...vocabulary.arguments import check_number
from ..base import check_distribution

GRAVITY = 9.81  # [m/s^2]


@dataclass
class LeggedParameters:
    """Choices of a legged gait (SI units; see `derive_gains` for the gains).

    Attributes:
        frequency: Natural frequency of the body's height, roll and pitch springs [Hz].
        damping_ratio: Their damping ratio [-].
        velocity_time: Time constant of the x, y and yaw-rate dampers toward the command [s].
        swing_frequency: Natural frequency of a swing foot's spring on its leg's mass [Hz].
        swing_damping_ratio: Its damping ratio [-].
        swing_time: Duration of a swing in units of ``sqrt(h / g)`` [-]; None: the pattern's.
        double_support_time: All feet down between two swings, in the same units [-].
        max_swing: A swing ends after this many swing times even without touchdown [-].
        touchdown_phase: From this swing phase on, the swing feet all touching end it [-].
        lift: Swing height as a fraction of the standing height ``h`` [-].
        lift_peak: Phase of the swing at which the foot is highest [-].
        touchdown_depth: How far below the ground the swing ends, fraction of ``h`` [-].
        reach: A foothold lies within this fraction of ``h`` of the foot's nominal place [-].
        placement_gain: The foothold moves this many ``sqrt(h / g)`` times the velocity error
            further [-]; 1 is the capture point.
        integral_time: The footholds (and the yaw damper's set point) also move by the
            velocity (yaw rate) error's integral over this many ``sqrt(h / g)`` [-].
        integral_limit: Those integrals stay within this many ``sqrt(g h)`` (velocity) and
            this many ``1 / sqrt(h / g)`` (yaw rate) [-].
        acceleration: The velocity set point follows the command at most this fast, in g [-].
        distribution: ``"qp"`` or ``"partitioned"``.
        friction: The distribution's pyramid ``|f_t| <= mu f_n`` [-].
        min_normal: Least normal force of a support foot, a fraction of the weight per foot [-].
        give_way: Axes along which the body's request gives way just enough to become
            producible (and first in the QP); ``()``: left to the distribution.
        stand_time: Standing on all feet before the first swing [s].
        posture_frequency: Natural frequency of the posture holding the joints off the legs [Hz].
        posture_damping_ratio: Its damping ratio [-].
        control_rate: The controller's rate [Hz], which bounds the derived gains.
    """

    frequency: float = 2.5
    damping_ratio: float = 1.0
    velocity_time: float = 0.05
    swing_frequency: float = 10.0
    swing_damping_ratio: float = 0.7
    swing_time: float | None = None
    double_support_time: float = 0.1
    max_swing: float = 1.2
    touchdown_phase: float = 0.6
    lift: float = 0.15
    lift_peak: float = 0.4
    touchdown_depth: float = 0.02
    reach: float = 0.6
    placement_gain: float = 1.0
    integral_time: float = 4.0
    integral_limit: float = 0.3
    acceleration: float = 0.2
    distribution: str = "qp"
    friction: float = 0.5
    min_normal: float = 0.05
    give_way: tuple[str, ...] = ("x", "y")
    stand_time: float = 0.2
    posture_frequency: float = 5.0
    posture_damping_ratio: float = 1.0
    control_rate: float = 1000.0

    def __post_init__(self) -> None:
        check_distribution(self.distribution)
        check_number(self.control_rate, "control_rate [Hz]", positive=True)


@dataclass(frozen=True)
class LeggedGains:
    """The gains in physical units (see `derive_gains`).

    Attributes:
        height: Standing height ``h`` of the body above its feet [m].
        time_scale: ``sqrt(h / g)`` [s].
        stiffness_z: [N/m].
        damping_z: [N s/m].
        stiffness_attitude: Roll, pitch [N m/rad].
        damping_attitude: Roll, pitch, yaw [N m s/rad].
        damping_xy: Along and across the heading [N s/m].
        swing_stiffness: Per foot [N/m].
        swing_damping: Per foot [N s/m].
    """

    height: float
    time_scale: float
    stiffness_z: float
    damping_z: float
    stiffness_attitude: tuple[float, float]
    damping_attitude: tuple[float, float, float]
    damping_xy: tuple[float, float]
    swing_stiffness: tuple[float, ...]
    swing_damping: tuple[float, ...]


def derive_gains(
    parameters: LeggedParameters,
    robot: Robot,
    q: np.ndarray,
    leg_masses: tuple[float, ...],
    height: float,
) -> LeggedGains:
    """Stiffness ``m w^2`` and damping ``2 zeta m w`` per axis; dampers ``m / tau``.

    Masses are the robot's, inertias its centroidal inertia at ``q`` ([`body_gains`][]).

    Args:
        parameters: The choices.
        robot: The robot.
        q: Its standing configuration.
        leg_masses: Mass of each foot's leg [kg].
        height: Standing height of the body above its feet [m].
    """
    p = parameters
    w = 2.0 * math.pi * p.frequency
    body = body_gains(robot, w, p.damping_ratio, ("z", "rx", "ry"), q)
    # a damper of time constant tau on an inertia m: m / tau (the inertias: gains at 1 rad/s)
    mass, _, yaw_inertia = body_gains(robot, 1.0, 0.0, ("x", "y", "rz"), q).stiffness
    swing = gains(leg_masses, 2.0 * math.pi * p.swing_frequency, p.swing_damping_ratio)
    return LeggedGains(
        height=height,
        time_scale=math.sqrt(height / GRAVITY),
        stiffness_z=float(body.stiffness[0]),
        damping_z=float(body.damping[0]),
        stiffness_attitude=(float(body.stiffness[1]), float(body.stiffness[2])),
        damping_attitude=(
            float(body.damping[1]), float(body.damping[2]), float(yaw_inertia) / p.velocity_time
        ),
        damping_xy=(float(mass) / p.velocity_time, float(mass) / p.velocity_time),
        swing_stiffness=tuple(swing.stiffness.tolist()),
        swing_damping=tuple(swing.damping.tolist()),
    )


def leg_mass(robot: Robot, frame: str) -> float:
    """Mass of the moving bodies from the floating base's first child down to ``frame`` [kg]."""
    model = robot.model
    joint = model.frames[model.getFrameId(frame)].parentJoint
    total = 0.0
    while joint > 1:  # 0: universe, 1: the floating base
        total += float(model.inertias[joint].mass)
        joint = model.parents[joint]
    return total
