"""Where a viewer's frames go: the live window, the recording, a standalone page.

`ViewerOutput` is the part of `Viewer` that sends what was drawn: to the
live MeshCat window at ``rate_hz`` (paced by a `FramePacer`), into an
`AnimationRecording`, or into a standalone HTML page.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from ..exceptions import InvalidInputError
from .framing import framing_commands
from .legend import legend_html
from .pacing import FramePacer
from .recording import AnimationRecording
from .windows import SceneWindow

if TYPE_CHECKING:
    from ..models.robot import Robot
    from .robot_scene import RobotScene

__all__ = ["ViewerOutput"]


class ViewerOutput:
    """The output side of a viewer (a base of `Viewer`, which sets the fields).

    Attributes:
        window: Where the scene is sent.
        pacer: When frames are sent and recorded.
    """

    robot: Robot
    robot_scene: RobotScene
    window: SceneWindow
    pacer: FramePacer

    def legend_entries(self) -> list[tuple[int | None, str]]:
        """The legend as ``(colour or None, text)`` pairs (see ``Viewer.legend_entries``)."""
        raise NotImplementedError

    @property
    def rate_hz(self) -> float:
        """Live updates per wall-clock second."""
        return self.pacer.rate_hz

    @rate_hz.setter
    def rate_hz(self, value: float) -> None:
        self.pacer.rate_hz = value

    @property
    def url(self) -> str | None:
        """URL of the live viewer (None without a server)."""
        return self.window.web_url

    @property
    def recording(self) -> bool:
        """Whether frames are being recorded."""
        return self.pacer.recording is not None

    def due(self, time: float | None = None) -> tuple[bool, bool]:
        """Whether a live update and a recorded frame are due (cheap: two comparisons).

        Args:
            time: Simulated time [s] (recordings are paced by it), or None for wall time.

        Returns:
            ``(live, record)``.
        """
        return self.pacer.due(time)

    def start_recording(self, fps: float = 30.0) -> None:
        """Record every following `show` (and due `maybe_show`) as animation frames.

        Args:
            fps: Frames per second of `maybe_show` / `tick_callback` (paced by the
                frames' ``time``, e.g. simulated time), and of `show` calls without a
                time.

        Raises:
            InvalidInputError: ``fps`` is not a positive number.
        """
        self.pacer.start_recording(fps)

    def stop_recording(self) -> AnimationRecording | None:
        """Stop recording; return the recording (None if none was running)."""
        return self.pacer.stop_recording()

    def static_html(self, title: str | None = None) -> str:
        """A standalone HTML page of the scene, animated with the recording if there is one.

        A recording is framed on the whole run: the camera sees everything drawn in any of its
        frames (see `framing`).

        Returns:
            The page (MeshCat's viewer inlined: it opens offline).
        """
        title = title or f"virtual_actuators: {self.robot.name}"
        scene = self.robot_scene
        framing = framing_commands(self.pacer.bounds, scene.view, 0.75 * scene.detail)
        return self.pacer.page(title, legend_html(self.legend_entries(), title), framing)

    def save_html(self, path: str, title: str | None = None) -> str:
        """Write `static_html` to ``path`` (the whole recorded run, if any).

        Args:
            path: File to write (``.html``).
            title: Page title.

        Returns:
            The path written.

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
