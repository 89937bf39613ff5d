"""The compiled core, ``virtual_actuators._core`` (C++ in ``src/core``), or None when not built.

Without it (or with ``VA_CORE=0``) the library runs its numpy paths, warning once
(`CoreMissingWarning`) unless asked; `kernel` and `has` decide between the two.
"""

from __future__ import annotations

import importlib
import os
import warnings
from types import ModuleType
from typing import TypeVar

_Kernel = TypeVar("_Kernel")


class CoreMissingWarning(RuntimeWarning):
    """``virtual_actuators._core`` is not built: the numpy paths run instead."""


def _load() -> ModuleType | None:
    if os.environ.get("VA_CORE", "1") == "0":
        return None
    try:  # the extension is a leaf: it imports no Python module of this package
        core = importlib.import_module(f"{__package__}._core")
    except ImportError as error:
        warnings.warn(
            f"virtual_actuators._core (the compiled core) is not built ({error}): using the "
            "numpy paths (correct, several times slower per tick). "
            "Install the package with pip (a C++17 compiler is needed) or run "
            "tools/build_core.sh in a source tree.",
            CoreMissingWarning,
            stacklevel=3,
        )
        return None
    return core


#: The compiled core's module (``Tree``, ``Distribution``, ...), or None: the numpy paths.
CORE: ModuleType | None = _load()


def has(name: str) -> bool:
    """Whether the compiled core is built and has ``name`` (a kernel, a class, a constant)."""
    return CORE is not None and hasattr(CORE, name)


def kernel(name: str, fallback: _Kernel) -> _Kernel:
    """The core's kernel ``name`` when the core is built, else ``fallback``.

    Args:
        name: The kernel's name in ``virtual_actuators._core``.
        fallback: The numpy implementation with the same arguments and results, or None
            where the caller has a general path of its own.

    Raises:
        AttributeError: The core is built but has no ``name`` (a build older than the package).
    """
    return fallback if CORE is None else getattr(CORE, name)
