"""Typed errors of `virtual_actuators` (all derive from [`VirtualActuatorError`][]); notices."""

from __future__ import annotations

import importlib
import logging
from collections.abc import Iterable
from pathlib import Path
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


class GaitPatternError(InvalidInputError):
    """A named gait pattern does not fit the robot's feet (the message names those that do)."""


class ConstraintError(VirtualActuatorError, ValueError):
    """The declared constraints contradict each other or are too many."""


class SingularConfigurationError(VirtualActuatorError, ArithmeticError):
    """The force distribution cannot be solved at this configuration."""


class InadmissibleWrenchError(VirtualActuatorError, ValueError):
    """The requested wrench cannot be produced (raised by ``solve(..., strict=True)``)."""

    def __init__(self, message: str, solution: object | None = None) -> None:
        super().__init__(message)
        #: The least-squares [`Solution`][virtual_actuators.Solution] that was computed.
        self.solution = solution


class ConcurrentUseError(VirtualActuatorError, RuntimeError):
    """An object that carries one run's state (a compiled machine) was used from two threads."""


class TraceError(VirtualActuatorError, TypeError):
    """A piece of a declaration cannot be lowered into a compiled plan (a strict lowering)."""


class MissingDependencyError(VirtualActuatorError, ImportError):
    """An optional package this feature needs is missing (the message says what to install).

    Args:
        message: What is missing and the ``pip install`` command that brings it.
        package: The missing package's import name (``"meshcat"``), when known.
        extra: The extra of ``virtual_actuators`` that installs it (``"viz"``), if any.

    Attributes:
        package: The missing package, or None.
        extra: The extra that installs it, or None.
    """

    def __init__(self, message: str, *, package: str | None = None, extra: str | None = None):
        super().__init__(message, name=package)
        self.package = package
        self.extra = extra


def import_optional(module: str, extra: str, feature: str) -> ModuleType:
    """Import an optional dependency, or raise a [`MissingDependencyError`][].

    Args:
        module: The module to import (``"meshcat"``, ``"mujoco"``...).
        extra: The extra of ``virtual_actuators`` that installs it (``"viz"``, ``"sim"``...).
        feature: What needs it, for the message (``"The MeshCat viewer"``).

    Raises:
        MissingDependencyError: If the module's top-level package is not installed (the message
            gives `install_command`). Other import errors propagate unchanged.
    """
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as error:
        if error.name is not None and module.split(".")[0] != error.name.split(".")[0]:
            raise  # the package is there but one of its own imports is missing
        package = module.split(".")[0]
        raise MissingDependencyError(
            f"{feature} needs the package {package!r}, which is not installed. Install the "
            f"extra [{extra}] of virtual_actuators: {install_command(extra)}.",
            package=package,
            extra=extra,
        ) from error


#: The extras that the extra ``all`` brings (the cluster engines ``dask`` and ``ray`` are apart).
EXTRAS_IN_ALL = ("viz", "sim", "plots", "urdf")


def install_command(extra: str) -> str:
    """How to add the extra ``extra`` (``"sim"``) to this copy of ``virtual_actuators``.

    From where pip recorded this copy came from (PEP 610's ``direct_url.json``; ``-e`` if
    editable), else the command to run in the source folder.

    Args:
        extra: The extra's name.

    Returns:
        Text such as ``pip install -e ".[sim]" in the source folder (".[all]" for every
        extra)`` (``[all]`` only for the extras in `EXTRAS_IN_ALL`).
    """
    source, editable = _installed_from()
    flag = "-e " if editable else ""
    where = "." if source is None else source
    command = f'pip install {flag}"{where}[{extra}]"'
    if source is None:
        command += " in the source folder"
    if extra in EXTRAS_IN_ALL:
        command += f' ("{where}[all]" for every extra)'
    return command


def _installed_from() -> tuple[str | None, bool]:
    """``(path, editable)`` pip installed this package from; ``(None, True)`` when not known."""
    import json
    from importlib import metadata
    from urllib.parse import unquote, urlparse

    try:
        text = metadata.distribution("virtual_actuators").read_text("direct_url.json")
        record = json.loads(text) if text else {}
    except (metadata.PackageNotFoundError, OSError, ValueError):
        return None, True
    url = urlparse(str(record.get("url", "")))
    path = Path(unquote(url.path))
    if url.scheme != "file" or not path.exists():
        return None, True
    return str(path), bool(record.get("dir_info", {}).get("editable", False))


def _key(name: str) -> str:
    """A name as compared by `closest_names`: lower case, without ``-`` and ``_``."""
    return name.lower().replace("-", "").replace("_", "")


def edit_distance(a: str, b: str) -> int:
    """Damerau-Levenshtein distance (optimal string alignment) between ``a`` and ``b``."""
    previous2: list[int] = []
    previous = list(range(len(b) + 1))
    for i, char_a in enumerate(a, start=1):
        current = [i] + [0] * len(b)
        for j, char_b in enumerate(b, start=1):
            cost = 0 if char_a == char_b else 1
            current[j] = min(previous[j] + 1, current[j - 1] + 1, previous[j - 1] + cost)
            if i > 1 and j > 1 and char_a == b[j - 2] and a[i - 2] == char_b:
                current[j] = min(current[j], previous2[j - 2] + 1)
        previous2, previous = previous, current
    return previous[-1]


def closest_names(name: str, candidates: Iterable[str], n: int = 5) -> list[str]:
    """The candidates closest to ``name``, best first: the one "did you mean" of the library.

    Names are compared in lower case without ``-`` and ``_``, by Damerau-Levenshtein distance.
    A candidate is close when its distance is at most half the length of the longer name (at
    least 2), or when one name contains the other. Ranked: equal but for case first, then the
    smallest distance, then containing or contained, then the closest length, then alphabetically.

    Args:
        name: The name that was not found.
        candidates: Known names.
        n: How many names at most.

    Returns:
        Up to ``n`` names (possibly none).
    """
    lowered = name.lower()
    wanted = _key(name)
    ranked = []
    for candidate in dict.fromkeys(candidates):
        key = _key(candidate)
        contained = bool(wanted) and bool(key) and (wanted in key or key in wanted)
        close = max(2, max(len(wanted), len(key)) // 2)
        if not contained and abs(len(wanted) - len(key)) > close:
            continue  # the distance is at least the difference in length: too far, not computed
        distance = edit_distance(wanted, key)
        if contained or distance <= close:
            same_but_case = candidate.lower() == lowered
            ranked.append(
                (not same_but_case, distance, not contained, abs(len(key) - len(wanted)), candidate)
            )
    return [candidate for *_, candidate in sorted(ranked)[:n]]


def suggestion(name: str, candidates: Iterable[str], what: str) -> str:
    """A ``did you mean`` sentence such as ``"Closest frames: 'FL_FOOT', 'FR_FOOT'."``.

    Args:
        name: The name that was not found.
        candidates: The valid names.
        what: What the names are (``"frames"``, ``"joints"``, ...).
    """
    candidates = list(candidates)
    matches = closest_names(name, candidates)
    if matches:
        return f"Closest {what}: " + ", ".join(repr(m) for m in matches) + "."
    shown = ", ".join(repr(c) for c in candidates[:12])
    more = f" (and {len(candidates) - 12} more)" if len(candidates) > 12 else ""
    return f"Known {what}: {shown}{more}."


#: The logger of the library's notices; ``NOTICES.setLevel(logging.ERROR)`` silences them.
NOTICES = logging.getLogger("virtual_actuators")

_noticed: set[str] = set()


def notice(message: str) -> None:
    """Tell the user, once per process, something the library did for them (on `NOTICES`)."""
    if message not in _noticed:
        _noticed.add(message)
        NOTICES.warning(message)
