"""Recording a run as a MeshCat animation, when frames are sent live and recorded, and framing.

A node that held still gets a copy of its last key before it moves, so it does not drift.
"""

from __future__ import annotations

import math
import time as wallclock

import numpy as np
import pinocchio as pin
import umsgpack
from meshcat.commands import SetProperty, SetTransform
from meshcat.path import Path as MeshcatPath

from ..exceptions import InvalidInputError
from ..vocabulary.arguments import check_number
from .shapes import translation
from .windows import Scene, SceneWindow

FLOAT32_ARRAY = 0x17  # MeshCat / msgpack-lite extension code of a Float32Array


def _float32(values: np.ndarray) -> umsgpack.Ext:
    return umsgpack.Ext(FLOAT32_ARRAY, np.ascontiguousarray(values, dtype=np.float32).tobytes())


def _track(name: str, kind: str, times: np.ndarray, values: object) -> dict:
    """One keyframe track of a three.js animation clip."""
    return {"name": name, "type": kind, "times": _float32(times), "values": values}


def _decompose(matrix: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``[R diag(s) | p]`` (``s`` positive) as ``p (3,)``, quaternion ``(x, y, z, w)``, ``s``."""
    linear = matrix[:3, :3]
    scale = np.linalg.norm(linear, axis=0)
    safe = np.where(scale > 1e-12, scale, 1.0)
    rotation = linear / safe
    if np.any(scale <= 1e-12):  # a flattened axis: rebuild an orthonormal frame
        u, _, vt = np.linalg.svd(rotation)
        rotation = u @ vt
        if np.linalg.det(rotation) < 0:
            rotation = u @ np.diag([1.0, 1.0, -1.0]) @ vt
    quaternion = pin.Quaternion(rotation).coeffs()  # x, y, z, w
    return matrix[:3, 3].copy(), np.asarray(quaternion, dtype=float), scale


class AnimationRecording:
    """Frames of the scene, kept as per-node changes.

    Args:
        fps: Nominal frames per second (key times follow the frames' own times).

    Raises:
        InvalidInputError: ``fps`` is not a positive number.
    """

    def __init__(self, fps: float = 30.0) -> None:
        self.fps = check_number(fps, "fps", positive=True)
        self.times: list[float] = []
        self._matrices: dict[str, list[tuple[int, np.ndarray]]] = {}
        self._visible: dict[str, list[tuple[int, bool]]] = {}

    @property
    def frames(self) -> int:
        """Number of frames recorded."""
        return len(self.times)

    @property
    def duration(self) -> float:
        """Time from the first to the last frame [s]."""
        return self.times[-1] - self.times[0] if self.times else 0.0

    def add(self, time: float, matrices: dict[str, np.ndarray], visible: dict[str, bool]) -> None:
        """Record one frame.

        Args:
            time: Time of the frame [s]; frames must come in increasing time.
            matrices: World matrix of every placed node (compared by identity).
            visible: Visibility of every dynamic node.

        Raises:
            InvalidInputError: ``time`` is not after the previous frame's.
        """
        time = float(time)
        if self.times and not time > self.times[-1]:
            message = f"Recorded frames need increasing times: {time} after {self.times[-1]}."
            raise InvalidInputError(message)
        k = len(self.times)
        self.times.append(time)
        for name, matrix in matrices.items():
            track = self._matrices.setdefault(name, [])
            if track and track[-1][1] is matrix:
                continue
            if track and track[-1][0] < k - 1:
                track.append((k - 1, track[-1][1]))  # hold still until this frame
            track.append((k, matrix))
        for name, shown in visible.items():
            track = self._visible.setdefault(name, [])
            if track and track[-1][1] == shown:
                continue
            if not track and k > 0 and shown:
                track.append((0, False))  # appeared after the start
            track.append((k, bool(shown)))

    def command(self, path_of) -> dict:
        """The ``set_animation`` command of the recording, one clip per node, played once.

        It comes lowered, as MeshCat's viewer reads it.

        Args:
            path_of: Maps a node name to its MeshCat path.
        """
        start = self.times[0] if self.times else 0.0
        frame_times = (np.array(self.times) - start) * self.fps  # in frames, as MeshCat counts
        clips: dict[str, list[dict]] = {}
        for name, keys in self._matrices.items():
            if len(keys) < 2:
                continue  # never moved while recording: its static transform is enough
            times = frame_times[[k for k, _ in keys]]
            columns = zip(*(_decompose(m) for _, m in keys), strict=True)
            positions, quaternions, scales = (np.array(column) for column in columns)
            for i in range(1, len(quaternions)):  # continuous signs for interpolation
                if quaternions[i] @ quaternions[i - 1] < 0:
                    quaternions[i] = -quaternions[i]
            tracks = [
                _track(".position", "vector3", times, _float32(positions.ravel())),
                _track(".quaternion", "quaternion", times, _float32(quaternions.ravel())),
            ]
            if np.any(np.abs(scales - 1.0) > 1e-9):
                tracks.append(_track(".scale", "vector3", times, _float32(scales.ravel())))
            clips.setdefault(name, []).extend(tracks)
        for name, keys in self._visible.items():
            times = frame_times[[k for k, _ in keys]]
            track = _track(".visible", "boolean", times, [v for _, v in keys])
            clips.setdefault(name, []).append(track)
        animations = [
            {"path": path_of(name), "clip": {"fps": self.fps, "name": "default", "tracks": tracks}}
            for name, tracks in clips.items()
        ]
        options = {"play": True, "repetitions": 1}
        return {"type": "set_animation", "path": "", "animations": animations, "options": options}

    def __repr__(self) -> str:
        return (
            f"AnimationRecording({self.frames} frames, {self.duration:.2f} s, "
            f"{len(self._matrices)} moving nodes)"
        )


#: Vertical field of view of MeshCat's default camera [deg].
CAMERA_FOV_DEG = 75.0


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
        self.bounds = None
        self._record_start = wallclock.perf_counter()
        self._next_record = -math.inf

    def stop_recording(self) -> AnimationRecording | None:
        """Stop recording; return the recording (None if none was running)."""
        self.last_recording, self.recording = self.recording, None
        return self.last_recording

    def _record(self, time: float | None) -> None:
        recording = self.recording
        if time is None:
            time = recording.times[-1] + 1.0 / recording.fps if recording.times else 0.0
        time = float(time)
        if recording.times and time <= recording.times[-1]:
            return  # the same instant again (a paused simulation): keep the first frame
        matrices = self.scene.matrices
        recording.add(time, dict(matrices), dict(self.scene.visible))
        root = matrices.get("", np.eye(4))  # the view's shift; the bodies are never hidden
        points = [(root @ m)[:3, 3] for name, m in matrices.items() if name.startswith("robot/")]
        if points:  # grow the box with the origins of the robot's bodies in this frame
            low, high = np.min(points, axis=0), np.max(points, axis=0)
            if self.bounds is not None:
                low, high = np.minimum(self.bounds[0], low), np.maximum(self.bounds[1], high)
            self.bounds = low, high
        self._next_record = time + 1.0 / recording.fps

    def __repr__(self) -> str:
        recording = f", recording {self.recording.frames} frames" if self.recording else ""
        return f"FramePacer(rate_hz={self.rate_hz:g}{recording})"
