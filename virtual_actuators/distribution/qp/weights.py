"""Per-axis weights of the QP's closest wrench: ``sum_a weight_a (produced_a - requested_a)^2``."""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence

import numpy as np

from ...exceptions import InvalidAxisError, InvalidInputError
from ...vocabulary.arguments import describe


def check_weights(weights: object, axes: Sequence[str], what: str = "weights") -> np.ndarray:
    """``weights`` as a read-only ``(n,)`` array of finite numbers > 0 over ``axes``.

    Args:
        weights: ``{axis: weight}`` (the axes not named keep 1), or ``n`` numbers over ``axes``.
        axes: The actuator's axes.
        what: The argument's name, for messages.

    Raises:
        InvalidAxisError: A key of the dict is not one of ``axes``.
        InvalidInputError: A weight that is not a finite number > 0 (the message names its
            axis), an array of the wrong length, or neither a dict nor a sequence.
    """
    axes = tuple(axes)
    if isinstance(weights, Mapping):
        out = np.ones(len(axes))
        for axis, value in weights.items():
            if not isinstance(axis, str) or axis not in axes:
                raise InvalidAxisError(
                    f"{what} names axis {axis!r}, not one of this actuator's axes {axes}."
                )
            out[axes.index(axis)] = _weight(value, f"{what}[{axis!r}]")
    elif isinstance(weights, np.ndarray) or (
        isinstance(weights, Iterable) and not isinstance(weights, (str, bytes))
    ):
        try:
            out = np.array(weights, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            out = None
        if out is None or out.shape != (len(axes),):
            raise InvalidInputError(
                f"{what} must be {len(axes)} numbers > 0 (one per axis {axes}) or a dict "
                f"{{axis: weight}}, got {describe(weights)}."
            )
        bad = ~((out > 0.0) & (out < np.inf))  # NaN fails both
        if bad.any():
            axis = axes[int(np.argmax(bad))]
            raise InvalidInputError(
                f"{what}[{axis!r}] must be a finite number > 0, got {out[axes.index(axis)]!r}."
            )
    else:
        raise InvalidInputError(
            f"{what} must be a dict {{axis: weight > 0}} or {len(axes)} numbers > 0 over the "
            f"axes {axes}, got {describe(weights)}."
        )
    out.setflags(write=False)
    return out


def _weight(value: object, what: str) -> float:
    """One weight: a real number, finite and > 0."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise InvalidInputError(f"{what} must be a finite number > 0, got {describe(value)}.")
    number = float(value)
    if not 0.0 < number < np.inf:
        raise InvalidInputError(f"{what} must be a finite number > 0, got {number!r}.")
    return number


__all__ = ["check_weights"]
