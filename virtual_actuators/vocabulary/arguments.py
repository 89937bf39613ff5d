"""Argument checks shared by the API: each raises a [`VirtualActuatorError`][] naming it."""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterable, Mapping, Sequence, Set

import numpy as np
import pinocchio as pin

from ..exceptions import InvalidInputError, VirtualActuatorError


def describe(value: object) -> str:
    """``"<type> <repr>"`` of a user's argument for error messages, the repr on one short line."""
    text = " ".join(repr(value).split())
    if len(text) > 60:
        text = text[:57] + "..."
    return f"{type(value).__name__} {text}"


def check_sequence(
    value: object,
    what: str,
    label: str,
    kind: type | tuple[type, ...] | None = None,
    single: type | tuple[type, ...] | None = None,
) -> Sequence:
    """Return ``value`` (named ``what``) as a sequence (a tuple unless it already is one).

    Every entry must be a ``kind`` (``label`` in messages, e.g. ``"va.Component"``) if given; a
    ``value`` that is a ``single`` stands alone: ``(value,)``.

    Raises:
        InvalidInputError: ``value`` is a str, bytes, a mapping or not iterable, or an entry is
            not a ``kind``.
    """
    if single is not None and isinstance(value, single):
        return (value,)
    if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, Iterable):
        raise InvalidInputError(f"{what} must be a sequence of {label}, got {describe(value)}.")
    values = value if isinstance(value, Sequence) else tuple(value)
    if kind is not None:
        for i, entry in enumerate(values):
            if not isinstance(entry, kind):
                raise InvalidInputError(f"{what}[{i}] must be a {label}, got {describe(entry)}.")
    return values


def check_robot(robot: object, where: str) -> None:
    """Check that ``robot`` is a robot (a [`Robot`][] or alike); ``where`` names the callee.

    Raises:
        InvalidInputError: ``robot`` has no Pinocchio ``model`` (None, a name, a bare model).
    """
    if isinstance(getattr(robot, "model", None), pin.Model):
        return
    hint = ""
    if isinstance(robot, str):
        hint = f" Load it first: va.load_robot({robot!r})."
    elif isinstance(robot, pin.Model):
        hint = " Wrap a Pinocchio model in va.Robot(name, model)."
    raise InvalidInputError(
        f"{where}: robot must be a va.Robot (e.g. va.load_robot('solo12')), got "
        f"{describe(robot)}.{hint}"
    )


def check_name(
    value: object, what: str, error: type[VirtualActuatorError] = InvalidInputError
) -> str:
    """Return ``value`` if it is a str, else raise ``error`` naming ``what``.

    Raises:
        VirtualActuatorError: ``error`` (by default [`InvalidInputError`][]).
    """
    if not isinstance(value, str):
        raise error(f"{what} must be a name (str), got {describe(value)}.")
    return value


def check_names(
    value: object,
    what: str,
    error: type[VirtualActuatorError] = InvalidInputError,
    ordered: bool = True,
) -> tuple[str, ...]:
    """Return a name or a collection of names (``what``) as a tuple of str.

    ``error`` is raised for an entry that is not a str; ``ordered`` rejects sets (their order is
    arbitrary).

    Raises:
        InvalidInputError: ``value`` is None, a number, a dict, bytes (or a set if ``ordered``).
        VirtualActuatorError: ``error`` for an entry that is not a str.
    """
    if isinstance(value, str):
        return (value,)
    unordered = ordered and isinstance(value, Set)
    if isinstance(value, (bytes, Mapping)) or unordered or not isinstance(value, Iterable):
        kind = "an ordered sequence" if ordered else "a collection"
        raise InvalidInputError(
            f"{what} must be a name or {kind} of names (str), got {describe(value)}."
        )
    names = tuple(value)
    for i, name in enumerate(names):
        if not isinstance(name, str):
            raise error(f"{what}[{i}] must be a name (str), got {describe(name)}.")
    return tuple(str(name) for name in names)


def _valid(minimum: float | None, positive: bool, allow_inf: bool) -> str:
    """What `check_number` accepts, in words (for its messages)."""
    valid = "a real number"
    if positive:
        valid += " > 0"
    elif minimum is not None:
        valid += f" >= {minimum:g}"
    return valid + ("" if allow_inf else " (finite)")


def check_number(
    value: object,
    what: str,
    minimum: float | None = None,
    positive: bool = False,
    allow_inf: bool = False,
    error: type[VirtualActuatorError] = InvalidInputError,
) -> float:
    """Return ``value`` (named ``what``) as a float, checked to be a real number in range.

    ``minimum`` is inclusive; ``positive`` requires ``value > 0``; ``allow_inf`` accepts ``inf``
    (never NaN).

    Raises:
        VirtualActuatorError: ``error`` (by default [`InvalidInputError`][]) for a bool, a
            complex number, a str, None, NaN, an infinity unless ``allow_inf``, or a value out
            of range.
    """
    # a plain float is a real number: the abstract-class checks run only for other types
    if type(value) is not float and (
        isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real)
    ):
        valid = _valid(minimum, positive, allow_inf)
        raise error(f"{what} must be {valid}, got {describe(value)}.")
    number = float(value)
    if (
        (-math.inf < number < math.inf or (allow_inf and number == number))
        and (not positive or number > 0.0)
        and (minimum is None or number >= minimum)
    ):
        return number
    shown = "NaN" if math.isnan(number) else repr(number)
    raise error(f"{what} must be {_valid(minimum, positive, allow_inf)}, got {shown}.")


def check_flag(value: object, what: str) -> bool:
    """Return ``value`` as a bool if it is one (numpy's included).

    Raises:
        InvalidInputError: Anything else (a str such as ``"no"`` is not a flag).
    """
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise InvalidInputError(f"{what} must be True or False, got {describe(value)}.")


def as_float_array(value: object, what: str, expected: str, copy: bool = False) -> np.ndarray:
    """Return an array-like of real numbers as float64 (the slow path of per-tick arguments).

    ``what`` names the argument and ``expected`` what is valid in messages; ``copy``: never
    ``value`` itself or a view of it.

    Raises:
        InvalidInputError: None, a str, a dict, a set, ragged nesting, or entries that are
            complex, bool, str or other non-numbers.
    """
    if value is None or isinstance(value, (str, bytes, Mapping, Set)):
        raise InvalidInputError(f"{what} must be {expected}, got {describe(value)}.")
    try:
        array = np.asarray(value)
        kind = array.dtype.kind
        if kind in "fiu":
            return array.astype(np.float64, copy=copy and isinstance(value, np.ndarray))
        if kind == "O":
            if any(isinstance(x, (complex, bool, np.bool_, str)) for x in array.flat):
                raise TypeError
            return array.astype(np.float64)
    except (TypeError, ValueError):
        pass
    else:
        if kind == "c":
            raise InvalidInputError(
                f"{what} must be {expected}, got complex values (the imaginary part would be lost)."
            )
        if kind == "b":
            raise InvalidInputError(f"{what} must be {expected}, got bool values.")
    raise InvalidInputError(f"{what} must be {expected}, got {describe(value)}.")
