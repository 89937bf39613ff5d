"""The base state a state estimator gives, in the library's conventions."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Estimate:
    """The state estimated from one [`SensorReading`][virtual_actuators.estimation.SensorReading].

    Attributes:
        time: The reading's time [s].
        q: ``(nq,)`` configuration in Pinocchio's conventions (the free flyer's position in
            the world [m], its orientation as a unit quaternion ``x, y, z, w``, then the joints).
        v: ``(nv,)`` velocity in Pinocchio's conventions (the free flyer's linear and angular
            velocity in its own axes [m/s, rad/s], then the joints).
        contact: Foot frame -> probability that it is in contact, in ``[0, 1]``.
        in_contact: Foot frame -> in contact, the probability with hysteresis.
        covariance: ``(6, 6)`` covariance of the base's position [m] and velocity [m/s] in
            world axes (position first).
    """

    time: float
    q: np.ndarray
    v: np.ndarray
    contact: dict[str, float]
    in_contact: dict[str, bool]
    covariance: np.ndarray
