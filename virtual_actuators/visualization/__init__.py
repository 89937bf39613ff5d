"""MeshCat visualization of robots, virtual actuators, components and joint efforts.

``viewer = Viewer(robot)`` starts a MeshCat server and prints its URL; ``viewer.show(q,
solution, actuator=...)`` or ``viewer.show(q, controller=..., output=..., state=...)`` draws a
frame; ``viewer.start_recording()`` then ``viewer.save_html("run.html")`` writes a standalone
animated page. Modules:

- `geometry`: shapes (cone, plane, text, coil) and the pure functions that place them;
- `bodies`: the robot's URDF visuals or a skeleton of its kinematic tree;
- `meshes`: the URDF's mesh files as decimated triangle meshes (small pages);
- `scene`: node bookkeeping (created once, per-frame transforms and visibility);
- `robot_scene`: the robot in the scene (kinematics, sizes, camera, ground) and the
  drawing primitives (arrows, triads, spans, markers);
- `snapshot`: `FrameSnapshot`, what one frame draws, checked;
- `overlays`: what is drawn over the robot, one `Overlay` each (wrenches,
  components, effort gauges, support feet, state name, legend);
- `windows`, `live`, `page`: where commands go (a recorder, an offline mirror,
  a server through a relay) and the standalone HTML page;
- `recording`: frames to a MeshCat animation;
- `legend`: colours and the legend;
- `viewer`: `Viewer` and the ``on_tick`` adapter `TickUpdater`.

A new kind of drawing is a subclass of `Overlay` (``draw(scene, frame)``) passed to
`Viewer.add_overlay`.
"""

from ..exceptions import import_optional

# MeshCat is optional (the viz extra): say which extra installs it before any module needs it.
import_optional("meshcat", "viz", "The MeshCat viewer (virtual_actuators.visualization)")

from .frame_snapshot import FrameSnapshot  # noqa: E402
from .legend import PALETTE, Palette  # noqa: E402
from .live import LiveWindow  # noqa: E402
from .overlays import Overlay  # noqa: E402
from .recording import AnimationRecording  # noqa: E402
from .robot_scene import RobotScene  # noqa: E402
from .viewer import TickUpdater, Viewer  # noqa: E402
from .windows import CommandRecorder, ForwardingWindow, OfflineWindow, SceneWindow  # noqa: E402

__all__ = [
    "PALETTE",
    "AnimationRecording",
    "CommandRecorder",
    "ForwardingWindow",
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
