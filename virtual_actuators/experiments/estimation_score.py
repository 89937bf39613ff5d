"""An estimator's estimate scored against the simulator's truth, tick by tick."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from ..estimation.legged import LeggedEstimator
from ..simulation.simulator import Simulator
from .plot_panels import new_figure, set_heading

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: The estimate's channels in a walk's JSON (world frame, estimated base).
ESTIMATE_CHANNELS = ("t", "x", "y", "z", "roll", "pitch", "yaw", "vx", "vy", "vz")
#: The velocity error counts after this long (the filter settling from its reset) [s].
SETTLE_TIME = 1.0


@dataclass(frozen=True)
class EstimationSummary:
    """How far an estimate was from the truth over a run.

    Attributes:
        velocity_error_rms_mps: RMS of the base's horizontal velocity error after `SETTLE_TIME`
            [m/s] (world axes).
        height_error_rms_m: RMS of the base's height error [m].
        yaw_drift_rad: The yaw error at the end [rad] (absolute).
        position_drift_m: The horizontal position error at the end [m].
        contact_agreement: Fraction of ticks on which every foot's ``in_contact`` equals
            MuJoCo's contact.
    """

    velocity_error_rms_mps: float
    height_error_rms_m: float
    yaw_drift_rad: float
    position_drift_m: float
    contact_agreement: float

    def to_dict(self) -> dict[str, float]:
        """The figures as a JSON-able dict."""
        return asdict(self)

    def summary(self) -> str:
        """One line for the terminal."""
        return (
            f"estimate: velocity error {self.velocity_error_rms_mps:.3f} m/s rms, height "
            f"{self.height_error_rms_m * 1000:.1f} mm rms, yaw drift {self.yaw_drift_rad:.3f} "
            f"rad, position drift {self.position_drift_m:.3f} m, contacts agree on "
            f"{100 * self.contact_agreement:.1f} % of ticks"
        )


def _world(q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The base's rotation and its world-axes velocity."""
    rotation = pin.Quaternion(q[6], q[3], q[4], q[5]).normalized().toRotationMatrix()
    return rotation, rotation @ v[:3]


class EstimationScore:
    """Scores the estimator of a run on every tick and keeps its estimate at a trace rate.

    Args:
        estimator: The estimator the controller reads (its ``last`` estimate is scored).
        simulator: The simulation (the truth).
        record_every: Ticks between two rows of the estimate trace.
    """

    def __init__(self, estimator: LeggedEstimator, simulator: Simulator, record_every: int) -> None:
        self.estimator, self.simulator, self.record_every = estimator, simulator, record_every
        self.rows: list[tuple[float, ...]] = []
        #: the truth at the rows' ticks: t, x, y, z, vx, vy, vz (world)
        self.truth_rows: list[tuple[float, ...]] = []
        self._ticks = self._agree = self._late = 0
        self._velocity_sq = self._height_sq = 0.0
        self._yaw_error = 0.0
        self._position_error = 0.0

    def tick(self) -> None:
        """Score the estimator's newest estimate against the simulator's state now.

        Call it between the reading and the next physics step: the truth then is the state
        the reading measured.
        """
        estimate = self.estimator.last
        if estimate is None:
            return
        simulator = self.simulator
        q_true, v_true = simulator.q, simulator.v
        rotation_true, velocity_true = _world(q_true, v_true)
        rotation, velocity = _world(estimate.q, estimate.v)
        self._ticks += 1
        if estimate.time >= SETTLE_TIME:
            self._late += 1
            self._velocity_sq += float(np.sum((velocity - velocity_true)[:2] ** 2))
        self._height_sq += (estimate.q[2] - q_true[2]) ** 2
        contact = estimate.in_contact
        self._agree += all(contact[foot] == simulator.in_contact(foot) for foot in contact)
        error = pin.log3(rotation_true.T @ rotation)  # in the true base's axes
        self._yaw_error = float((rotation_true @ error)[2])
        self._position_error = float(np.hypot(*(estimate.q[:2] - q_true[:2])))
        if (self._ticks - 1) % self.record_every == 0:
            roll, pitch, yaw = pin.rpy.matrixToRpy(rotation)
            self.rows.append((estimate.time, *estimate.q[:3], roll, pitch, yaw, *velocity))
            self.truth_rows.append((estimate.time, *q_true[:3], *velocity_true))

    def trace(self) -> dict[str, list[float]]:
        """``ESTIMATE_CHANNELS`` as equal-length lists (the yaw continuous)."""
        rows = np.array(self.rows).reshape(-1, len(ESTIMATE_CHANNELS))
        rows[:, 6] = np.unwrap(rows[:, 6])
        return {name: rows[:, k].tolist() for k, name in enumerate(ESTIMATE_CHANNELS)}

    def to_json(self) -> dict[str, object]:
        """``estimate`` (the estimated base's `trace`) and ``estimation`` (the `summary`)."""
        return {"estimate": self.trace(), "estimation": self.summary().to_dict()}

    def summary(self) -> EstimationSummary:
        """The run's `EstimationSummary` (NaN where no tick was scored)."""
        ticks, late = self._ticks, self._late
        return EstimationSummary(
            velocity_error_rms_mps=math.sqrt(self._velocity_sq / late) if late else math.nan,
            height_error_rms_m=math.sqrt(self._height_sq / ticks) if ticks else math.nan,
            yaw_drift_rad=abs(self._yaw_error),
            position_drift_m=self._position_error,
            contact_agreement=self._agree / ticks if ticks else math.nan,
        )


def draw_estimate(score: EstimationScore, title: str = "") -> Figure:
    """The estimated against the true base: horizontal velocity and height over time."""
    figure = new_figure(8.0, 6.0, dpi=110)
    axes = figure.subplots(3, 1, sharex=True)
    estimate = np.array(score.rows).reshape(-1, len(ESTIMATE_CHANNELS))
    truth = np.array(score.truth_rows).reshape(-1, 7)
    panels = ((4, 7, "vx [m/s]"), (5, 8, "vy [m/s]"), (3, 3, "height z [m]"))
    for ax, (true_column, estimate_column, label) in zip(axes, panels, strict=True):
        ax.plot(truth[:, 0], truth[:, true_column], color="0.2", lw=1.2, label="true")
        ax.plot(estimate[:, 0], estimate[:, estimate_column], color="C1", lw=1.0,
                label="estimate")  # fmt: skip
        ax.set_ylabel(label)
        ax.grid(True, lw=0.4, alpha=0.5)
        ax.legend(loc="upper right", fontsize=7)
    axes[-1].set_xlabel("time [s]")
    set_heading(figure, title or score.summary().summary(), fontsize=8)
    return figure
