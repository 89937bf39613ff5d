"""The robot's centre of mass and composite inertia, read from Pinocchio for the gait.

Local to the gait layer until the models expose them (``robot.center_of_mass(q)``): one
``pin.Data`` of its own, so the controller's kinematics are not disturbed.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ...models.robot import Robot


class MassModel:
    """Centre of mass and centroidal inertia of a robot (a ``pin.Data`` of its own).

    Args:
        robot: The robot.

    Attributes:
        mass: Total mass [kg].

    """

    def __init__(self, robot: Robot) -> None:
        self.model = robot.model
        self.data = self.model.createData()
        self.mass = float(pin.computeTotalMass(self.model))

    def center_of_mass(self, q: np.ndarray) -> np.ndarray:
        """``(3,)`` world position of the centre of mass [m]."""
        return pin.centerOfMass(self.model, self.data, q, False).copy()

    def centroidal_inertia(self, q: np.ndarray) -> np.ndarray:
        """``(3, 3)`` rotational inertia about the centre of mass, world axes [kg m^2]."""
        pin.ccrba(self.model, self.data, q, np.zeros(self.model.nv))
        return np.array(self.data.Ig.inertia)

    def chain_mass(self, frame: str) -> float:
        """Mass of the moving bodies from the root's first child down to ``frame`` [kg]."""
        joint = self.model.frames[self.model.getFrameId(frame)].parentJoint
        total = 0.0
        while joint > 1:  # 0: universe, 1: the floating base
            total += float(self.model.inertias[joint].mass)
            joint = self.model.parents[joint]
        return total


__all__ = ["MassModel"]
