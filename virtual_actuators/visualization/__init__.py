"""MeshCat visualization of robots, virtual actuators, components and joint efforts (`Viewer`)."""

from ..exceptions import import_optional

# MeshCat is optional (the viz extra): name the extra before any module needs it
import_optional("meshcat", "viz", "The MeshCat viewer (virtual_actuators.visualization)")

from .frame_snapshot import FrameSnapshot  # noqa: E402
from .legend import PALETTE, Palette  # noqa: E402
from .live import LiveWindow  # noqa: E402
from .overlays import Overlay  # noqa: E402
from .recording import AnimationRecording  # noqa: E402
from .robot_scene import RobotScene  # noqa: E402
from .viewer import TickUpdater, Viewer  # noqa: E402
from .windows import CommandRecorder, OfflineWindow, SceneWindow  # noqa: E402

__all__ = [
    "PALETTE",
    "AnimationRecording",
    "CommandRecorder",
    "FrameSnapshot",
    "LiveWindow",
    "OfflineWindow",
    "Overlay",
    "Palette",
    "RobotScene",
    "SceneWindow",
    "TickUpdater",
    "Viewer",
]
