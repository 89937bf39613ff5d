"""What is drawn over the robot, one `Overlay` per kind of thing (`Viewer.add_overlay` adds one)."""

from ..robot_scene import Overlay
from .markers import EffortOverlay, LegendOverlay, StateOverlay, SupportOverlay
from .wrenches import ComponentOverlay, WrenchOverlay


def default_overlays(legend: bool = True) -> list[Overlay]:
    """The viewer's overlays, in drawing order: wrenches, components, efforts, state, support.

    Args:
        legend: Add the legend, last (it lists what the others drew).
    """
    kinds = [WrenchOverlay, ComponentOverlay, EffortOverlay, StateOverlay, SupportOverlay]
    return [kind() for kind in (kinds + [LegendOverlay] if legend else kinds)]
