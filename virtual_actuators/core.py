"""The compiled core, ``virtual_actuators._core``, or None when it was not built.

The core's kernels are C++ (``src/core``, header-only C++17), bound with nanobind and built
when the package is installed (scikit-build-core, ``pip install``), or in place by
``tools/build_core.sh`` for a source tree that is not installed. Each kernel follows a reference
kernel of this package (numba, or plain Python without numba) operation by operation, so that
both give the same bits (``tests/test_core_parity.py``). The GIL is released inside the kernels.

When the extension is missing, `CORE` is None: the library runs its reference kernels and
warns once, at import (`CoreMissingWarning`). ``VA_CORE=0`` in the environment selects the
reference kernels on purpose (no warning), for instance to compare both paths.
"""

from __future__ import annotations

import importlib
import os
import warnings
from types import ModuleType
from typing import TypeVar

_Kernel = TypeVar("_Kernel")


class CoreMissingWarning(RuntimeWarning):
    """``virtual_actuators._core`` is not built: the reference kernels run instead."""


def _load() -> ModuleType | None:
    if os.environ.get("VA_CORE", "1") == "0":
        return None
    try:  # the extension is a leaf: it imports no Python module of this package
        core = importlib.import_module(f"{__package__}._core")
    except ImportError as error:
        warnings.warn(
            f"virtual_actuators._core (the compiled core) is not built ({error}): using the "
            "reference kernels, which numba compiles on first use (seconds to a minute). "
            "Install the package with pip (a C++17 compiler is needed) or run "
            "tools/build_core.sh in a source tree.",
            CoreMissingWarning,
            stacklevel=3,
        )
        return None
    return core


#: The compiled core's module (``Tree``, ``Distribution``, ...), or None: the reference path.
CORE: ModuleType | None = _load()



def has(name: str) -> bool:
    """Whether the compiled core is built and has ``name`` (a kernel, a class, a constant)."""
    return CORE is not None and hasattr(CORE, name)


def kernel(name: str, fallback: _Kernel) -> _Kernel:
    """The core's kernel ``name`` when the core is built, else ``fallback`` (the reference).

    Args:
        name: The kernel's name in ``virtual_actuators._core``.
        fallback: The reference implementation with the same arguments and results.

    Raises:
        AttributeError: The core is built but has no ``name`` (a build older than the package).

    """
    return fallback if CORE is None else getattr(CORE, name)


__all__ = ["CORE", "CoreMissingWarning", "has", "kernel"]
