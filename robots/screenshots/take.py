"""Screenshots of the viewer for the README: each robot with a virtual actuator and its wrench.

``python robots/screenshots/take.py`` writes ``robots/screenshots/<robot>.png`` (needs Debian's
``chromium``): the scene is saved as a standalone HTML page and rendered headless.
``tests/test_screenshots.py`` checks that the committed PNGs are what this script draws.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

import virtual_actuators as va
from virtual_actuators.visualization import OfflineWindow
from virtual_actuators.visualization.browser import screenshot

HERE = Path(__file__).resolve().parent


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
