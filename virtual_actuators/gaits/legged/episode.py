"""One legged walk being run under `drive`: command, push, contact switches, fall test, trace."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ...control.controller import ControlOutput
from ...experiments.recorder import Recorder
from ...simulation.simulator import Simulator
from ...simulation.terrain import Terrain
from ..attitude import attitude_and_velocity
from ..guidance import Guidance, PlanarState, SinePath, TrackObject, wrap
from ..runner import FALL_PITCH, Episode, allowed_geoms
from .walker import LeggedWalker

if TYPE_CHECKING:  # walk.py runs the episodes
    from .walk import LeggedWalkConfig

TRACE_RATE = 100.0  # [Hz]

__all__ = ["TRACE_RATE", "LeggedEpisode"]


class LeggedEpisode(Episode):
    """A legged walk under `drive`."""

    ignore_unactuated = True

    def __init__(
        self,
        gait: LeggedWalker,
        simulator: Simulator,
        terrain: Terrain,
        recorder: Recorder,
        config: LeggedWalkConfig,
    ) -> None:
        super().__init__(gait, simulator, terrain, recorder)
        self.config = config
        self.record_every = max(1, round(1.0 / (TRACE_RATE * simulator.control_period)))
        self.stance_every = self.record_every  # MuJoCo's stance forces at the trace's rate
        c, s = math.cos(config.direction), math.sin(config.direction)
        gait.set_command((config.speed * c, config.speed * s), config.yaw_rate)
        self.guidance: Guidance | None = None
        if config.path == "sine":
            self.guidance = SinePath(config.speed, config.amplitude, config.wavelength)
        elif config.track:
            self.guidance = TrackObject(config.speed, config.direction)
        if self.guidance is not None:
            q = simulator.q
            yaw = attitude_and_velocity(q, simulator.v)[0]
            self.guidance.begin(PlanarState(0.0, float(q[0]), float(q[1]), yaw, 0.0, 0.0))
        self.pushed = config.push is None
        model = simulator.mujoco_model
        #: frames that may touch the ground: those sharing a geometry with a foot
        self.allowed = frozenset(
            name
            for foot in gait.feet
            for geom in model.frame_geoms.get(foot, ())
            for name in model.geom_frames[geom]
        ) | frozenset(gait.feet)
        #: per geom, 1 when every frame owning it is allowed (the fall test's one call)
        self.allowed_geoms = allowed_geoms(simulator, self.allowed.__contains__)
        self.attitude = (0.0, 0.0, 0.0, 0.0, 0.0)
        self.yaw_unwrapped = self.yaw_last = 0.0

    def sense(self, q: np.ndarray, v: np.ndarray, now: float) -> dict[str, bool]:
        """The push when its time comes; the feet's contact switches."""
        self.attitude = yaw, _, _, vx, vy = attitude_and_velocity(q, v)
        if self.guidance is not None:
            state = PlanarState(now, float(q[0]), float(q[1]), yaw, vx, vy)
            self.gait.set_command(*self.guidance.command(state))
        if not self.pushed and now >= self.config.push.time:
            self.config.push.apply(self.simulator, self.gait.body_frame)
            self.pushed = True
        return self.simulator.contact_switches(self.gait.feet)

    def fallen(self, q: np.ndarray) -> bool:
        """Base low or tilted, or a part other than a foot's link on the ground."""
        _, pitch, roll, _, _ = self.attitude
        height = float(q[2] - self.terrain.height(float(q[0])))
        if height < 0.5 * self.gait.stand_height or max(abs(roll), abs(pitch)) > FALL_PITCH:
            return True
        return self.simulator.touches_outside(self.allowed_geoms)  # touching_frames <= allowed

    def record(
        self, now: float, q: np.ndarray, v: np.ndarray, output: ControlOutput, fallen: bool
    ) -> None:
        """One sample of `CHANNELS`."""
        machine = self.gait.machine
        yaw, pitch, roll, vx, vy = self.attitude
        self.yaw_unwrapped += wrap(yaw - self.yaw_last)
        self.yaw_last = yaw
        self.recorder.append(
            state=machine.index[machine.current.name],
            time=now,
            x=q[0],
            y=q[1],
            z=float(q[2] - self.terrain.height(float(q[0]))),
            roll=roll,
            pitch=pitch,
            yaw=self.yaw_unwrapped,
            vx=vx,
            vy=vy,
            fallen=float(fallen),
        )
