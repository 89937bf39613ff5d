"""The hexapod's walk under `drive`: guidance, contact switches, fall test, trace."""

from __future__ import annotations

import math

import numpy as np

from ...control.controller import ControlOutput
from ...experiments.recorder import Recorder
from ...simulation.simulator import Simulator
from ...simulation.terrain import Terrain
from ..attitude import attitude_and_velocity, rotation
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
        self.command = np.zeros(2)
        self.yaw_unwrapped, self.yaw_last = 0.0, 0.0
        self._touching: frozenset[str] | None = None  # the last contact set and its switches
        self._switches: dict[str, bool] = {}

    def sense(self, q: np.ndarray, v: np.ndarray, now: float) -> dict[str, bool]:
        """Steer the walker along the guidance; the feet's contact switches (a shared dict)."""
        self.attitude = yaw, _, _, vx, vy = attitude_and_velocity(q, v)
        state = PlanarState(now, float(q[0]), float(q[1]), yaw, vx, vy)
        self.command, yaw_rate = self.guidance.command(state)
        self.gait.set_command(self.command, yaw_rate)
        touching = self.simulator.touching_frames()  # the same set object for the same contacts
        if touching is not self._touching:
            self._touching = touching
            self._switches = {foot: foot in touching for foot in self.gait.contact_frames}
        return self._switches

    def fallen(self, q: np.ndarray) -> bool:
        """Body low or tilted, something else than a foot down, or the pendulum leaning."""
        _, pitch, roll, _, _ = self.attitude
        gait, parameters = self.gait, self.gait.parameters
        height = float(q[2] - self.terrain.height(q[0]))
        tilt = max(abs(roll), abs(pitch))
        fallen = has_fallen(self.simulator, height, tilt, parameters.height, self.feet)
        leaning = gait.pendulum is not None and abs(gait.pendulum_angle) > parameters.pendulum_fall
        return fallen or leaning

    def record(
        self, now: float, q: np.ndarray, v: np.ndarray, output: ControlOutput, fallen: bool
    ) -> None:
        """One sample of `CHANNELS`."""
        gait, machine = self.gait, self.gait.machine
        yaw, pitch, roll, vx, vy = self.attitude
        self.yaw_unwrapped += wrap(yaw - self.yaw_last)
        self.yaw_last = yaw
        target = self.guidance.target(now) or (np.nan, np.nan)
        wrench = _body_wrench(output)
        axes = rotation(q)
        c, s = math.cos(yaw), math.sin(yaw)
        self.recorder.append(
            state=machine.index[machine.current.name],
            time=now,
            x=q[0],
            y=q[1],
            z=float(q[2] - self.terrain.height(q[0])),
            roll=roll,
            pitch=pitch,
            yaw=self.yaw_unwrapped,
            vx=vx,
            vy=vy,
            vx_heading=c * vx + s * vy,
            vx_command=float(self.command[0]),
            yaw_rate=float(axes[2] @ (axes @ v[3:6])),
            fx=c * wrench[0] + s * wrench[1],
            pendulum=gait.pendulum_angle if gait.pendulum is not None else np.nan,
            target_x=target[0],
            target_y=target[1],
            fallen=float(fallen),
        )


def _body_wrench(output) -> np.ndarray:
    """The virtual wrench the body's components ask for this tick (world axes)."""
    for name in ("support_a", "support_b", "support_all"):
        if name in output.wrenches:
            return output.wrenches[name]
    return np.zeros(6)
