"""Gait variables and virtual component constants of the hexapod's tripod gait."""

from __future__ import annotations

from dataclasses import dataclass

from ..base import check_distribution


@dataclass
class HexapodParameters:
    """Gait variables and virtual component constants (SI units).

    Attributes:
        height: Body height set point above the ground under the support feet [m].
        stiffness_z: [N/m].
        damping_z: [N s/m].
        stiffness_attitude: Roll, pitch springs [N m/rad].
        damping_attitude: Roll, pitch, yaw dampers [N m s/rad].
        damping_xy: Dampers along and across the heading [N s/m].
        step_length: The body's travel over the support tripod per stance, along the heading [m].
        step_width: The same across the heading [m] (between: the ellipse of the two).
        max_stance_time: A stance ends after this long even if the body has not travelled a
            step [s].
        double_support_time: All six feet support between two tripods [s].
        touchdown_phase: From this swing phase on (0 to 1), the swing tripod's three contact
            switches all closed end the stance.
        acceleration: The velocity set point follows the command at most this fast [m/s^2].
        lift: Swing foot lift [m].
        lift_peak: Phase of the swing (0 to 1) at which the foot is highest.
        swing_stiffness: Swing-foot springs (x, y, z), body axes [N/m].
        swing_damping: Swing-foot dampers (x, y, z) [N s/m].
        touchdown_depth: How far below the support feet's level the swing set point ends [m].
        placement_gain: Raibert term: the landing point moves this many seconds times the
            velocity error further [s].
        velocity_filter: Time constant of the low-pass filters on the measured body velocity
            and the swing set points' velocity [s].
        distribution: ``"qp"`` or ``"partitioned"``.
        friction: Friction coefficient of the pyramid ``|f_x|, |f_y| <= mu f_z`` [-].
        min_normal: Least normal force of a support foot in the distribution [N].
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
    step_length: float = 0.09
    step_width: float = 0.07
    max_stance_time: float = 0.35
    double_support_time: float = 0.03
    touchdown_phase: float = 0.5
    acceleration: float = 2.0
    lift: float = 0.04
    lift_peak: float = 0.4
    swing_stiffness: tuple[float, float, float] = (800.0, 800.0, 800.0)
    swing_damping: tuple[float, float, float] = (12.0, 12.0, 12.0)
    touchdown_depth: float = 0.01
    placement_gain: float = 0.05
    velocity_filter: float = 0.02
    distribution: str = "qp"
    friction: float = 0.5
    min_normal: float = 3.0
    pendulum_weights: tuple[float, float, float] = (100.0, 1.0, 300.0)
    pendulum_effort: float = 0.01
    pendulum_fall: float = 0.6

    def __post_init__(self) -> None:
        check_distribution(self.distribution)
