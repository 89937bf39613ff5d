"""Typed errors raised by :mod:`virtual_actuators`.

Every error derives from :class:`VirtualActuatorError`, so ``except va.VirtualActuatorError``
catches all of them. Messages name the offending frame, joint, axis or constraint and say what
would be valid.
"""

from __future__ import annotations

import difflib
import importlib
from collections.abc import Iterable
from types import ModuleType


class VirtualActuatorError(Exception):
    """Base class of every error raised by this library."""


class RobotNotFoundError(VirtualActuatorError, LookupError):
    """A robot name or URDF path could not be resolved."""


class RobotDescriptionError(VirtualActuatorError, ValueError):
    """A robot description (URDF) exists but cannot be loaded."""


class FrameNotFoundError(VirtualActuatorError, LookupError):
    """A frame name is not in the robot model."""


class JointNotFoundError(VirtualActuatorError, LookupError):
    """A joint name is not in the robot model (or not on the chains where it must be)."""


class InvalidAxisError(VirtualActuatorError, ValueError):
    """An axis name is not one of ``x y z rx ry rz`` or the axes are not an ordered subset."""


class InvalidInputError(VirtualActuatorError, ValueError):
    """An array argument has the wrong shape or holds NaN or infinite values."""


class ConstraintError(VirtualActuatorError, ValueError):
    """The declared constraints contradict each other or are too many."""


class SingularConfigurationError(VirtualActuatorError, ArithmeticError):
    """The force distribution cannot be solved at this configuration."""


class InadmissibleWrenchError(VirtualActuatorError, ValueError):
    """The requested wrench cannot be produced (raised by ``solve(..., strict=True)``)."""

    def __init__(self, message: str, solution: object | None = None) -> None:
        super().__init__(message)
        #: The least-squares :class:`~virtual_actuators.Solution` that was computed.
        self.solution = solution


class MissingDependencyError(VirtualActuatorError, ImportError):
    """An optional package this feature needs is missing (the message says what to install).

    Args:
        message: What is missing and the ``pip install`` command that brings it.
        package: The missing package's import name (``"meshcat"``), when known.
        extra: The extra of ``virtual_actuators`` that installs it (``"viz"``), when there is
            one.

    Attributes:
        package: The missing package, or None.
        extra: The extra that installs it, or None.

    """

    def __init__(self, message: str, *, package: str | None = None, extra: str | None = None):
        super().__init__(message, name=package)
        self.package = package
        self.extra = extra


def import_optional(module: str, extra: str, feature: str) -> ModuleType:
    """Import an optional dependency, or raise a :class:`MissingDependencyError`.

    Args:
        module: The module to import (``"meshcat"``, ``"mujoco"``...).
        extra: The extra of ``virtual_actuators`` that installs it (``"viz"``, ``"sim"``...).
        feature: What needs it, for the message (``"The MeshCat viewer"``).

    Returns:
        The module.

    Raises:
        MissingDependencyError: If the module (or its top-level package) is not installed.
            Other import errors (a broken installation) propagate unchanged.

    """
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as error:
        if error.name is not None and module.split(".")[0] != error.name.split(".")[0]:
            raise  # the package is there but one of its own imports is missing
        package = module.split(".")[0]
        raise MissingDependencyError(
            f"{feature} needs the package {package!r}, which is not installed: "
            f'pip install "virtual_actuators[{extra}]" (or "virtual_actuators[all]").',
            package=package,
            extra=extra,
        ) from error


def close_matches(name: str, candidates: Iterable[str], n: int = 5) -> list[str]:
    """Return the candidates closest to ``name``, best first.

    Args:
        name: The name that was not found.
        candidates: The valid names.
        n: How many matches at most.

    Returns:
        Up to ``n`` close matches (possibly none).

    """
    candidates = list(candidates)
    matches = difflib.get_close_matches(name, candidates, n=n, cutoff=0.4)
    if len(matches) < n:
        lowered = name.lower()
        matches += [c for c in candidates if lowered in c.lower() and c not in matches]
    return matches[:n]


def suggestion(name: str, candidates: Iterable[str], what: str) -> str:
    """Format a ``did you mean`` hint listing the valid names closest to ``name``.

    Args:
        name: The name that was not found.
        candidates: The valid names.
        what: What the names are (``"frames"``, ``"joints"``, ...).

    Returns:
        A sentence such as ``"Closest frames: 'FL_FOOT', 'FR_FOOT'."``.

    """
    candidates = list(candidates)
    matches = close_matches(name, candidates)
    if matches:
        return f"Closest {what}: " + ", ".join(repr(m) for m in matches) + "."
    shown = ", ".join(repr(c) for c in candidates[:12])
    more = f" (and {len(candidates) - 12} more)" if len(candidates) > 12 else ""
    return f"Known {what}: {shown}{more}."
