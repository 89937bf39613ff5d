"""The ``on_tick(simulator, gait)`` adapter of a viewer: `TickUpdater`."""

from __future__ import annotations

import time as wallclock
from typing import TYPE_CHECKING, Protocol

from ..control import Controller, ControlOutput
from .frame_snapshot import FrameSnapshot

if TYPE_CHECKING:
    from ..simulation.simulator import Simulator
    from .viewer import Viewer


class Gait(Protocol):
    """What `TickUpdater` reads of a gait (its ``machine`` too, if it has one).

    Attributes:
        controller: The gait's controller.
        last: Its output of the last tick, or None before the first.
    """

    controller: Controller
    last: ControlOutput | None


class TickUpdater:
    """``on_tick(simulator, gait)`` adapter: throttled live updates and recorded frames.

    When one is due, it draws the simulator's ``q`` with the gait's controller, last output
    and state.

    Args:
        viewer: The viewer.
        realtime: Sleep so that simulated time does not run ahead of wall-clock time.
        terrain: Draw the simulator's terrain at the first tick.
    """

    def __init__(self, viewer: Viewer, realtime: bool = False, terrain: bool = True) -> None:
        self.viewer = viewer
        self.realtime = realtime
        self.terrain = terrain
        self.updates = 0
        self._start: float | None = None
        self._sim_start = 0.0

    def __call__(self, simulator: Simulator, gait: Gait) -> None:
        """Update the viewer if due.

        Raises:
            InvalidInputError: The simulator's ``q`` or the gait's output does not fit.
            FrameNotFoundError: A frame the gait names is not in the viewer's robot.
        """
        viewer = self.viewer
        sim_time = simulator.time
        if self._start is None:
            self._start, self._sim_start = wallclock.perf_counter(), sim_time
            if self.terrain and getattr(simulator, "terrain", None) is not None:
                viewer.set_terrain(simulator.terrain)
        if self.realtime:
            ahead = (sim_time - self._sim_start) - (wallclock.perf_counter() - self._start)
            if ahead > 0.005:
                wallclock.sleep(ahead)
        live, record = viewer.due(sim_time)
        if not (live or record):
            return
        machine = getattr(gait, "machine", None)
        frame = FrameSnapshot.build(
            viewer.robot.model.nq,
            viewer.robot.name,
            simulator.q,
            controller=gait.controller if gait.last is not None else None,
            output=gait.last,
            state=machine.current if machine is not None else None,
        )
        viewer.draw(frame)
        viewer.pacer.publish(live, record, sim_time)
        self.updates += 1

    def __repr__(self) -> str:
        return (
            f"TickUpdater({self.viewer.robot.name!r}, realtime={self.realtime}, "
            f"updates={self.updates})"
        )
