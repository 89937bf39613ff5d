"""The simulated robot as hardware: the callbacks of ``va.run`` on a MuJoCo simulation.

``read_state`` returns the simulator's ``(q, v, time)``; ``write_effort`` holds the efforts for one
control period and steps the physics. Run the loop with ``realtime=False`` to simulate as fast as
possible, or at the simulator's control rate to watch it in real time.
"""

from __future__ import annotations

import numpy as np

from .simulator import Simulator


class MujocoHardware:
    """A [`Simulator`][] behind the two callbacks of a hardware control loop.

    Args:
        simulator: The simulation that plays the robot.

    Example:
        >>> hardware = MujocoHardware(Simulator(robot))
        >>> va.run(controller, hardware.read_state, hardware.write_effort, rate_hz=1000,
        ...        realtime=False, should_stop=lambda: hardware.simulator.time > 5.0)

    """

    def __init__(self, simulator: Simulator) -> None:
        self.simulator = simulator
        self.efforts_written = 0

    def read_state(self) -> tuple[np.ndarray, np.ndarray, float]:
        """``(q, v, time)`` of the simulation (Pinocchio conventions, seconds)."""
        simulator = self.simulator
        return simulator.q, simulator.v, float(simulator.time)

    def write_effort(self, tau: np.ndarray) -> None:
        """Hold ``tau`` for one control period (efforts on unactuated joints are dropped).

        Raises:
            InvalidInputError: ``tau`` of the wrong size or with non-finite entries.

        """
        self.simulator.step(tau, ignore_unactuated=True)
        self.efforts_written += 1

    def __repr__(self) -> str:
        return f"MujocoHardware({self.simulator!r})"


__all__ = ["MujocoHardware"]
