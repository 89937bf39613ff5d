"""A controller's effort limits (the URDF's, checked, the clip) and its optional rate limit."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..exceptions import InvalidInputError, JointNotFoundError, suggestion
from ..models.robot import Robot
from ..vocabulary.arguments import as_float_array, check_number


def urdf_effort_limits(robot: Robot) -> np.ndarray:
    """``(nv,)`` a 1-dof joint's positive finite URDF ``effortLimit`` [N m, N], else ``inf``."""
    model = robot.model
    effort = np.asarray(model.effortLimit, dtype=float)
    one_dof = [model.joints[j].idx_v for j in range(1, model.njoints) if model.joints[j].nv == 1]
    usable = [i for i in one_dof if np.isfinite(effort[i]) and effort[i] > 0.0]
    limits = np.full(model.nv, np.inf)
    limits[usable] = effort[usable]
    return limits


def check_effort_limits(limits: object, nv: int) -> tuple[np.ndarray, np.ndarray]:
    """``(lower, upper)`` read-only copies of ``limits`` (``upper``; ``lower = -upper``).

    Raises:
        InvalidInputError: Not ``nv`` numbers, or a NaN or negative entry.
    """
    expected = f"{nv} numbers >= 0 (inf where unlimited)"
    upper = as_float_array(limits, "effort_limits", expected, copy=True)
    if upper.shape != (nv,) or np.isnan(upper).any() or (upper < 0.0).any():
        raise InvalidInputError(f"effort_limits must be {expected}, got {upper}.")
    lower = -upper
    upper.setflags(write=False)
    lower.setflags(write=False)
    return lower, upper


def clip_efforts(
    requested: np.ndarray, lower: np.ndarray, upper: np.ndarray, clip: bool
) -> tuple[np.ndarray, np.ndarray]:
    """``(efforts, saturated)``: ``requested`` clipped to the limits (a copy when not ``clip``).

    ``saturated`` is True where the request exceeds a limit (clipped there when ``clip``).
    """
    if clip:
        tau = np.minimum(np.maximum(requested, lower), upper)
        return tau, tau != requested  # clipped exactly where the request exceeds a limit
    return requested.copy(), np.abs(requested) > upper


@dataclass(frozen=True)
class LimitFraction:
    """An effort rate limit as a multiple of each joint's effort limit per second.

    Attributes:
        per_second: [1/s] (> 0): 20 lets an effort cross its whole limit in 50 ms.

    Raises:
        InvalidInputError: ``per_second`` is not a positive finite number.
    """

    per_second: float

    def __post_init__(self) -> None:
        check_number(self.per_second, "LimitFraction: per_second [1/s]", positive=True)


#: What ``effort_rate_limit=`` takes
RateSpec = float | Sequence[float] | np.ndarray | Mapping[str, float] | LimitFraction | None


def effort_rates(
    spec: RateSpec, limits: np.ndarray, joint_names: Sequence[str]
) -> np.ndarray | None:
    """``(nv,)`` rates [N m/s or N/s], ``inf`` where unlimited, from ``spec``; None for None.

    ``limits`` are the controller's effort limits (`LimitFraction` scales them).

    Raises:
        InvalidInputError: A rate that is not a positive number (``inf`` allowed), the wrong
            number of rates, or a spec of another kind.
        JointNotFoundError: A dict naming a joint the robot lacks (with close matches).
    """
    nv = len(joint_names)
    if spec is None:
        return None
    if isinstance(spec, LimitFraction):
        return spec.per_second * np.asarray(limits, dtype=float)
    if isinstance(spec, Mapping):
        rates = np.full(nv, np.inf)
        for joint, rate in spec.items():
            if joint not in joint_names:
                raise JointNotFoundError(
                    f"effort_rate_limit names {joint!r}, not a joint of the robot. "
                    f"{suggestion(str(joint), joint_names, 'joints')}"
                )
            rates[joint_names.index(joint)] = _rate(rate, f"effort_rate_limit[{joint!r}]")
        return rates
    expected = (
        "a number > 0 [N m/s], one per velocity entry, a {joint: rate} dict or a LimitFraction"
    )
    values = as_float_array(spec, "effort_rate_limit", expected, copy=True)
    if values.ndim == 0:
        values = np.full(nv, _rate(float(values), "effort_rate_limit"))
    if values.shape != (nv,):
        raise InvalidInputError(f"effort_rate_limit must be {expected}; got shape {values.shape}.")
    for index, value in enumerate(values.tolist()):
        _rate(value, f"effort_rate_limit[{index}] ({joint_names[index]})")
    return values


def _rate(value: object, what: str) -> float:
    return check_number(value, f"{what} [N m/s]", positive=True, allow_inf=True)


class EffortRateLimit:
    """The rate limit's state: the last efforts and when they were given (rates [N m/s])."""

    def __init__(self, rates: np.ndarray) -> None:
        self.rates = np.asarray(rates, dtype=float)
        self._unlimited = np.isinf(self.rates)  # inf * 0 s would be NaN
        self.previous: np.ndarray | None = None
        self.time = -np.inf

    def restart(self, tau: object, time: float) -> None:
        """Limit the next tick from ``tau`` given at ``time`` (None: the next tick is free).

        Raises:
            InvalidInputError: ``tau`` is not ``nv`` finite numbers, or ``time`` not finite.
        """
        time = check_number(time, "reset_effort_rate: time [s]")
        if tau is None:
            self.previous, self.time = None, -np.inf
            return
        nv = self.rates.shape[0]
        tau = as_float_array(tau, "reset_effort_rate: tau", f"{nv} finite numbers", copy=True)
        if tau.shape != (nv,) or not np.isfinite(tau).all():
            raise InvalidInputError(f"reset_effort_rate: tau must be {nv} finite numbers.")
        self.previous, self.time = tau, time

    def apply(self, tau: np.ndarray, time: float) -> tuple[np.ndarray, np.ndarray]:
        """``(efforts, limited)``: ``tau`` moved in place at most the rate's step from the last.

        ``limited`` is True on the joints held back.
        """
        previous = self.previous
        if previous is None or time < self.time:  # the first tick, or a new run
            self.previous, self.time = tau.copy(), time
            return tau, np.zeros(tau.shape, dtype=bool)
        step = np.where(self._unlimited, np.inf, self.rates * (time - self.time))
        low, high = previous - step, previous + step
        limited = (tau < low) | (tau > high)
        np.minimum(np.maximum(tau, low, out=tau), high, out=tau)
        self.previous, self.time = tau.copy(), time
        return tau, limited
