"""Screenshots of viewer pages in headless Chromium (WebGL in software, no display needed).

Used by the browser tests and ``robots/screenshots/take.py``; needs Debian's ``chromium``.
"""

from __future__ import annotations

import shutil
import subprocess
import tempfile
from pathlib import Path

from ..exceptions import VirtualActuatorError

# Headless, software WebGL (SwiftShader), and no background connections: on a closed network
# Chromium otherwise retries Google's hosts at every start.
CHROMIUM_FLAGS = tuple(
    "--headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
    "--disable-background-networking --disable-component-update --disable-sync "
    "--enable-unsafe-swiftshader --use-angle=swiftshader --hide-scrollbars".split()
)


def find_chromium() -> str | None:
    """Path of the ``chromium`` executable, or None."""
    return shutil.which("chromium") or shutil.which("chromium-browser")


def screenshot(
    url: str, path: str | Path, size: tuple[int, int] = (800, 600), budget_ms: int = 6000
) -> Path:
    """Render ``url`` (``file://`` or ``http://``) headless and save a PNG.

    Args:
        url: The page.
        path: PNG to write.
        size: Window ``(width, height)`` [px].
        budget_ms: Virtual time the page gets to load and draw [ms].

    Returns:
        The PNG's path.

    Raises:
        VirtualActuatorError: Chromium is not installed, or it failed (its output attached).
    """
    chromium = find_chromium()
    if chromium is None:
        raise VirtualActuatorError("Screenshots need Debian's chromium: apt-get install chromium.")
    path = Path(path)
    with tempfile.TemporaryDirectory() as profile:
        result = subprocess.run(
            [
                chromium,
                *CHROMIUM_FLAGS,
                f"--user-data-dir={profile}",
                f"--window-size={size[0]},{size[1]}",
                f"--virtual-time-budget={budget_ms}",
                f"--screenshot={path}",
                url,
            ],
            capture_output=True,
            text=True,
            timeout=120,
        )
    if result.returncode != 0 or not path.is_file():
        raise VirtualActuatorError(f"Chromium could not render {url}:\n{result.stderr[-2000:]}")
    return path
