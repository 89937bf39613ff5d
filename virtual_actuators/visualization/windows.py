"""Where the scene's commands go: a MeshCat server, a recorder, or nowhere but the HTML page."""

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
        elif isinstance(command, mc.SetObject):
            node = self._node(path_of(command))
            node.object, node.properties = command, {}
        elif isinstance(command, mc.Delete):
            self._delete(path_of(command))
        elif isinstance(command, (mc.SetAnimation, mc.CaptureImage)):
            pass  # animations belong to a page, not to the scene tree
        else:  # other objects with a set_object lowering (Pinocchio's Collada meshes)
            data = command.lower()
            if data.get("type") == "set_object":
                node = self._node(str(data.get("path", "")))
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
            extra: Commands applied after the scene (e.g. a ``set_animation``).
            title: Page title.
            overlay: HTML placed over the 3D view (a legend).
        """
        script = Path(meshcat.__file__).parent / "viewer" / "dist" / "main.min.js"
        bundle = script.read_text(encoding="utf-8").replace("</script", "<\\/script")
        packed = (umsgpack.packb(c.lower()) for c in [*self.scene_commands(), *extra])
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
    """A window with no viewer: only the mirror (for HTML recordings without a server)."""

    live = False


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
