"""When a frame is sent live and recorded, and how a recording is framed."""

from __future__ import annotations

import math
import time as wallclock

import numpy as np
from meshcat.commands import SetProperty, SetTransform
from meshcat.path import Path as MeshcatPath

from .recording import AnimationRecording
from .scene import Scene
from .shapes import translation
from .windows import SceneWindow

#: Vertical field of view of MeshCat's default camera [deg].
CAMERA_FOV_DEG = 75.0


def _body_points(scene: Scene) -> np.ndarray:
    """Origins ``(n, 3)`` of the robot's bodies (``robot/...``, never hidden) in the view."""
    root = scene.matrices.get("", np.eye(4))
    points = [(root @ m)[:3, 3] for name, m in scene.matrices.items() if name.startswith("robot/")]
    return np.array(points) if points else np.zeros((0, 3))


#: MeshCat's camera object, and the node above every drawn scene (shifted to centre the run).
CAMERA_PATH = MeshcatPath(("Cameras", "default", "rotated", "<object>"))
SCENES_PATH = MeshcatPath(("meshcat",))


def framing_commands(
    bounds: tuple[np.ndarray, np.ndarray] | None, view: np.ndarray, margin: float
) -> list[object]:
    """Commands that centre the run's box on the origin and fit a sphere around it in view.

    Args:
        bounds: The run's box ``(low, high)`` (None: no frame).
        view: Unit vector from the target to the camera (world axes).
        margin: Added around the box [m].

    Returns:
        ``SetTransform`` of ``/meshcat`` and ``SetProperty`` of the camera's position (none
        for an empty box).
    """
    if bounds is None:
        return []
    low, high = bounds
    centre = (low + high) / 2.0
    radius = 0.5 * float(np.linalg.norm(high - low)) + margin
    distance = max(0.8, radius / math.sin(math.radians(CAMERA_FOV_DEG) / 2.0))
    offset = view * distance  # world axes; three.js is y-up
    local = [float(offset[0]), float(offset[2]), float(-offset[1])]
    return [
        SetTransform(translation(-centre), SCENES_PATH),
        SetProperty("position", local, CAMERA_PATH),
    ]


class FramePacer:
    """Live updates and recorded frames of one scene.

    Args:
        window: The window (live updates only go to a ``live`` one).
        scene: The scene whose state is sent and recorded.
        rate_hz: Live updates per wall-clock second.

    Attributes:
        last_live: Wall-clock time of the last live update (``perf_counter``).
        recording: The running recording, or None.
        last_recording: The last recording stopped, or None.
        bounds: ``(low, high)`` corners of the box holding the robot's visible bodies in every
            frame of the (last) recording, in the view's coordinates [m] (None: no frame).
    """

    def __init__(self, window: SceneWindow, scene: Scene, rate_hz: float) -> None:
        self.window = window
        self.scene = scene
        self.rate_hz = rate_hz
        self.last_live = -math.inf
        self.recording: AnimationRecording | None = None
        self.last_recording: AnimationRecording | None = None
        self._record_start = 0.0
        self._next_record = -math.inf
        self.bounds: tuple[np.ndarray, np.ndarray] | None = None

    def due(self, time: float | None = None) -> tuple[bool, bool]:
        """``(live, record)``: whether a live update and a recorded frame are due (`Viewer.due`)."""
        live = (
            self.window.live
            and wallclock.perf_counter() - self.last_live >= 1.0 / self.rate_hz
            and not getattr(self.window, "congested", False)  # a lagging server: skip frames
        )
        record = False
        if self.recording is not None:
            now = (wallclock.perf_counter() - self._record_start) if time is None else time
            record = now >= self._next_record - 1e-9
        return live, record

    def publish(self, live: bool, record: bool, time: float | None) -> None:
        """Send the drawn frame to the live window and/or add it to the recording.

        Args:
            live: Send it (the changes since the last update).
            record: Record it (if recording).
            time: Time of the frame [s] (None: one frame after the last at the recording's fps).
        """
        if live:
            self.scene.sync()
            self.last_live = wallclock.perf_counter()
        if record and self.recording is not None:
            self._record(time)

    def start_recording(self, fps: float = 30.0) -> None:
        """Record the following published frames (see `Viewer.start_recording`).

        Raises:
            InvalidInputError: ``fps`` is not a positive number.
        """
        self.recording = AnimationRecording(fps)
        self.bounds = None
        self._record_start = wallclock.perf_counter()
        self._next_record = -math.inf

    def stop_recording(self) -> AnimationRecording | None:
        """Stop recording; return the recording (None if none was running)."""
        recording, self.recording = self.recording, None
        self.last_recording = recording
        return recording

    def _record(self, time: float | None) -> None:
        recording = self.recording
        if time is None:
            time = recording.times[-1] + 1.0 / recording.fps if recording.times else 0.0
        time = float(time)
        if recording.times and time <= recording.times[-1]:
            return  # the same instant again (a paused simulation): keep the first frame
        recording.add(time, dict(self.scene.matrices), dict(self.scene.visible))
        points = _body_points(self.scene)
        if len(points):  # grow the box with the robot's visible bodies in this frame
            low, high = points.min(axis=0), points.max(axis=0)
            if self.bounds is not None:
                low, high = np.minimum(self.bounds[0], low), np.maximum(self.bounds[1], high)
            self.bounds = low, high
        self._next_record = time + 1.0 / recording.fps

    def __repr__(self) -> str:
        recording = f", recording {self.recording.frames} frames" if self.recording else ""
        return f"FramePacer(rate_hz={self.rate_hz:g}{recording})"
