"""When a drawn frame is sent live (at most ``rate_hz``, none while the server lags), recorded."""

from __future__ import annotations

import math
import time as wallclock

from meshcat.commands import SetProperty

from .framing import RunBounds
from .recording import AnimationRecording
from .scene import Scene
from .windows import SceneWindow


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
        bounds: Box of everything shown in the frames of the (last) recording.
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
        self.bounds = RunBounds()

    def due(self, time: float | None = None) -> tuple[bool, bool]:
        """``(live, record)``: whether a live update and a recorded frame are due.

        Args:
            time: Simulated time [s] (recordings are paced by it), or None for wall time.
        """
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
        self.bounds = RunBounds()
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
        self.bounds.add(self.scene)
        self._next_record = time + 1.0 / recording.fps

    def page(self, title: str, overlay: str, framing: list[object] = ()) -> str:
        """A standalone page of the scene, animated with the (last) recording if there is one.

        Args:
            title: Page title.
            overlay: HTML over the view (the legend; the scene's own is hidden).
            framing: Commands that frame the recording (camera, offset), applied with it.
        """
        self.scene.sync()
        recording = self.recording or self.last_recording
        extra: list[object] = [SetProperty("visible", False, self.scene.node("hud/legend").path)]
        if recording is not None and recording.frames >= 2:
            extra += [*framing, recording.command(self.scene.path)]
        return self.window.static_html(extra, title=title, overlay=overlay)

    def __repr__(self) -> str:
        recording = f", recording {self.recording.frames} frames" if self.recording else ""
        return f"FramePacer(rate_hz={self.rate_hz:g}{recording})"
