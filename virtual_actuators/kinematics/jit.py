"""The reference kernels' decorator `njit`: numba when it is needed, plain Python without it.

The package's kernels are written once, in Python, as plain loops (``@njit(cache=True)``). They
are the reference of the compiled core's C++ ports (`virtual_actuators.core`):

* without the core (not built, or ``VA_CORE=0``) the library runs them, so numba is imported
  with the package and compiles each kernel on its first call (``cache=True``: once per
  machine);
* with the core built the library calls its ports instead, and numba is not imported at all
  (its import costs about 0.2 s): `njit` returns a `LazyKernel`, which imports
  numba on the first call of any reference kernel (a test comparing both paths, a tool), then
  makes every reference kernel declared so far a numba dispatcher (each compiles on its first
  call, as usual) and rebinds the package's module globals to them, so that kernels calling
  kernels compile as they did;
* without numba installed the kernels run as plain Python: correct, slow.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
import threading
from collections.abc import Callable
from typing import Any

from ..core import CORE


def _numba_installed() -> bool:
    """Whether numba can be imported, found without importing it."""
    try:
        return importlib.util.find_spec("numba") is not None
    except ImportError:  # a finder that refuses it
        return False


#: Whether numba is installed (found without importing it).
HAVE_NUMBA = _numba_installed()

_lock = threading.RLock()
_pending: list[LazyKernel] = []  # the kernels declared before numba was imported
_numba_njit: Callable[..., Any] | None = None  # numba.njit once imported, else None


class LazyKernel:
    """A reference kernel that numba compiles on its first call (numba imported then).

    Calls, and attributes of numba's dispatcher (``signatures``, ``_numba_type_``: numba types a
    lazy kernel met as a global like its dispatcher), go to the compiled kernel once it exists;
    ``py_func`` is the Python function.
    """

    def __init__(self, function: Callable[..., Any], options: dict[str, Any]) -> None:
        self.py_func = function
        self.options = options
        self.compiled: Callable[..., Any] | None = None
        self.__name__ = function.__name__
        self.__qualname__ = function.__qualname__
        self.__module__ = function.__module__
        self.__doc__ = function.__doc__
        self.__wrapped__ = function

    def __call__(self, *args: Any) -> Any:
        """Run the compiled kernel (compiled first if needed)."""
        compiled = self.compiled
        if compiled is None:
            compiled = _compile_all()[self]
        return compiled(*args)

    def __getattr__(self, name: str) -> Any:  # only for names not set above
        if name.startswith("__"):
            raise AttributeError(name)
        compiled = self.compiled if self.compiled is not None else _compile_all()[self]
        return getattr(compiled, name)

    def __repr__(self) -> str:
        return f"LazyKernel({self.__module__}.{self.__qualname__})"


def _fallback(**_: Any) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Without numba, ``njit(...)``: the kernel runs as plain Python."""
    return lambda function: function


def _compile_all() -> dict[LazyKernel, Callable[..., Any]]:
    """Import numba (once), make every pending kernel numba's, rebind the package's globals.

    Returns:
        Each kernel made so far -> its numba dispatcher (or its Python function without numba).

    """
    global _numba_njit
    with _lock:
        if _numba_njit is None:
            try:
                _numba_njit = importlib.import_module("numba").njit
            except ImportError:
                _numba_njit = _fallback
        done = {}
        for kernel in _pending:  # in declaration order: callees before their callers
            if kernel.compiled is None:
                kernel.compiled = _numba_njit(**kernel.options)(kernel.py_func)
            done[kernel] = kernel.compiled
        for name, module in list(sys.modules.items()):  # kernels calling kernels see numba's
            if name.partition(".")[0] != __name__.partition(".")[0] or module is None:
                continue
            space = vars(module)
            for key, value in list(space.items()):
                if isinstance(value, LazyKernel) and value.compiled is not None:
                    space[key] = value.compiled
        return done


def njit(*args: Any, **options: Any) -> Any:
    """The reference kernels' ``njit``, used as ``@njit(cache=True)``.

    numba's own when the compiled core is missing (the library runs the kernels), a
    `LazyKernel` when the core is built (numba imported on a first call), the function
    itself without numba.
    """
    if args and callable(args[0]):
        return njit(**options)(args[0])

    def decorate(function: Callable[..., Any]) -> Any:
        with _lock:
            if _numba_njit is not None:
                return _numba_njit(**options)(function)
            kernel = LazyKernel(function, options)
            _pending.append(kernel)
            return kernel

    return decorate


if CORE is None and HAVE_NUMBA:  # the library runs the reference kernels: numba from the start
    try:
        _numba_njit = importlib.import_module("numba").njit
    except ImportError:  # found but broken: plain Python, as without numba
        HAVE_NUMBA, _numba_njit = False, _fallback
elif not HAVE_NUMBA:
    _numba_njit = _fallback

__all__ = ["HAVE_NUMBA", "LazyKernel", "njit"]
