"""Torque limits of the actuated joints: ``-limit <= tau_v <= limit``, two-sided rows."""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from ..exceptions import InvalidInputError
from ..vocabulary.arguments import as_float_array

#: Effort limits at or above this [N m, N] mean "unlimited" (URDFs write "none" as 1e308).
UNLIMITED = 1e30


class TorqueLimits:
    """The torque limits of the joints that a chain moves and an actuator drives.

    Args:
        model: The Pinocchio model (``effortLimit``, ``nv``).
        torque_limits: False (none), True (URDF effort limits) or ``(nv,)`` limits [N m, N].
        on_chain: ``(nv,)`` whether some chain moves each joint.
        actuated: ``(nv,)`` whether each joint is actuated (not limp, not passive).

    Raises:
        InvalidInputError: ``torque_limits`` is not True, False or ``nv`` numbers >= 0.
    """

    def __init__(
        self,
        model: object,
        torque_limits: bool | Sequence[float] | np.ndarray,
        on_chain: np.ndarray,
        actuated: np.ndarray,
    ) -> None:
        if torque_limits is True:
            limits = np.asarray(model.effortLimit, dtype=float).copy()
            limits[(limits <= 0) | ~np.isfinite(limits)] = np.inf
        elif torque_limits is False or torque_limits is None:
            limits = np.full(model.nv, np.inf)
        else:
            valid = f"True, False or {model.nv} numbers >= 0 [N m, N]"
            limits = as_float_array(torque_limits, "torque_limits", valid).reshape(-1)
            if limits.shape != (model.nv,) or np.any(np.isnan(limits)) or np.any(limits < 0):
                raise InvalidInputError(
                    f"torque_limits must be True, False or {model.nv} numbers >= 0, got "
                    f"{torque_limits!r}."
                )
        limits = np.where(limits >= UNLIMITED, np.inf, limits)
        # a joint that no chain moves would give an all-zero row (a stall for ProxQP): left out
        limited = actuated & np.isfinite(limits) & on_chain
        #: ``(t,)`` velocity indices of the limited joints
        self.limited_v = np.flatnonzero(limited)
        #: ``(t,)`` their limits [N m, N]
        self.limits = limits[self.limited_v]

    def names(self, joint_name: Callable[[int], str]) -> list[str]:
        """The rows' names, ``joint_name(v)`` naming velocity index ``v``."""
        return [
            f"torque {joint_name(int(v))}: |tau| <= {limit:g}"
            for v, limit in zip(self.limited_v, self.limits, strict=True)
        ]

    def rows(self, torque_map: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(G, lows, uppers)``: ``-limit <= tau <= limit`` with ``tau = torque_map x``."""
        return torque_map[self.limited_v], -self.limits, self.limits
