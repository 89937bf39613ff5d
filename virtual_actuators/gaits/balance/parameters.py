"""The standing balancer's constants: frequencies and damping ratios, not raw gains.

Every stiffness and damping comes from the robot's own inertia
([`gains`][virtual_actuators.components.gains]): the body's translations from its mass, its
rotations from its centroidal inertia, the posture's joints from the joint-space inertia. The
same figures then hold a 2.5 kg quadruped and a 100 kg humanoid.
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
        tilt_about_feet: Roll and pitch gains from the inertia about the feet (the centroidal
            inertia plus mass times the centre of mass's height squared) instead of the
            centroidal inertia alone; None: on point feet (a quadruped's body leans on its
            legs' spread), not on flat soles (a humanoid's pelvis gives way to a push, a hip
            strategy).
        body_damping: Damping ratio of the body's translations and rotations.
        posture_frequency: Natural frequency of the posture's joints (arms, head, torso)
            [rad/s].
        posture_damping: Damping ratio of the posture.
        friction: Friction coefficient of the contact QP's cones.
        sole_margin: Fraction of each sole (from its collision geometry) that the centre of
            pressure may use.
        support_margin: Fraction of the support's half extents (the soles' rectangle, or the
            feet's) within which the body's request keeps its centre of pressure.
        min_normal: Least normal force of a contact, as a fraction of its share of the weight.
        yield_weight: Weight of the body's moments against its horizontal forces (1) when a
            push asks for more than the support allows: both give way, in this proportion
            (smaller: the body tilts more and drifts less).
        height_ratio: Hip-to-foot height of a generated standing pose (robots without an SRDF
            pose), see [`standing_pose`][virtual_actuators.models.standing.standing_pose].
        push_duration: How long a ``--push`` lasts [s].
        control_rate: The rate the controller runs at [Hz]: the body's and the posture's gains
            are bounded so that they change a velocity by at most half of it per tick
            ([`tick_rate`][virtual_actuators.control.tick_rate]).
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
