"""The standalone HTML page: MeshCat's three.js viewer inlined, the scene's commands embedded."""

from __future__ import annotations

import base64
import html
from pathlib import Path


def _viewer_bundle() -> str:
    import meshcat

    path = Path(meshcat.__file__).parent / "viewer" / "dist" / "main.min.js"
    return path.read_text(encoding="utf-8")


def page(blobs: list[bytes], title: str = "MeshCat", overlay: str = "") -> str:
    """A standalone HTML page: MeshCat's viewer inlined plus commands decoded in order.

    Args:
        blobs: MessagePack commands.
        title: Page title.
        overlay: HTML shown over the view.

    Returns:
        The page.
    """
    bundle = _viewer_bundle().replace("</script", "<\\/script")
    commands = ",\n".join(f'"{base64.b64encode(b).decode("ascii")}"' for b in blobs)
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
