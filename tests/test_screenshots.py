"""The README's screenshots are what ``robots/screenshots/take.py`` draws.

Without a browser: the legend in each committed PNG (an HTML box, flat colour swatches at the
bottom left) lists, top to bottom, the colours of the legend the script's viewer builds for that
scene. With Debian's chromium (slow): the script's scene rendered again matches the committed
PNG pixel for pixel, within a tolerance for another Chromium's rasterisation.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("meshcat")
from matplotlib import image as mpimg  # noqa: E402

FOLDER = Path(__file__).resolve().parents[1] / "robots" / "screenshots"


def _take():
    spec = importlib.util.spec_from_file_location("take", FOLDER / "take.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


TAKE = _take()
SCENES = {scene[0].name: scene for scene in TAKE.scenes()}


def pixels(path: Path) -> np.ndarray:
    """RGB ``(height, width, 3)`` in [0, 255]."""
    return np.round(mpimg.imread(path)[..., :3] * 255.0).astype(int)


def swatch_colours(image: np.ndarray) -> list[int]:
    """Colours of the legend's swatches, top to bottom (a column through the swatches).

    A swatch is a run of at least 8 rows of one saturated colour in the legend box's swatch
    column (the box's white and the text are not saturated).
    """
    height, width, _ = image.shape
    column = image[height // 3 :, 18:32]  # the box sits at the bottom left, swatches 12 px wide
    found: list[int] = []
    run, previous = 0, None
    for row in column:
        values, counts = np.unique(row, axis=0, return_counts=True)
        colour = values[np.argmax(counts)]
        saturated = colour.max() - colour.min() > 60 and counts.max() >= 10
        key = int(colour[0]) << 16 | int(colour[1]) << 8 | int(colour[2]) if saturated else None
        run = run + 1 if key == previous else 1
        previous = key
        if key is not None and run == 8:
            found.append(key)
    return found


@pytest.mark.parametrize("name", sorted(SCENES))
def test_the_committed_legend_is_the_one_the_script_draws(name):
    viewer = TAKE.draw(*SCENES[name])
    expected = [color for color, _ in viewer.legend_entries() if color is not None]
    assert swatch_colours(pixels(FOLDER / f"{name}.png")) == expected


def test_the_readme_shows_every_screenshot_the_script_takes():
    readme = (FOLDER.parents[1] / "README.md").read_text(encoding="utf-8")
    for name in SCENES:
        assert f"![](robots/screenshots/{name}.png)" in readme
    assert sorted(p.stem for p in FOLDER.glob("*.png")) == sorted(SCENES)


@pytest.mark.slow
@pytest.mark.skipif(TAKE.find_chromium() is None, reason="chromium is not installed")
@pytest.mark.parametrize("name", sorted(SCENES))
def test_the_committed_screenshot_is_what_the_script_renders(name, tmp_path):
    rendered = pixels(TAKE.render(TAKE.draw(*SCENES[name]), tmp_path)) / 255.0
    committed = pixels(FOLDER / f"{name}.png") / 255.0
    assert rendered.shape == committed.shape
    difference = np.abs(rendered - committed).max(axis=-1)
    assert difference.mean() < 0.01 and (difference > 0.25).mean() < 0.01
