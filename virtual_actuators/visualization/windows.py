"""The viewer's MeshCat nodes (`Scene`) and where their commands go (a `SceneWindow`)."""

from __future__ import annotations

import base64
import html
from dataclasses import dataclass, field
from pathlib import Path

import meshcat
import meshcat.commands as mc
import numpy as np
import umsgpack
from meshcat.path import Path as MeshcatPath


def path_of(command: object) -> str:
    """The path of a MeshCat command, as a string."""
    path = getattr(command, "path", None)
    if path is None:
        return str(command.lower().get("path", ""))
    return path.lower() if hasattr(path, "lower") and not isinstance(path, str) else str(path)


@dataclass(slots=True)
class _Node:
    """One node of the mirrored scene: its object, properties and transform."""

    object: object = None
    properties: dict[str, object] = field(default_factory=dict)
    transform: np.ndarray | None = None


class SceneWindow:
    """Base window: mirrors the scene built by the commands it receives (`_deliver` sends them).

    Attributes:
        live: Whether commands reach a viewer as they are sent (the viewer sends live updates
            only to live windows).
        web_url: URL of the live viewer, or None.
    """

    live: bool = False
    web_url: str | None = None

    def __init__(self) -> None:
        self._nodes: dict[str, _Node] = {}

    def send(self, command: object) -> None:
        """Apply a MeshCat command to the mirror and deliver it."""
        self._mirror(command)
        self._deliver(command)

    def send_transform(self, path: str, matrix: np.ndarray) -> None:
        """Fast path of ``send(SetTransform(matrix, path))`` for a path given as a string."""
        self._node(path).transform = matrix
        self._deliver_transform(path, matrix)

    def _deliver(self, command: object) -> None:
        """Send the command on (nothing by default)."""

    def _deliver_transform(self, path: str, matrix: np.ndarray) -> None:
        """Send a transform on (by default as a MeshCat command to `_deliver`)."""
        self._deliver(mc.SetTransform(matrix, MeshcatPath(tuple(p for p in path.split("/") if p))))

    def commit(self) -> None:
        """Deliver the commands queued since the last commit (nothing to do by default)."""

    def flush(self, timeout: float | None = None) -> bool:
        """Wait until every command was delivered; True if they were (always, here)."""
        return True

    def close(self) -> None:
        """Release the window's resources (nothing by default)."""

    def _mirror(self, command: object) -> None:
        if isinstance(command, mc.SetTransform):
            self._node(path_of(command)).transform = command.matrix
        elif isinstance(command, mc.SetProperty):
            self._node(path_of(command)).properties[command.key] = command
        elif isinstance(command, mc.Delete):
            self._delete(path_of(command))
        elif isinstance(command, (mc.SetAnimation, mc.CaptureImage)):
            pass  # animations belong to a page, not to the scene tree
        elif isinstance(command, mc.SetObject) or command.lower().get("type") == "set_object":
            node = self._node(path_of(command))  # (the second kind: Pinocchio's Collada meshes)
            node.object, node.properties = command, {}

    def _node(self, path: str) -> _Node:
        node = self._nodes.get(path)
        if node is None:
            node = self._nodes[path] = _Node()
        return node

    def _delete(self, path: str) -> None:
        if path in ("", "/"):
            self._nodes.clear()
            return
        prefix = path.rstrip("/") + "/"
        for key in [k for k in self._nodes if k == path or k.startswith(prefix)]:
            del self._nodes[key]

    def scene_commands(self) -> list[object]:
        """The commands that rebuild the current scene: objects, properties, then transforms."""
        out = []
        for path, node in self._nodes.items():
            if node.object is not None:
                out.append(node.object)
            out.extend(node.properties.values())
            if node.transform is not None:
                entries = tuple(p for p in path.split("/") if p)
                out.append(mc.SetTransform(node.transform, MeshcatPath(entries)))
        return out

    def static_html(
        self, extra: list[object] = (), title: str = "MeshCat", overlay: str = ""
    ) -> str:
        """A self-contained HTML page (it opens offline) of the scene, then ``extra`` commands.

        Args:
            extra: Commands (or lowered ones, dicts) applied after the scene (e.g. a
                ``set_animation``).
            title: Page title.
            overlay: HTML placed over the 3D view (a legend).
        """
        script = Path(meshcat.__file__).parent / "viewer" / "dist" / "main.min.js"
        bundle = script.read_text(encoding="utf-8").replace("</script", "<\\/script")
        every = [*self.scene_commands(), *extra]
        packed = (umsgpack.packb(c if isinstance(c, dict) else c.lower()) for c in every)
        commands = ",\n".join(f'"{base64.b64encode(b).decode("ascii")}"' for b in packed)
        return f"""<!DOCTYPE html>
<html>
<head>
<meta charset="utf-8">
<title>{html.escape(title)}</title>
<style>
body {{ margin: 0; }}
#meshcat-pane {{ width: 100vw; height: 100vh; overflow: hidden; }}
#va-overlay {{ position: absolute; left: 8px; bottom: 8px; font: 12px sans-serif;
  background: rgba(255, 255, 255, 0.85); padding: 6px 10px; border-radius: 4px;
  max-width: 45vw; }}
#va-overlay .sw {{ display: inline-block; width: 12px; height: 12px; margin-right: 6px;
  vertical-align: middle; border: 1px solid #444; }}
</style>
</head>
<body>
<div id="meshcat-pane"></div>
{overlay}
<script>
{bundle}
</script>
<script>
var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
var commands = [
{commands}
];
for (var i = 0; i < commands.length; i++) {{
  var text = atob(commands[i]);
  var bytes = new Uint8Array(text.length);
  for (var k = 0; k < text.length; k++) {{ bytes[k] = text.charCodeAt(k); }}
  viewer.handle_command_bytearray(bytes);
}}
</script>
</body>
</html>
"""

    def __repr__(self) -> str:
        return f"{type(self).__name__}({len(self._nodes)} nodes)"


class OfflineWindow(SceneWindow):
    """A window with no viewer (not ``live``): only the mirror, for HTML pages without a server."""


class CommandRecorder(SceneWindow):
    """Keeps every command in order (for tests and inspection); stands for a live viewer.

    Attributes:
        commands: Every command received, as MeshCat command objects.
    """

    live = True

    def __init__(self) -> None:
        super().__init__()
        self.commands: list[object] = []

    def _deliver(self, command: object) -> None:
        self.commands.append(command)

    def __repr__(self) -> str:
        return f"CommandRecorder({len(self.commands)} commands, {len(self._nodes)} nodes)"


class Scene:
    """The nodes under one prefix of a MeshCat visualizer.

    Args:
        vis: The ``meshcat.Visualizer`` of a `SceneWindow` (its root path is ``/meshcat``).
        prefix: Node under which everything is drawn.

    Attributes:
        matrices: Current world matrix of each placed node.
        visible: Current visibility of each dynamic node.
    """

    def __init__(self, vis: object, prefix: str) -> None:
        self.vis = vis
        self.prefix = prefix.strip("/")
        self._views: dict[str, object] = {}
        self._paths: dict[str, str] = {}
        self._created: set[str] = set()
        self.matrices: dict[str, np.ndarray] = {}
        self._sent: dict[str, np.ndarray] = {}
        self._dynamic: set[str] = set()
        self.visible: dict[str, bool] = {}
        self._sent_visible: dict[str, bool] = {}
        self._used: set[str] = set()

    def node(self, name: str) -> object:
        """The MeshCat view of a node (``/absolute`` names are outside the prefix)."""
        view = self._views.get(name)
        if view is None:  # no empty path element: MeshCat restarts the path at the root on one
            key = name if name.startswith("/") else "/".join(p for p in (self.prefix, name) if p)
            view = self._views[name] = self.vis[key]
        return view

    def path(self, name: str) -> str:
        """The node's full MeshCat path (``/meshcat/<prefix>/<name>``)."""
        path = self._paths.get(name)
        if path is None:
            path = self._paths[name] = self.node(name).path.lower()
        return path

    def has(self, name: str) -> bool:
        """Whether an object was created at ``name``."""
        return name in self._created

    def create(self, name: str, geometry: object, material: object = None) -> None:
        """Send the object at ``name`` once (later calls with the same name do nothing)."""
        if name in self._created:
            return
        self._created.add(name)
        self.node(name).set_object(geometry, material)

    def remove(self, name: str) -> None:
        """Delete the node ``name`` and everything under it (objects are created anew later)."""
        self.node(name).delete()
        inside = name.rstrip("/") + "/"
        for store in (self._created, self._dynamic):
            store.difference_update({n for n in store if n == name or n.startswith(inside)})
        for store in (self.matrices, self._sent, self.visible, self._sent_visible):
            for key in [n for n in store if n == name or n.startswith(inside)]:
                del store[key]

    def declare(self, name: str) -> None:
        """Make ``name`` dynamic: hidden in every frame that does not `use` it."""
        if name not in self._dynamic:
            self._dynamic.add(name)
            self.visible.setdefault(name, False)
            self._sent_visible.setdefault(name, True)  # three.js objects start visible

    def use(self, name: str) -> None:
        """Show the dynamic node ``name`` in this frame."""
        self._used.add(name)

    def place(self, name: str, matrix: np.ndarray) -> None:
        """Set the world matrix of ``name`` for this frame (sent at the next `sync`)."""
        self.matrices[name] = matrix

    def set_property(self, name: str, key: str, value: object) -> None:
        """Send a static property now (the background's colours, the camera)."""
        self.node(name).set_property(key, value)

    def end_frame(self) -> None:
        """Fix the visibility of every dynamic node for this frame."""
        used = self._used
        for name in self._dynamic:
            self.visible[name] = name in used
        self._used = set()

    def sync(self) -> None:
        """Send the transforms and visibilities that changed since the last sync, then commit."""
        window = self.vis.window  # a SceneWindow
        for name, matrix in self.matrices.items():
            previous = self._sent.get(name)
            if previous is matrix:
                continue
            self._sent[name] = matrix
            if previous is not None and np.array_equal(previous, matrix):
                continue  # placed again where it was (a frame that does not move)
            window.send_transform(self.path(name), matrix)
        for name, visible in self.visible.items():
            if self._sent_visible.get(name) != visible:
                self.node(name).set_property("visible", visible)
                self._sent_visible[name] = visible
        window.commit()  # windows that batch (the live window) send the frame now

    def __repr__(self) -> str:
        return (
            f"Scene(prefix={self.prefix!r}, {len(self._created)} objects, "
            f"{len(self.matrices)} placed, {len(self._dynamic)} dynamic)"
        )
