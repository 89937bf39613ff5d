"""Checks that a drawn figure shows everything it draws: text inside the image, keys for the marks.

Shared by the figure tests. The figure is rendered on an Agg renderer that notes every text artist
it actually draws (tick labels outside the view limits and hidden artists are never drawn, so
they are never checked), then each one's window extent is compared with the figure's box.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import RendererAgg
from matplotlib.collections import Collection, LineCollection
from matplotlib.figure import Figure
from matplotlib.legend import Legend
from matplotlib.lines import Line2D
from matplotlib.text import Text

#: Text may touch the image edge by this much [px] (antialiasing, rounding of the layout).
EDGE_TOLERANCE = 0.5


class TextRecorder(RendererAgg):
    """An Agg renderer of the figure's size that keeps every text artist drawn on it."""

    def __init__(self, figure: Figure) -> None:
        width, height = figure.bbox.size
        super().__init__(int(np.ceil(width)), int(np.ceil(height)), figure.dpi)
        self.texts: list[Text] = []


@contextmanager
def _recording_texts() -> Iterator[None]:
    """While open, every ``Text.draw`` on a :class:`TextRecorder` is noted on the renderer."""
    original = Text.draw

    def draw(text: Text, renderer) -> None:
        if isinstance(renderer, TextRecorder) and text.get_visible() and text.get_text().strip():
            renderer.texts.append(text)
        original(text, renderer)

    Text.draw = draw
    try:
        yield
    finally:
        Text.draw = original


@dataclass
class FigureReport:
    """What :func:`inspect_figure` found wrong (empty lists: the figure is fine)."""

    clipped: list[str] = field(default_factory=list)
    unlabelled_axes: list[str] = field(default_factory=list)
    without_key: list[str] = field(default_factory=list)
    texts: list[str] = field(default_factory=list)
    renderer: TextRecorder | None = None

    def problems(self) -> list[str]:
        """Every problem, one line each."""
        return (
            [f"clipped text: {c}" for c in self.clipped]
            + [f"axis without a label: {a}" for a in self.unlabelled_axes]
            + [f"no legend entry: {w}" for w in self.without_key]
        )


def render(figure: Figure) -> TextRecorder:
    """Draw ``figure`` (constrained layout included) on a recording renderer."""
    renderer = TextRecorder(figure)
    with _recording_texts():
        figure.draw(renderer)
    return renderer


def _describe(text: Text) -> str:
    return repr(text.get_text()[:70])


def clipped_texts(figure: Figure, renderer: TextRecorder) -> list[str]:
    """Texts drawn with any part outside the figure's box, with how far out they reach."""
    box = figure.bbox
    out = []
    for text in renderer.texts:
        extent = text.get_window_extent(renderer)
        over = max(
            box.x0 - extent.x0, extent.x1 - box.x1, box.y0 - extent.y0, extent.y1 - box.y1
        )
        if over > EDGE_TOLERANCE:
            out.append(f"{_describe(text)} by {over:.1f} px")
    return out


def _shows_tick_labels(axis, renderer: TextRecorder) -> bool:
    drawn = set(map(id, renderer.texts))
    return any(id(label) in drawn for label in axis.get_ticklabels())


def unlabelled_axes(figure: Figure, renderer: TextRecorder) -> list[str]:
    """Axes (colour bars too) that show numbers or names along an axis without naming it."""
    out = []
    for index, ax in enumerate(figure.axes):
        if not ax.get_visible() or not ax.axison:
            continue
        for name, axis, label in (
            ("x", ax.xaxis, ax.get_xlabel()),
            ("y", ax.yaxis, ax.get_ylabel()),
        ):
            if _shows_tick_labels(axis, renderer) and not label.strip():
                out.append(f"axes {index} ({ax.get_ylabel() or ax.get_title()!r}) {name} axis")
    return out


def _legends(figure: Figure) -> list[Legend]:
    legends = list(figure.legends)
    legends += [ax.get_legend() for ax in figure.axes if ax.get_legend() is not None]
    return legends


def _keyed_labels(figure: Figure) -> set[str]:
    return {text.get_text() for legend in _legends(figure) for text in legend.get_texts()}


def _is_reference_line(ax: Axes, artist) -> bool:
    """A full-width horizontal line at y = 0 (``axhline(0)``): part of the grid, not data."""
    return (
        isinstance(artist, Line2D)
        and artist.get_transform() == ax.get_yaxis_transform()
        and np.allclose(np.asarray(artist.get_ydata(), float), 0.0)
    )


def marks_without_key(figure: Figure) -> list[str]:
    """Lines and collections that no legend explains, beyond each panel's own series.

    In every panel, every line and line collection (step marks, fall lines, set points, paths)
    needs a legend entry carrying its label, except one: the panel's own series, which its y
    label names. Zero reference lines count as grid.
    """
    keyed = _keyed_labels(figure)
    out = []
    for index, ax in enumerate(figure.axes):
        artists = [
            a
            for a in [*ax.lines, *ax.collections]
            if isinstance(a, Line2D | LineCollection | Collection)
            and a.get_visible()
            and not _is_reference_line(ax, a)
            and type(a).__name__ not in ("QuadMesh", "PolyCollection", "FillBetweenPolyCollection")
        ]
        missing = [a for a in artists if a.get_label() not in keyed]
        if len(missing) > 1:
            names = ", ".join(f"{type(a).__name__} {a.get_label()!r}" for a in missing)
            out.append(f"axes {index} ({ax.get_ylabel()!r}): {names}")
    return out


def inspect_figure(figure: Figure) -> FigureReport:
    """Render ``figure`` and list clipped texts, unnamed axes and lines no legend explains."""
    renderer = render(figure)
    return FigureReport(
        clipped=clipped_texts(figure, renderer),
        unlabelled_axes=unlabelled_axes(figure, renderer),
        without_key=marks_without_key(figure),
        texts=[text.get_text() for text in renderer.texts],
        renderer=renderer,
    )


def assert_figure_fits(figure: Figure) -> FigureReport:
    """Fail with every problem :func:`inspect_figure` finds; return the report otherwise."""
    report = inspect_figure(figure)
    problems = report.problems()
    assert not problems, "\n".join(problems)
    return report
