"""The standing balancer's constants: frequencies and damping ratios, not raw gains.

Every stiffness and damping comes from the robot's own inertia
([`gains`][virtual_actuators.components.gains]), so the same figures hold any robot.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class BalanceParameters:
    """Constants of [`Balancer`][].

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
