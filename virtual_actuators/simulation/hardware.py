"""The simulated robot as hardware: the callbacks of ``va.run`` on a MuJoCo simulation.

``write_effort`` holds the efforts for one control period and steps the physics; ``va.run``'s
final zero steps once more unless ``write_final=hardware.hold_effort`` takes it.
"""

from __future__ import annotations

from time import perf_counter

import numpy as np

from .conversions import torques_to_ctrl
from .simulator import Simulator


class MujocoHardware:
    """A [`Simulator`][] behind the two callbacks of a hardware control loop.

    Args:
        simulator: The simulation that plays the robot.
        ignore_unactuated: Drop efforts on degrees of freedom no actuator drives (False: an
            error of `write_effort`, as [`Simulator.step`][] raises it).

    Attributes:
        simulator: As given.
        ignore_unactuated: As given.
        efforts_written: Calls of `write_effort` and `hold_effort` (the final zero included).
        physics_time: Wall-clock time spent in the physics steps [s].
    """

    def __init__(self, simulator: Simulator, *, ignore_unactuated: bool = True) -> None:
        self.simulator = simulator
        self.ignore_unactuated = bool(ignore_unactuated)
        self.efforts_written = 0
        self.physics_time = 0.0
        self._data = simulator.data

    def read_state(self) -> tuple[np.ndarray, np.ndarray, float]:
        """``(q, v, time)`` of the simulation (Pinocchio conventions, seconds)."""
        return self.simulator.q, self.simulator.v, float(self._data.time)

    def write_effort(self, tau: np.ndarray) -> None:
        """Hold ``tau`` for one control period (see ``ignore_unactuated``).

        Raises:
            InvalidInputError: ``tau`` of the wrong size or with non-finite entries; an effort
                on an unactuated degree of freedom without ``ignore_unactuated``.
        """
        start = perf_counter()
        self.simulator.step(tau, ignore_unactuated=self.ignore_unactuated)
        self.physics_time += perf_counter() - start
        self.efforts_written += 1

    def hold_effort(self, tau: np.ndarray) -> None:
        """Set the efforts MuJoCo holds (its controls) without stepping: a loop's final zero.

        Raises:
            InvalidInputError: ``tau`` of the wrong size or with non-finite entries; an effort
                on an unactuated degree of freedom without ``ignore_unactuated``.
        """
        model = self.simulator.mujoco_model
        self._data.ctrl[:] = torques_to_ctrl(model, tau, ignore_unactuated=self.ignore_unactuated)
        self.efforts_written += 1

    def __repr__(self) -> str:
        return f"MujocoHardware({self.simulator!r})"


__all__ = ["MujocoHardware"]
