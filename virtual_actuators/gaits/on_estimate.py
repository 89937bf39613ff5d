"""A walk on the estimate: the gait reads a `LeggedEstimator` fed by the simulated sensors."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..estimation.legged import LeggedEstimator
from ..estimation.tuning import EstimatorTuning
from ..experiments.estimation_score import EstimationScore
from .attitude import attitude_and_velocity


class OnEstimate:
    """What an `Episode` does to run its gait on the estimate instead of the simulator's state.

    Attributes:
        estimation: With `use_estimator`, what scores the estimator the gait reads; else None.
    """

    estimation: EstimationScore | None = None

    def use_estimator(self, feet: tuple[str, ...] | None = None) -> LeggedEstimator:
        """Run the gait on a `LeggedEstimator` fed by the simulator's sensors (not its state).

        The estimator starts from the simulator's state now; the truth only scores it. On a
        terrain that is not flat it does not assume level ground (``level_ground=False``).

        Args:
            feet: The estimator's feet (None: the gait's contact frames, else found).
        """
        robot = self.simulator.robot
        feet = feet or tuple(self.gait.contact_frames) or None
        tuning = EstimatorTuning(level_ground=self.level is not None)  # Episode.level: flat's
        estimator = LeggedEstimator(robot, feet=feet, tuning=tuning)
        estimator.reset(self.simulator.q, self.simulator.v)
        self.estimation = EstimationScore(estimator, self.simulator, self.record_every)
        return estimator

    def contact_switches(self) -> Mapping[str, bool]:
        """The gait's contact switches: MuJoCo's, or the estimator's ``in_contact``."""
        frames = self.gait.contact_frames
        if self.estimation is None:
            return self.simulator.contact_switches(frames)
        estimate = self.estimation.estimator.last
        contact = {} if estimate is None else estimate.in_contact
        return {frame: contact.get(frame, True) for frame in frames}

    def observe_truth(self, q: np.ndarray, v: np.ndarray) -> None:
        """The true state after a tick on the estimate: what the fall test and the log read."""
        self.attitude = attitude_and_velocity(q, v)  # what Episode.fallen reads

