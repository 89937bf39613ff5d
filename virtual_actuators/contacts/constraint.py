"""Linear inequalities over the stacked reaction forces, a name per row; the torque limits' rows."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..exceptions import InvalidInputError
from ..vocabulary.arguments import as_float_array


@dataclass(frozen=True, slots=True)
class Constraint:
    """``lows <= G x <= uppers`` over ``x = forces.ravel()`` (``p n`` entries), a name a row.

    Attributes:
        G: ``(m, p n)`` the rows.
        lows: ``(m,)`` their lower bounds.
        uppers: ``(m,)`` their upper bounds (``INFINITY`` for one-sided rows).
        names: ``m`` names, one per row (what the conflict error reports).
    """

    G: np.ndarray
    lows: np.ndarray
    uppers: np.ndarray
    names: Sequence[str]


def force_entries(axes: Sequence[str]) -> tuple[list[int], list[int]]:
    """The positions of the force axes among ``axes``, and which of x, y, z each is (0-2)."""
    positions = [i for i, axis in enumerate(axes) if axis in ("x", "y", "z")]
    return positions, ["xyz".index(axes[i]) for i in positions]


def moment_entries(axes: Sequence[str]) -> tuple[list[int], list[int]]:
    """The positions of the moment axes among ``axes``, and which of rx, ry, rz each is."""
    moments = ("rx", "ry", "rz")
    positions = [i for i, axis in enumerate(axes) if axis in moments]
    return positions, [moments.index(axes[i]) for i in positions]


class Entries(NamedTuple):
    """Where one contact's force and moment entries sit in ``x = forces.ravel()``."""

    #: positions in ``x`` of the contact's force entries
    force: np.ndarray
    #: positions in ``x`` of its moment entries
    moment: np.ndarray
    #: which of x, y, z each force entry is (0-2)
    force_components: list[int]
    #: which of rx, ry, rz each moment entry is (0-2)
    moment_components: list[int]
    #: the length of ``x`` (``p n``)
    width: int


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross products of ``(..., 3)`` arrays (np.cross costs ~10 us a call)."""
    return np.stack(
        (
            a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
            a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
            a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0],
        ),
        axis=-1,
    )


def reaction_index(name: object, reactions: Sequence[str], what: str) -> int:
    """The position of reaction frame ``name`` (``what`` names the argument in the error).

    Raises:
        InvalidInputError: ``name`` is not a reaction frame.
    """
    if name not in reactions:
        raise InvalidInputError(
            f"{what} names {name!r}, not a reaction frame; reactions are {list(reactions)}."
        )
    return list(reactions).index(name)


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
