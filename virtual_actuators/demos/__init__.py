"""Runnable demos: the walks in MuJoCo (``python -m virtual_actuators demo``) and their sweeps.

The names are imported on first use (they bring MuJoCo), so that option parsing, which uses
`virtual_actuators.demos.sweep`, works on a core-only install; ``WalkSpec`` is `Walk`.
"""

from __future__ import annotations

from typing import Any

__all__ = ["WALKS", "Walk", "WalkResult", "WalkSpec", "run_walk"]


def __getattr__(name: str) -> Any:
    """``WALKS``, ``Walk``, ``WalkSpec``, ``WalkResult`` and ``run_walk``, imported when asked.

    Raises:
        AttributeError: Any other name.
        MissingDependencyError: MuJoCo is not installed (the extra ``sim``).
    """
    if name in ("Walk", "WalkSpec"):
        from ..gaits.base import Walk

        return Walk
    if name in ("WALKS", "run_walk"):
        from ..gaits import registry

        return getattr(registry, name)
    if name == "WalkResult":
        from ..gaits.runner import WalkResult

        return WalkResult
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
