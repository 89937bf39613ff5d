"""Runnable demos: the walks in MuJoCo (``python -m virtual_actuators demo``) and their sweeps.

``WALKS`` and ``run_walk`` (`virtual_actuators.gaits.registry`) are imported on first use (they
bring MuJoCo), so that option parsing, which uses `virtual_actuators.demos.sweep`, works on a
core-only install.
"""

from __future__ import annotations

from typing import Any

__all__ = ["WALKS", "run_walk"]


def __getattr__(name: str) -> Any:
    """``WALKS`` and ``run_walk``, imported when asked.

    Raises:
        AttributeError: Any other name.
        MissingDependencyError: MuJoCo is not installed (the extra ``sim``).
    """
    if name in __all__:
        from ..gaits import registry

        return getattr(registry, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
