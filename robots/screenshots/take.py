"""Screenshots of the viewer for the README: each robot with a virtual actuator and its wrench.

``python robots/screenshots/take.py`` writes ``robots/screenshots/<robot>.png`` (needs Debian's
``chromium``): the scene is saved as a standalone HTML page and rendered headless (WebGL in
software, no display needed). ``tests/test_screenshots.py`` checks that the committed PNGs are
what this script draws; ``tests/test_browser.py`` renders its own pages with `screenshot`.
"""

from __future__ import annotations

import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np

import virtual_actuators as va
from virtual_actuators.exceptions import VirtualActuatorError
from virtual_actuators.visualization import OfflineWindow

HERE = Path(__file__).resolve().parent

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


def scenes():
    """``(robot, q, actuator, solution or None, wrench or None, force_scale)`` per robot."""
    planar = ("x", "z", "ry")
    for name in ("spring_turkey", "spring_flamingo"):
        robot = va.load_robot(name)
        limp = ["left_ankle", "right_ankle"] if name == "spring_flamingo" else []
        body = va.ParallelVirtualActuator(
            robot,
            "body",
            ["left_foot", "right_foot"],
            "world",
            planar,
            contact="flat" if limp else "point",
            unactuated=limp,
        )
        q = robot.neutral()
        weight = sum(i.mass for i in robot.model.inertias) * 9.81
        yield robot, q, body, body.solve(q, np.array([0.2 * weight, weight, 0.5])), None, 0.004
    robot = va.load_robot("hexapod")
    feet = ["foot_1", "foot_3", "foot_5"]
    body = va.ParallelVirtualActuator(robot, "body", feet, "world", contact="point")
    q = robot.neutral()
    yield robot, q, body, body.solve(q, np.array([5.0, 0, 37.3, 0, 0.3, 0])), None, 0.01
    robot = va.load_robot("solo12")
    feet = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
    body = va.ParallelVirtualActuator(robot, "base_link", feet, "world", contact="point")
    q = robot.neutral()
    yield robot, q, body, body.solve(q, np.array([8.0, 0, 25.0, 0, 0.5, 0])), None, 0.01
    robot = va.load_robot("ur5_robot")
    hand = robot.model.frames[robot.model.nframes - 1].name
    arm = va.VirtualActuator(robot, hand, "world", "world", ("x", "y", "z"))
    q = robot.neutral()
    yield robot, q, arm, None, np.array([20.0, 0.0, 30.0]), 0.006


#: Window size of the screenshots [px].
SIZE = (960, 600)


def draw(robot, q, actuator, solution, wrench, scale):
    """The viewer of one scene of :func:`scenes`, drawn offline."""
    viewer = va.viz.Viewer(robot, window=OfflineWindow(), force_scale=scale)
    viewer.show(q, solution, actuator=actuator, wrench=wrench)
    return viewer


def render(viewer, folder: Path) -> Path:
    """Save ``viewer``'s page in ``folder`` and screenshot it there as ``<robot>.png``."""
    name = viewer.robot.name
    page = viewer.save_html(str(folder / f"{name}.html"))
    return screenshot(Path(page).as_uri(), folder / f"{name}.png", SIZE)


def main() -> None:
    """Render every scene of :func:`scenes` to a PNG next to this script."""
    with tempfile.TemporaryDirectory() as tmp:
        for scene in scenes():
            png = render(draw(*scene), Path(tmp))
            target = HERE / png.name
            target.write_bytes(png.read_bytes())
            print(target)


if __name__ == "__main__":
    main()
