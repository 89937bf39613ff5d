"""The viewer in a real browser: headless Chromium renders a recorded HTML file and a live page.

Chromium (Debian's ``chromium``, which ``.ci/run`` installs) draws the MeshCat page with WebGL in
software (SwiftShader) and saves a screenshot; the test reads its pixels back. A colour is
"seen" where a pixel has that colour's hue (its RGB direction: lighting changes brightness, not
hue). Every check is a difference against the same scene without the thing looked for, so the
legend's colour swatches (drawn in both) cannot make it pass.

Without Chromium the tests are skipped, except under CI (``CI`` set), where they fail.
"""

from __future__ import annotations

import importlib.util
import os
from pathlib import Path

import numpy as np
import pytest
from matplotlib import image as mpimg

import virtual_actuators as va
from virtual_actuators.visualization import PALETTE, OfflineWindow

# the README screenshots' script renders the pages (Chromium, headless)
TAKE_PY = Path(__file__).resolve().parents[1] / "robots" / "screenshots" / "take.py"
_spec = importlib.util.spec_from_file_location("take", TAKE_PY)
take = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(take)
screenshot = take.screenshot

CHROMIUM = take.find_chromium()
if CHROMIUM is None and os.environ.get("CI"):
    pytest.fail("CI must provide Debian's chromium for the browser tests", pytrace=False)
pytestmark = [
    pytest.mark.slow,
    pytest.mark.skipif(CHROMIUM is None, reason="chromium is not installed"),
]

SIZE = (800, 600)
FEET = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]


def render(url: str, path: Path, budget_ms: int = 6000) -> np.ndarray:
    """Render ``url`` headless and return its pixels ``(height, width, 3)`` in [0, 1]."""
    pixels = mpimg.imread(screenshot(url, path, SIZE, budget_ms))[..., :3]
    assert pixels.shape == (SIZE[1], SIZE[0], 3)
    return pixels


def hue_mask(pixels: np.ndarray, color: int, cosine: float = 0.995) -> np.ndarray:
    """Pixels whose RGB direction is within ``cosine`` of ``color``'s and not grey or dark."""
    rgb = np.array([(color >> 16) & 255, (color >> 8) & 255, color & 255], dtype=float)
    rgb /= np.linalg.norm(rgb)
    norm = np.linalg.norm(pixels, axis=-1)
    direction = pixels / np.maximum(norm, 1e-9)[..., None]
    saturation = pixels.max(axis=-1) - pixels.min(axis=-1)
    return (direction @ rgb > cosine) & (saturation > 0.15) & (norm > 0.2)


def solo12_scene():
    robot = va.load_robot("solo12")
    q = robot.neutral()
    body = va.ParallelVirtualActuator(
        robot, action="base_link", reactions=FEET, reference="world", contact="point"
    )
    wrench = np.array([30.0, 0.0, 60.0, 0.0, 0.0, 0.0])  # [N, N m]: a long arrow up and forward
    return robot, q, body, body.solve(q, wrench)


def test_recorded_html_shows_the_robot_and_the_wrench_arrows(tmp_path):
    robot, q, body, solution = solo12_scene()
    pages = {}
    for name, sol in (("arrows", solution), ("bare", None)):
        viewer = va.viz.Viewer(robot, window=OfflineWindow(), legend=False, force_scale=0.008)
        viewer.start_recording(fps=10)
        for _ in range(3):  # a short animation: the file plays it
            viewer.show(q, sol, actuator=body if sol is not None else None)
        viewer.stop_recording()
        path = viewer.save_html(str(tmp_path / f"{name}.html"))
        html = Path(path).read_text(encoding="utf-8")
        assert "https://" not in html and "http://cdn" not in html  # opens offline
        pages[name] = render(Path(path).as_uri(), tmp_path / f"{name}.png")
    arrows, bare = pages["arrows"], pages["bare"]
    background = np.median(bare.reshape(-1, 3), axis=0)
    robot_pixels = np.linalg.norm(bare - background, axis=-1) > 0.15
    assert robot_pixels.mean() > 0.01  # the robot (solo12's meshes) covers part of the view
    for color in (PALETTE.requested_force, PALETTE.share_force):
        added = hue_mask(arrows, color).sum() - hue_mask(bare, color).sum()
        assert added > 300, f"colour {color:06x}: {added} more pixels with the arrows"


def test_live_viewer_page_shows_the_arrows(tmp_path):
    robot, q, body, solution = solo12_scene()
    viewer = va.viz.Viewer(robot, legend=False, force_scale=0.008)
    try:
        url = viewer.url
        assert url and url.startswith("http://")
        viewer.show(q)
        viewer.flush(10.0)
        bare = render(url, tmp_path / "bare.png")
        viewer.show(q, solution, actuator=body)
        viewer.flush(10.0)
        baseline = hue_mask(bare, PALETTE.requested_force).sum()
        for budget_ms in (6000, 12000, 24000):  # the page gets the scene over a websocket:
            arrows = render(url, tmp_path / "arrows.png", budget_ms)  # give a busy
            added = hue_mask(arrows, PALETTE.requested_force).sum() - baseline  # machine time
            if added > 300:
                break
    finally:
        viewer.close()
    assert added > 300
