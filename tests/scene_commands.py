"""Reading back what a viewer sent to a `CommandRecorder`: its ``commands``, in order.

Shared by the viewer tests.
"""

from __future__ import annotations

import meshcat.commands as mc

from virtual_actuators.visualization import CommandRecorder
from virtual_actuators.visualization.windows import path_of


def transform_paths(rec: CommandRecorder) -> list[str]:
    """Paths of the recorded ``set_transform`` commands."""
    return [path_of(c) for c in rec.commands if isinstance(c, mc.SetTransform)]


def last_transform(rec: CommandRecorder, path: str):
    """The last matrix sent to ``path`` (a ``(4, 4)`` array), or None."""
    for command in reversed(rec.commands):
        if isinstance(command, mc.SetTransform) and path_of(command) == path:
            return command.matrix
    return None


def objects(rec: CommandRecorder) -> dict[str, dict]:
    """The lowered object of every ``set_object`` command, by path (last one wins)."""
    return {
        path_of(c): c.object.lower() for c in rec.commands if isinstance(c, mc.SetObject)
    }


def visible(rec: CommandRecorder, path: str) -> bool | None:
    """The last ``visible`` property sent to ``path``, or None if never sent."""
    for command in reversed(rec.commands):
        kind = isinstance(command, mc.SetProperty) and command.key == "visible"
        if kind and path_of(command) == path:
            return bool(command.value)
    return None
