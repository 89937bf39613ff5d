"""The MeshCat viewer: a robot, its virtual actuators and what the controller does with them."""

from __future__ import annotations

import time as wallclock
from pathlib import Path
from typing import TYPE_CHECKING, Protocol, Unpack

import meshcat
import numpy as np
from meshcat.commands import SetProperty

from ..control import Controller, ControlOutput
from ..distribution.result import Solution
from ..exceptions import InvalidInputError
from ..models.robot import Robot
from ..vocabulary.arguments import check_number
from .bodies import RobotBodies, typical_link_length
from .frame_snapshot import FrameExtras, FrameSnapshot
from .legend import PALETTE, Palette, legend_entries, legend_html
from .live import LiveWindow
from .overlays import Overlay, default_overlays
from .recording import AnimationRecording, FramePacer, framing_commands
from .robot_scene import RobotScene
from .windows import Scene, SceneWindow

if TYPE_CHECKING:
    from ..simulation.simulator import Simulator
    from ..simulation.terrain import Terrain


class Viewer:
    """Show a robot and its virtual actuators in MeshCat.

    Args:
        robot: The robot.
        window: None starts a MeshCat server (or connects to ``zmq_url``) and prints its URL;
            a `CommandRecorder` or `OfflineWindow` (a `SceneWindow`) draws without a server.
        force_scale: Arrow length per newton [m/N].
        moment_scale: Arrow length per newton-metre [m/(N m)].
        effort_reference: Full gauge at joints without a URDF effort limit [N m or N].
        zmq_url: URL of a running ``meshcat-server`` to use instead of starting one.
        geometry: ``"auto"`` (URDF visuals if any, else a skeleton), ``"urdf"``, ``"skeleton"``.
        legend: Draw the legend in the scene.
        rate_hz: Live updates per wall-clock second of `maybe_show` and `tick_callback`.
        palette: Colours.

    Attributes:
        robot_scene: The robot's geometry, kinematics and drawing primitives (its scales,
            sizes and ``data`` at the last configuration drawn).
        scene: Its MeshCat nodes.
        overlays: What is drawn over the robot, in drawing order.
        window: Where the scene is sent.
        pacer: When frames are sent and recorded.

    Raises:
        InvalidInputError: ``robot`` is not a [`Robot`][], a scale or the rate is not a
            positive number, ``geometry`` is unknown, or ``window`` is neither
            None nor a `SceneWindow`.
        RobotDescriptionError: ``geometry="urdf"`` for a robot without visual geometry.
        VirtualActuatorError: The MeshCat server cannot be started or reached.
    """

    def __init__(
        self,
        robot: Robot,
        *,
        window: SceneWindow | None = None,
        force_scale: float = 0.01,
        moment_scale: float = 0.05,
        effort_reference: float = 10.0,
        zmq_url: str | None = None,
        geometry: str = "auto",
        legend: bool = True,
        rate_hz: float = 30.0,
        palette: Palette = PALETTE,
    ) -> None:
        if not isinstance(robot, Robot):
            raise InvalidInputError(f"Viewer needs a virtual_actuators.Robot, got {robot!r}.")
        scales = {"force_scale": force_scale, "moment_scale": moment_scale}
        scales["effort_reference"] = effort_reference
        scales = [check_number(value, what, positive=True) for what, value in scales.items()]
        rate_hz = check_number(rate_hz, "rate_hz", positive=True)
        if window is not None and not isinstance(window, SceneWindow):
            raise InvalidInputError(f"window must be None or a SceneWindow, got {window!r}.")
        self.robot = robot
        self.bodies = RobotBodies(robot, geometry, typical_link_length(robot.model))
        self.window: SceneWindow = LiveWindow(zmq_url) if window is None else window
        self.vis = meshcat.Visualizer(window=self.window)
        self.scene = Scene(self.vis, "virtual_actuators")
        self.robot_scene = RobotScene(robot, self.bodies, self.scene, palette, *scales)
        self.overlays: list[Overlay] = default_overlays(legend)
        self.pacer = FramePacer(self.window, self.scene, rate_hz)
        self.robot_scene.build()
        for overlay in self.overlays:
            overlay.setup(self.robot_scene)
        self.show(robot.neutral())
        if window is None:
            print(f"MeshCat viewer of {robot.name}: {self.url}")

    @property
    def url(self) -> str | None:
        """URL of the live viewer (None without a server)."""
        return self.window.web_url

    def start_recording(self, fps: float = 30.0) -> None:
        """Record every following `show` (and due `maybe_show`) as animation frames.

        Args:
            fps: Frames per second of `maybe_show` / `tick_callback` (by the frames' ``time``)
                and of `show` calls without a time.

        Raises:
            InvalidInputError: ``fps`` is not a positive number.
        """
        self.pacer.start_recording(fps)

    def stop_recording(self) -> AnimationRecording | None:
        """Stop recording; return the recording (None if none was running)."""
        return self.pacer.stop_recording()

    def static_html(self, title: str | None = None) -> str:
        """A standalone HTML page (it opens offline) of the scene, animated with the recording.

        A recording is framed on the robot over the whole run.
        """
        title = title or f"virtual_actuators: {self.robot.name}"
        overlay = legend_html(self.legend_entries(), title)  # the scene's own legend is hidden
        scene, pacer = self.robot_scene, self.pacer
        self.scene.sync()
        extra: list[object] = [SetProperty("visible", False, self.scene.node("hud/legend").path)]
        recording = pacer.recording or pacer.last_recording
        if recording is not None and recording.frames >= 2:
            extra += framing_commands(pacer.bounds, scene.view, 0.75 * scene.detail)
            extra.append(recording.command(self.scene.path))
        return self.window.static_html(extra, title=title, overlay=overlay)

    def save_html(self, path: str, title: str | None = None) -> str:
        """Write `static_html` (the whole recorded run, if any) to ``path``; return the path.

        Raises:
            InvalidInputError: The folder of ``path`` does not exist.
        """
        target = Path(path).expanduser()
        if not target.parent.is_dir():
            raise InvalidInputError(f"Cannot write {str(path)!r}: its folder does not exist.")
        target.write_text(self.static_html(title), encoding="utf-8")
        return str(target)

    def flush(self, timeout: float | None = 10.0) -> bool:
        """Wait until the live viewer received everything sent (True if it did in time)."""
        return self.window.flush(timeout)

    def close(self) -> None:
        """Stop the sender and the MeshCat server this viewer started."""
        self.window.close()

    def legend_entries(self) -> list[tuple[int | None, str]]:
        """The legend as ``(colour or None, text)`` pairs: what has been drawn so far."""
        return legend_entries(self.robot_scene, self.robot_scene.drawn)

    def add_overlay(self, overlay: Overlay) -> Overlay:
        """Draw ``overlay`` in every following frame, after the others (its `setup` runs now).

        Returns:
            The overlay.

        Raises:
            InvalidInputError: ``overlay`` is not an `Overlay`.
        """
        if not isinstance(overlay, Overlay):
            raise InvalidInputError(f"overlay must be an Overlay, got {overlay!r}.")
        self.overlays.append(overlay)
        overlay.setup(self.robot_scene)
        return overlay

    def set_terrain(self, terrain: Terrain | np.ndarray, run: float = 30.0) -> None:
        """Draw a planar ground profile (a [`Terrain`][]).

        Args:
            terrain: A terrain or an ``(n, 2)`` array of ``(x, z)`` points [m].
            run: Level ground drawn before the first and after the last point [m].

        Raises:
            InvalidInputError: The points are not an ``(n, 2)`` finite array.
        """
        self.robot_scene.set_terrain(terrain, run)
        if self.window.live:
            self.scene.sync()

    def show(
        self, q: np.ndarray, solution: Solution | None = None, **extras: Unpack[FrameExtras]
    ) -> None:
        """Draw one frame and send it (and record it while recording).

        Args:
            q: Configuration ``(model.nq,)``.
            solution: A [`Solution`][] of ``actuator``.
            actuator: The [`ParallelVirtualActuator`][] or [`VirtualActuator`][] to draw.
            wrench: Requested wrench on the actuator's axes, without a ``solution``.
            controller: A [`Controller`][] (with ``output``).
            output: Its [`ControlOutput`][] of this tick.
            state: The gait's current [`State`][] (its name shown, its support feet
                highlighted) or a state name.
            support: More support frames to highlight.
            time: Time of the frame [s] for recordings (None: one frame per call at the
                recording's fps).

        Raises:
            InvalidInputError: Bad ``q``, ``wrench``, a solution without its actuator or of
                another actuator, an output without its controller or naming unknown
                attachments.
            FrameNotFoundError: A frame (action, reaction, reference, support) is not in the
                viewer's robot.
        """
        self._draw(q, solution, extras, self.window.live, self.pacer.recording is not None)

    def maybe_show(
        self, q: np.ndarray, solution: Solution | None = None, **extras: Unpack[FrameExtras]
    ) -> bool:
        """`show` (same arguments), only when a live update or a recorded frame is due.

        Cheap when nothing is due, so it can be called at every control tick.

        Returns:
            Whether a frame was drawn.

        Raises:
            InvalidInputError: See `show`.
            FrameNotFoundError: See `show`.
        """
        live, record = self.pacer.due(extras.get("time"))
        if not (live or record):
            return False
        self._draw(q, solution, extras, live, record)
        return True

    def _draw(
        self,
        q: np.ndarray,
        solution: Solution | None,
        extras: FrameExtras,
        live: bool,
        record: bool,
    ) -> None:
        """Check a frame (`FrameSnapshot.build`), draw it, then send and/or record it."""
        frame = FrameSnapshot.build(self.robot.model.nq, self.robot.name, q, solution, **extras)
        self.robot_scene.pose(frame.q)
        for overlay in self.overlays:
            overlay.draw(self.robot_scene, frame)
        self.scene.end_frame()
        self.pacer.publish(live, record, frame.time)

    def tick_callback(self, realtime: bool = False) -> TickUpdater:
        """An ``on_tick(simulator, gait)`` for `run_walk`.

        Args:
            realtime: Sleep so that simulated time does not run ahead of wall-clock time.
        """
        return TickUpdater(self, realtime=realtime)

    def __repr__(self) -> str:
        running, scene = self.pacer.recording, self.robot_scene
        recording = f", recording {running.frames} frames" if running else ""
        return (
            f"Viewer(robot={self.robot.name!r}, url={self.url!r}, geometry={self.bodies.kind!r}, "
            f"force_scale={scene.force_scale:g} m/N, moment_scale={scene.moment_scale:g} m/(N m)"
            f"{recording})"
        )


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
    """

    def __init__(self, viewer: Viewer, realtime: bool = False) -> None:
        self.viewer = viewer
        self.realtime = realtime
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
            if getattr(simulator, "terrain", None) is not None:  # drawn at the first tick
                viewer.set_terrain(simulator.terrain)
        if self.realtime:
            ahead = (sim_time - self._sim_start) - (wallclock.perf_counter() - self._start)
            if ahead > 0.005:
                wallclock.sleep(ahead)
        if not any(viewer.pacer.due(sim_time)):
            return  # (the state and q are read only for a frame that is due)
        machine = getattr(gait, "machine", None)
        self.updates += viewer.maybe_show(
            simulator.q,
            controller=gait.controller if gait.last is not None else None,
            output=gait.last,
            state=machine.current if machine is not None else None,
            time=sim_time,
        )

    def __repr__(self) -> str:
        return (
            f"TickUpdater({self.viewer.robot.name!r}, realtime={self.realtime}, "
            f"updates={self.updates})"
        )
