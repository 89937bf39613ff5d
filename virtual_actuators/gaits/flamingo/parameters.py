"""Blind slope walking's gait variables (the seed's Table 2) and component constants."""

from __future__ import annotations

import math
from dataclasses import dataclass

from ...vocabulary.scalar import minimum, tan


@dataclass
class FlamingoParameters:
    """Gait variables (the seed's Table 2) and component constants, SI units.

    The defaults are the seed's values except four, which make the walk hold 0.3 to 0.5 m/s on
    ``profile-one`` and ``profile-two`` with every seeded start (the seed's fall at 0.5 m/s on
    ``profile-one``; at 0.6 m/s the defaults fall there too, 2 starts of 3): ``stance_slope``,
    a shorter swing, a faster push-down and longer steps; `seed` gives the seed's set.

    Attributes:
        speed: Desired horizontal hip speed ``xdot_d`` [m/s].
        pitch: Desired body pitch ``theta_d`` [rad].
        step_length: Desired step length ``s_l`` [m].
        transition_distance: ``l_t``: double support ends when the hip is this far behind the
            front ankle [m].
        lift: Swing lift ``h_l`` above the global slope [m].
        k_height: Fraction of the height limit used as the hip height set point.
        leg_length: ``l1 + l2``, hip to ankle [m].
        stiffness_z, damping_z: Granny walker on height [N/m], [N s/m].
        min_lift: Fraction of the weight below which the granny walker's z force never goes:
            its spring-damper part is saturated at ``(1 - min_lift) * weight`` both ways, so
            that a dropping height set point never pulls the body down (legs only push) and
            the feet keep the normal force the bunny needs.
        stiffness_pitch, damping_pitch: Granny walker on pitch [N m/rad], [N m s/rad].
        bunny_damping: ``b_x`` [N s/m] (Table 2's "2" read as 200).
        level_single_support: Hold the height set point in single support (climb in double
            support, where the legs can pay for it), instead of following the global slope.
        height_rate: Fastest change of the height set point [m/s] (no step in the spring).
        equal_hip_torques: Double support with the seed's matched hip torques (eq. 12). The
            default (False) takes the minimum-norm distribution instead: with matched hip
            torques each leg's force runs close to its hip-ankle line, so the bunny cannot
            brake hard enough on slopes and the speed runs away (measured: falls on the 20
            degree downslope of ``profile-one``; crosses it with the minimum-norm split).
        min_normal_force: In double support, each foot pushes at least this much on the ground,
            normal to its sole [N]; the bunny's force is scaled down when it would make a foot
            pull.
        friction: Friction coefficient assumed for the feet: in double support each foot's
            force stays in this cone around its sole's normal (the sole lies on the local
            slope, known from the joint angles); the bunny's force is scaled down otherwise.
        swing_time: Planned duration of the swing [s].
        lift_peak: Phase of the swing (0 to 1) at which the foot is highest above its path.
        swing_stiffness: Swing linkage (x, z, pitch) [N/m, N/m, N m/rad].
        swing_damping: Swing linkage (x, z, pitch) [N s/m, N s/m, N m s/rad].
        min_speed: Double support ends only if the hip, vaulting over the front ankle as a
            linear inverted pendulum (``xdot^2 - g / h * d^2``, ``d`` its distance behind the
            ankle), would pass over the ankle at least this fast [m/s] (so that a robot
            starting from rest, or slowed down, does not lift a foot too early). Keep it well
            below ``speed``, or double support lasts until the hip passes the front ankle.
        max_overspeed: Double support also waits, while the hip is still behind the front
            ankle (where the bunny can brake), until that vault speed is at most ``speed``
            plus this [m/s]; None: no upper bound. With limp ankles, single support only
            accelerates the body once it is over the ankle: speed is won or lost in double
            support.
        step_gain: Touchdown target moves ``step_gain * (xdot - speed)`` beyond the step
            length (clipped to -40 % / +60 % of it) [s]: a faster hip steps further, which
            lengthens the braking double support; a premature landing on an upslope (a short
            step) would otherwise feed the speed up step after step.
        swing_hip_travel: The swing foot reaches forward no faster than the hip travels: its
            progress is at most the hip's displacement since lift-off over this distance [m]
            (None: time only). A hip slowed by a slope then does not lose its momentum to a
            swing leg rushing forward (the seed's linkage "mirrors the stance leg").
        push_speed: Speed of the swing set point going down after the swing time [m/s].
        weight: Feed-forward on z [N]; None: total mass times g.
        stance_slope: At lift-off, if the stance sole (its pitch from the joint angles) lies on
            a lower slope than the global slope, take the sole's slope as the global slope (the
            line through the stance ankle): the swing is planned, and the height set, for the
            ground just under the stance foot. After a convex corner (upslope to level) the
            global slope still points up, the swing would aim above the ground and land late,
            and every late instant of single support over a limp ankle feeds the speed (an
            early landing is handled, section 6.2). False: the seed's global slope only.
        distribution: How double support shares the body's wrench: ``"partitioned"`` (the
            minimum-norm split, the bunny's force scaled down when a foot would pull or leave
            its friction cone) or ``"qp"`` (the cone and the least normal force as
            inequalities; x gives way first); both about each sole's normal, see
            ``sole_normals``.
        sole_normals: The cones' normals are the feet frames' z axes, read every tick (a
            limp-ankled foot lies flat on the slope; the actuator's ``normals="frames"``);
            False: world z.
        qp_min_normal_force: ``distribution="qp"``: each foot's least normal force [N] (None:
            ``min_normal_force``), a hard bound: set above the forces the quasi-static split
            does not see (foot and leg inertia at touchdown): 10 and 20 N let feet unload. A
            trade: at 0.6 m/s the back leg's least force pushes the body on, and it falls.
        qp_friction: ``distribution="qp"``: the QP's cone coefficient (None: ``friction``). The
            QP uses a cone to its edge when the bunny asks for more than the feet can give, so
            its margin below the ground's (MuJoCo: 1) absorbs those forces: 0.45 beat 0.6.
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
        """The seed's Table 2 values and its global slope only (0.28 m steps, 0.4 s swings).

        They walk at the seed's 0.4 m/s but fall at 0.5 m/s on ``profile-one``: the defaults
        differ in four places (``stance_slope``, ``swing_time`` 0.34 s, ``push_speed``
        0.8 m/s, ``step_length`` 0.32 m) and walk 0.3 to 0.5 m/s on both profiles.
        """
        seed = {"step_length": 0.28, "swing_time": 0.4, "push_speed": 0.3, "stance_slope": False}
        return cls(**{**seed, **changes})

    def height_limit(self, slope: float) -> float:
        """Hip height limit above the global slope, the smaller of eq. 15 and eq. 16 [m].

        On a float or a traced slope (a compiled plan's ops).

        Eq. 15: the back leg at the transition plane, ``r = s_l - l_t`` behind the hip:
        ``sqrt(L^2 - r^2) - r tan(beta)``. Eq. 16: the swing leg touching down ``r1 = s_l / 2``
        ahead of the hip: ``sqrt(L^2 - r1^2) + r1 tan(beta)``.
        """
        length = self.leg_length
        r = self.step_length - self.transition_distance
        r1 = 0.5 * self.step_length
        upslope = math.sqrt(length**2 - r**2) - r * tan(slope)
        downslope = math.sqrt(length**2 - r1**2) + r1 * tan(slope)
        return minimum(upslope, downslope)

    def hip_height(self, slope: float) -> float:
        """Hip height set point ``k_height * h_limit`` above the global slope [m]."""
        return self.k_height * self.height_limit(slope)
