"""MeshCat visualization of robots, virtual actuators, components and joint efforts.

``viewer = Viewer(robot)`` starts a MeshCat server and prints its URL; ``viewer.show(q,
solution, actuator=...)`` or ``viewer.show(q, controller=..., output=..., state=...)`` draws a
frame; ``viewer.start_recording()`` then ``viewer.save_html("run.html")`` writes a standalone
animated page. Modules:

- :mod:`.geometry`: shapes (cone, plane, text, coil) and the pure functions that place them;
- :mod:`.bodies`: the robot's URDF visuals or a skeleton of its kinematic tree;
- :mod:`.scene`: node bookkeeping (created once, per-frame transforms and visibility);
- :mod:`.windows`: where commands go (a server, a recorder, an offline mirror) and the HTML page;
- :mod:`.recording`: frames to a MeshCat animation;
- :mod:`.legend`: colours and the legend;
- :mod:`.viewer`: :class:`Viewer` and the ``on_tick`` adapter :class:`TickUpdater`.
"""

from .legend import PALETTE, Palette
from .recording import AnimationRecording
from .viewer import TickUpdater, Viewer
from .windows import CommandRecorder, ForwardingWindow, LiveWindow, OfflineWindow, SceneWindow

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
