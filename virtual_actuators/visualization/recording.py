"""Recording a run as a MeshCat animation, written into a standalone HTML page.

A node that held still gets a copy of its last key before it moves, so it does not drift.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin
import umsgpack

from ..exceptions import InvalidInputError
from ..vocabulary.arguments import check_number

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


@dataclass(repr=False)
class AnimationCommand:
    """A MeshCat ``set_animation`` command with pre-lowered clips, played once on loading.

    Attributes:
        animations: ``[{"path": ..., "clip": {...}}]`` in MeshCat's format.
    """

    animations: list[dict]

    def lower(self) -> dict:
        """The command as MeshCat's viewer reads it."""
        return {
            "type": "set_animation",
            "path": "",
            "animations": self.animations,
            "options": {"play": True, "repetitions": 1},
        }

    def __repr__(self) -> str:
        return f"AnimationCommand({len(self.animations)} clips)"


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
        self._last_matrix: dict[str, np.ndarray] = {}
        self._last_visible: dict[str, bool] = {}

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
            previous = self._last_matrix.get(name)
            if previous is matrix:
                continue
            track = self._matrices.setdefault(name, [])
            if track and track[-1][0] < k - 1:
                track.append((k - 1, previous))  # hold still until this frame
            track.append((k, matrix))
            self._last_matrix[name] = matrix
        for name, shown in visible.items():
            if self._last_visible.get(name) == shown:
                continue
            track = self._visible.setdefault(name, [])
            if not track and k > 0 and shown:
                track.append((0, False))  # appeared after the start
            track.append((k, bool(shown)))
            self._last_visible[name] = shown

    def command(self, path_of) -> AnimationCommand:
        """The ``set_animation`` command of the recording, one clip per node.

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
        return AnimationCommand(animations)

    def __repr__(self) -> str:
        return (
            f"AnimationRecording({self.frames} frames, {self.duration:.2f} s, "
            f"{len(self._matrices)} moving nodes)"
        )
