"""The inequalities of the QP distribution: the contacts' rows and the torque limits, named."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ...contacts import Constraint, ContactSet, TorqueLimits
from ..problem import DistributionProblem
from ..tolerances import INFINITY


class ContactLimits:
    """The inequalities of a parallel actuator's QP: its contacts' rows, then torque limits.

    Args:
        problem: The distribution problem.
        contacts: The actuator's contacts (`declare`).
        torque_limits: False (none), True (URDF effort limits) or ``(nv,)`` limits [N m, N].

    Raises:
        InvalidInputError: Bad torque limits.
    """

    def __init__(
        self,
        problem: DistributionProblem,
        contacts: ContactSet,
        torque_limits: bool | Sequence[float] | np.ndarray,
    ) -> None:
        self.contacts = contacts
        on_chain = np.zeros(problem.model.nv, dtype=bool)
        on_chain[np.concatenate(problem.kinematics.chain_columns)] = True
        limits = TorqueLimits(problem.model, torque_limits, on_chain, problem.actuated_mask)
        self.torque_limits = limits
        #: the declaration's tables for the compiled path
        self.tables = {**contacts.tables(), "limited_v": limits.limited_v, "limits": limits.limits}
        #: the inequality rows' names, in the order both paths build the rows
        self.row_names = [*contacts.names, *limits.names(problem.joint_name)]

    def rows(self, state: object, torque_map: np.ndarray) -> Constraint:
        """``lows <= G x <= uppers`` over ``x = forces.ravel()``, with a name per row.

        Args:
            state: The tick's kinematic state (rotations, offsets, Jacobian rows in {O}).
            torque_map: ``(nv, p n)`` joint torques of ``x``.
        """
        offsets = state.offsets_o() if self.contacts.sole_rows else None
        one_sided = self.contacts.rows(state.rotation_o, state.rotation_a, offsets)
        rows, low, upper = self.torque_limits.rows(torque_map)  # two-sided
        return Constraint(
            np.vstack((one_sided.G, rows)),
            np.concatenate((one_sided.lows, low)),
            np.concatenate((np.full(len(one_sided.lows), INFINITY), upper)),
            self.row_names,
        )


def kinds(names: Sequence[str]) -> list[str]:
    """The kinds of inequality among row names: friction, normal, moment, torque."""
    words = ("friction", "normal", "moment", "torque")
    return [word for name in names for word in words if word in name] or ["none"]


def torque_map(problem: DistributionProblem, jacobian_o: np.ndarray) -> np.ndarray:
    """``(nv, p n)``: the joint torques ``sum_i J_i^T F_i`` as a matrix over ``F.ravel()``."""
    p, n = problem.p, problem.n
    matrix = np.zeros((problem.model.nv, p * n))
    for group in problem.groups:
        columns = group.columns  # (g, k): each chain's velocity columns
        targets = group.chains[:, None, None] * n + np.arange(n)[None, None, :]
        share = jacobian_o[:, columns].transpose(1, 2, 0) * group.signs[:, :, None]  # (g, k, n)
        matrix[columns[:, :, None], targets] += share
    return matrix
