"""Turkey walking's gait variables and virtual component constants."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass
class TurkeyParameters:
    """Gait variables and virtual component constants of turkey walking (SI units).

    Attributes:
        speed: Dogtrack bunny speed [m/s].
        height: Granny walker height set point, hip above the ground [m].
        pitch: Granny walker pitch set point [rad].
        stiffness_z: [N/m].
        damping_z: [N s/m].
        stiffness_pitch: [N m/rad].
        damping_pitch: [N m s/rad].
        bunny_damping: Dogtrack bunny damper [N s/m].
        bunny_limit: Largest bunny force [N].
        min_normal_force: Least normal force of each foot in double support [N].
        weight: Feed-forward on z [N]; None: total mass times g.
        over_distance: "Body nearly over the foot": body x minus front foot x above this [m].
        away_distance: "Body away from the stance foot": body x minus stance foot x above this
            [m].
        swing_reach: Swing foot x relative to the body at the end of the swing [m].
        lift: Swing foot lift above the ground [m].
        lift_peak: Phase of the swing (0 to 1) at which the foot is highest.
        swing_stiffness: Swing-leg linkage springs (x, z) [N/m].
        swing_damping: Swing-leg linkage dampers (x, z) [N s/m].
        touchdown_depth: How far below the ground the swing set point ends [m].
        buffer_delay: Time the swing leg stays limp in the buffer states [s].
        foot_radius: Height of the foot frame above the ground when in contact [m].
        distribution: ``"partitioned"`` (the seed's matched hip torques) or ``"qp"`` (the same
            with friction pyramids and least normal forces as inequalities).
        friction: Friction coefficient assumed by ``distribution="qp"``.
    """

    speed: float = 0.5
    height: float = 0.54
    pitch: float = 0.0
    stiffness_z: float = 1500.0
    damping_z: float = 150.0
    stiffness_pitch: float = 200.0
    damping_pitch: float = 20.0
    bunny_damping: float = 80.0
    bunny_limit: float = 60.0
    min_normal_force: float = 10.0
    weight: float | None = None
    over_distance: float = -0.075
    away_distance: float = 0.075
    swing_reach: float = 0.19
    lift: float = 0.05
    lift_peak: float = 0.35
    swing_stiffness: tuple[float, float] = (400.0, 600.0)
    swing_damping: tuple[float, float] = (20.0, 25.0)
    touchdown_depth: float = 0.02
    buffer_delay: float = 0.04
    foot_radius: float = 0.02
    distribution: str = "partitioned"
    friction: float = 0.6
