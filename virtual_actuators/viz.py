"""MeshCat viewer of robots and virtual actuators: ``va.viz.Viewer(robot)``.

Re-exports :mod:`virtual_actuators.visualization` (see there for the details). Importing this
module imports MeshCat; ``import virtual_actuators`` alone does not (``va.viz`` is loaded on
first use).
"""

from .visualization import (
    PALETTE,
    AnimationRecording,
    CommandRecorder,
    ForwardingWindow,
    LiveWindow,
    OfflineWindow,
    Palette,
    SceneWindow,
    TickUpdater,
    Viewer,
)

__all__ = [
    "PALETTE",
    "AnimationRecording",
    "CommandRecorder",
    "ForwardingWindow",
    "LiveWindow",
    "OfflineWindow",
    "Palette",
    "SceneWindow",
    "TickUpdater",
    "Viewer",
]
