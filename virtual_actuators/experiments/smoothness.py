"""Is a closed loop smooth at its tick rate? Figures of every tick's efforts and base rates.

Definitions of the figures: the "Command line" page, section on a walk's summary line.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from ..exceptions import InvalidInputError
from ..vocabulary.arguments import as_float_array, check_number

#: Ticks after the start of a run left out (its start-up) [s].
SKIP_S = 1.0
#: The percentile over the ticks of the oscillation figures.
PERCENTILE = 75.0
#: The base rate's changes from tick to tick in a zigzag exceed this [rad/s] (a smooth motion
#: changes it by ``|dw/dt| dt`` and does not reverse three times in a row).
RATE_FLOOR_RADPS = 0.01


@dataclass(frozen=True, kw_only=True)
class SmoothnessFigures:
    """The smoothness figures a walk's metrics carry (None: not measured).

    Attributes:
        effort_oscillation: Tick-rate oscillation ``|tau_k - (tau_{k-1} + tau_{k+1}) / 2|``, its
            `PERCENTILE` th percentile on the worst joint, a fraction of its effort limit [-].
        effort_oscillation_joint: That joint.
        effort_change_rms: RMS change of the efforts per tick, a fraction of the limits [-].
        base_rate_alternation: Fraction of ticks at which the base's angular rate zigzags (three
            sign reversals in a row of changes above `RATE_FLOOR_RADPS`), worst axis [-].
        base_rate_oscillation_radps: The same percentile as ``effort_oscillation`` of the base
            rate, worst axis [rad/s].
    """

    effort_oscillation: float | None = None
    effort_oscillation_joint: str | None = None
    effort_change_rms: float | None = None
    base_rate_alternation: float | None = None
    base_rate_oscillation_radps: float | None = None

    def smoothness_summary(self) -> str:
        """``effort osc 0.12 % (LF_HAA), change 1.3 %/tick, base rate alternating 0.0 %``.

        Empty when not measured; the base rate's part only when measured.
        """
        if self.effort_oscillation is None:
            return ""
        text = (
            f"effort osc {_percent(self.effort_oscillation)} ({self.effort_oscillation_joint}), "
            f"change {_percent(self.effort_change_rms, 1)}/tick"
        )
        if self.base_rate_alternation is not None:
            text += f", base rate alternating {_percent(self.base_rate_alternation, 1)}"
        return text


def _percent(fraction: float | None, digits: int = 2) -> str:
    """``fraction`` in percent (never ``-0.00``), ``n/a`` for None."""
    return "n/a" if fraction is None else f"{abs(100.0 * fraction):.{digits}f} %"


@dataclass(frozen=True)
class EffortSmoothness:
    """How smooth a run's efforts and base rates are at the tick rate.

    Attributes:
        oscillation: `SmoothnessFigures.effort_oscillation` (None: no limited joint, or no
            tick after the skip with both neighbours).
        oscillation_joint: The worst joint.
        change_rms: `SmoothnessFigures.effort_change_rms` (None: as above).
        rate_alternation: `SmoothnessFigures.base_rate_alternation` (None: no base rates, or
            no tick after the skip with two neighbours on each side).
        rate_oscillation_radps: `SmoothnessFigures.base_rate_oscillation_radps` [rad/s].
        joints: The joints measured (those with a limit).
        joint_oscillation: Each one's oscillation figure [-], in ``joints``' order.
        joint_change_rms: Each one's RMS change per tick [-].
        ticks: Ticks measured (after the skip).
        rate_floor_radps: A zigzag's least change per tick [rad/s].
    """

    oscillation: float | None
    oscillation_joint: str | None
    change_rms: float | None
    rate_alternation: float | None
    rate_oscillation_radps: float | None
    joints: tuple[str, ...]
    joint_oscillation: tuple[float, ...]
    joint_change_rms: tuple[float, ...]
    ticks: int
    rate_floor_radps: float = RATE_FLOOR_RADPS

    def figures(self) -> SmoothnessFigures:
        """The figures a walk's metrics carry."""
        return SmoothnessFigures(
            effort_oscillation=self.oscillation,
            effort_oscillation_joint=self.oscillation_joint,
            effort_change_rms=self.change_rms,
            base_rate_alternation=self.rate_alternation,
            base_rate_oscillation_radps=self.rate_oscillation_radps,
        )

    def metrics_fields(self) -> dict[str, Any]:
        """`figures` as keyword arguments (``dataclasses.replace(metrics, **...)``)."""
        return asdict(self.figures())

    def summary(self) -> str:
        """One line: `SmoothnessFigures.smoothness_summary`."""
        return self.figures().smoothness_summary() or "not measured"

    def to_dict(self) -> dict[str, Any]:
        """A JSON-able dict (tuples as lists)."""
        return {k: list(v) if isinstance(v, tuple) else v for k, v in asdict(self).items()}


def effort_smoothness(
    efforts: object,
    limits: object,
    base_rates: object | None = None,
    *,
    time_step: float = 1e-3,
    skip_s: float = SKIP_S,
    names: Sequence[str] | None = None,
    rate_floor_radps: float = RATE_FLOOR_RADPS,
) -> EffortSmoothness:
    """Measure a run's smoothness at the tick rate.

    Args:
        efforts: ``(ticks, nv)`` every tick's applied efforts [N m or N].
        limits: ``(nv,)`` effort limits [N m or N]; a joint whose limit is not positive and
            finite is left out.
        base_rates: ``(ticks, 1 to 3)`` the base's angular velocity at every tick [rad/s], or None.
        time_step: Time between two ticks [s].
        skip_s: Ticks before this time (tick 0 at 0 s) are left out [s].
        names: ``nv`` names of the degrees of freedom (default ``"dof <index>"``).
        rate_floor_radps: The least change per tick of a zigzag of the base rate [rad/s].

    Returns:
        The `EffortSmoothness` (its figures None when too few ticks remain after the skip).

    Raises:
        InvalidInputError: Arrays of the wrong shape or with non-finite entries (a NaN limit
            included), ``names`` of the wrong length, or a bad ``time_step``, ``skip_s`` or
            ``rate_floor_radps``.
    """
    tau = _checked(efforts, "efforts", "a (ticks, nv) array of finite efforts", 2)
    ticks, nv = tau.shape
    upper = as_float_array(limits, "limits", f"({nv},) effort limits")
    if upper.shape != (nv,) or np.isnan(upper).any():
        raise InvalidInputError(f"limits must be {nv} numbers (inf where unlimited), got {upper}.")
    if names is None:
        names = [f"dof {j}" for j in range(nv)]
    elif isinstance(names, str) or len(names) != nv:
        raise InvalidInputError(f"names must be {nv} names, got {names!r}.")
    dt = check_number(time_step, "time_step", positive=True)
    skip = check_number(skip_s, "skip_s", minimum=0.0)
    floor = check_number(rate_floor_radps, "rate_floor_radps", minimum=0.0)
    start = max(1, math.ceil(skip / dt - 1e-9))  # the first tick measured (it has a neighbour)
    limited = np.flatnonzero(np.isfinite(upper) & (upper > 0.0))
    scaled = tau[:, limited] / upper[limited]  # [-]
    joints = tuple(str(names[j]) for j in limited)
    measured = max(0, ticks - 1 - start)  # ticks k in [start, ticks - 2]
    per_joint = _percentiles(_second_differences(scaled, start))
    changes = np.diff(scaled[start - 1 :], axis=0)  # tau_k - tau_{k-1}, k in [start, ticks - 1]
    worst = int(np.argmax(per_joint)) if per_joint.size and measured else None
    squares = (changes**2).mean(axis=0) if worst is not None else np.zeros(0)
    alternation, oscillation = _rate_figures(base_rates, ticks, start, floor)
    return EffortSmoothness(
        oscillation=None if worst is None else float(per_joint[worst]),
        oscillation_joint=None if worst is None else joints[worst],
        change_rms=None if worst is None else float(np.sqrt(squares.mean())),
        rate_alternation=alternation,
        rate_oscillation_radps=oscillation,
        joints=joints,
        joint_oscillation=() if worst is None else tuple(map(float, per_joint)),
        joint_change_rms=tuple(map(float, np.sqrt(squares))),
        ticks=measured,
        rate_floor_radps=floor,
    )


def _checked(value: object, what: str, expected: str, ndim: int) -> np.ndarray:
    """``value`` as a finite float array of ``ndim`` dimensions, else an InvalidInputError."""
    array = as_float_array(value, what, expected)
    if array.ndim != ndim or not np.isfinite(array).all():
        shown = f"shape {array.shape}" if array.ndim != ndim else "non-finite entries"
        raise InvalidInputError(f"{what} must be {expected}, got {shown}.")
    return array


def _second_differences(signal: np.ndarray, start: int) -> np.ndarray:
    """``|x_k - (x_{k-1} + x_{k+1}) / 2|`` for the ticks ``k`` in ``[start, ticks - 2]``."""
    if len(signal) < start + 2:
        return np.zeros((0, signal.shape[1]))
    window = signal[start - 1 :]
    return np.abs(window[1:-1] - 0.5 * (window[:-2] + window[2:]))


def _percentiles(values: np.ndarray) -> np.ndarray:
    """Each column's `PERCENTILE` th percentile (none for no rows)."""
    if not len(values):
        return np.zeros(0)
    return np.percentile(values, PERCENTILE, axis=0)


def _rate_figures(
    base_rates: object | None, ticks: int, start: int, floor: float
) -> tuple[float | None, float | None]:
    """The base rate's alternation (fraction of ticks) and oscillation [rad/s], worst axis."""
    if base_rates is None:
        return None, None
    expected = f"a ({ticks}, axes) array of finite base rates (1 to 3 axes)"
    rates = _checked(base_rates, "base_rates", expected, 2)
    if len(rates) != ticks or not 1 <= rates.shape[1] <= 3:
        raise InvalidInputError(f"base_rates must be {expected}, got shape {rates.shape}.")
    start = max(start, 2)  # a zigzag at tick k reads w_{k-2} to w_{k+2}
    if len(rates) < start + 3:
        return None, None
    changes = np.diff(rates[start - 2 :], axis=0)  # c_i, i in [start - 1, ticks - 1]
    big, reversed_ = np.abs(changes) > floor, changes[:-1] * changes[1:] < 0.0
    zigzag = reversed_[:-2] & reversed_[1:-1] & reversed_[2:] & big[:-3] & big[1:-2] & big[2:-1]
    zigzag &= big[3:]  # ticks k in [start, ticks - 3]
    second = _second_differences(rates, start)
    return float(np.max(np.mean(zigzag, axis=0))), float(np.max(_percentiles(second)))
