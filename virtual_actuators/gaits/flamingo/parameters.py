"""Blind slope walking's gait variables (the seed's Table 2) and component constants."""

from __future__ import annotations

import math
from dataclasses import dataclass

from ...vocabulary.scalar import minimum, tan


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
