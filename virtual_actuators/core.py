"""The compiled core, ``virtual_actuators._core``, or None when it was not built.

The core's kernels are C++ (``src/core``, header-only C++17), bound with nanobind and built
when the package is installed (scikit-build-core, ``pip install``), or in place by
``tools/build_core.sh`` for a source tree that is not installed. They are the library's only
fast path: each kernel exists once, in C++. The GIL is released inside the kernels.

When the extension is missing, `CORE` is None: the library runs its numpy paths (Pinocchio's
kinematics, the numpy distribution and QP rows, the gaits' ticks in Python), which are also the
oracles the tests compare the core with, and warns once, at import (`CoreMissingWarning`).
``VA_CORE=0`` in the environment selects them on purpose (no warning). The library decides
between the two in one place, `kernel` (and `has` for the core's classes).
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


__all__ = ["CORE", "CoreMissingWarning", "has", "kernel"]
