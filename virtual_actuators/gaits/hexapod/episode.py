"""The hexapod's walk under `drive`: guidance, contact switches, fall test, trace."""

from __future__ import annotations

import math

import numpy as np

from ...control.controller import ControlOutput
from ...experiments.recorder import Recorder
from ...simulation.simulator import Simulator
from ...simulation.terrain import Terrain
from ..attitude import attitude_and_velocity
from ..guidance import Guidance, PlanarState, wrap
from ..runner import Episode, has_fallen
from .walker import HexapodWalker

TRACE_RATE = 100.0  # [Hz] samples of the trace and the log

__all__ = ["TRACE_RATE", "HexapodEpisode"]


class HexapodEpisode(Episode):
    """The hexapod's walk under `drive` (the body state recorded at `TRACE_RATE`)."""

    ignore_unactuated = True

    def __init__(
        self,
        gait: HexapodWalker,
        simulator: Simulator,
        terrain: Terrain,
        recorder: Recorder,
        guidance: Guidance,
    ) -> None:
        super().__init__(gait, simulator, terrain, recorder)
        self.guidance = guidance
        self.record_every = max(1, round(1.0 / (TRACE_RATE * simulator.control_period)))
        self.attitude = (0.0, 0.0, 0.0, 0.0, 0.0)  # yaw, pitch, roll, vx, vy this tick
        self.nominal = gait.parameters.height  # [m]
        self.pendulum_fall = gait.parameters.pendulum_fall  # [rad]
        self.command = np.zeros(2)
        if guidance.fixed:  # set once: the state does not change it
            start = PlanarState(simulator.time, *guidance.start, 0.0, 0.0)
            self.command, yaw_rate = guidance.command(start)
            gait.set_command(self.command, yaw_rate)
        self.yaw_unwrapped, self.yaw_last = 0.0, 0.0

    def sense(self, q: np.ndarray, v: np.ndarray, now: float) -> dict[str, bool]:
        """Steer the walker along the guidance; the feet's contact switches."""
        self.attitude = yaw, _, _, vx, vy = attitude_and_velocity(q, v)
        if not self.guidance.fixed:
            state = PlanarState(now, q.item(0), q.item(1), yaw, vx, vy)
            self.command, yaw_rate = self.guidance.command(state)
            self.gait.set_command(self.command, yaw_rate)
        return self.simulator.contact_switches(self.gait.contact_frames)

    def fallen(self, q: np.ndarray) -> bool:
        """Body low or tilted, something else than a foot down, or the pendulum leaning."""
        _, pitch, roll, _, _ = self.attitude
        level = self.level
        height = q.item(2) - (self.terrain.height(q.item(0)) if level is None else level)
        tilt = max(abs(roll), abs(pitch))
        if has_fallen(self.simulator, height, tilt, self.nominal, self.feet):
            return True
        gait = self.gait
        return gait.pendulum is not None and abs(gait.pendulum_angle) > self.pendulum_fall

    def record(
        self, now: float, q: np.ndarray, v: np.ndarray, output: ControlOutput, fallen: bool
    ) -> None:
        """One sample of `CHANNELS`."""
        gait, machine = self.gait, self.gait.machine
        yaw, pitch, roll, vx, vy = self.attitude
        self.yaw_unwrapped += wrap(yaw - self.yaw_last)
        self.yaw_last = yaw
        target_x, target_y = self.guidance.target(now) or (math.nan, math.nan)
        wrench = _body_wrench(output)
        x, y, z, w = q[3:7].tolist()  # the body's world z rate: row z of its rotation . omega
        row_z = 2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)
        c, s = math.cos(yaw), math.sin(yaw)
        self.recorder.append_row(  # one value per CHANNELS entry, in its order
            (
                now,
                q.item(0),
                q.item(1),
                q.item(2) - (self.terrain.height(q.item(0)) if self.level is None else self.level),
                roll,
                pitch,
                self.yaw_unwrapped,
                vx,
                vy,
                c * vx + s * vy,
                float(self.command[0]),
                sum(r * rate for r, rate in zip(row_z, v[3:6].tolist(), strict=True)),
                c * wrench.item(0) + s * wrench.item(1),
                gait.pendulum_angle if gait.pendulum is not None else math.nan,
                target_x,
                target_y,
                float(fallen),
            ),
            machine.current_index,
        )


def _body_wrench(output) -> np.ndarray:
    """The virtual wrench the body's components ask for this tick (world axes)."""
    for name in ("support_a", "support_b", "support_all"):
        wrench = output.wrench_of(name)
        if wrench is not None:
            return wrench
    return np.zeros(6)
