"""The shapes of a distribution problem: chain groups, their rows at one configuration."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...kinematics.relative import KinematicState


@dataclass
class ChainGroup:
    """Chains of identical structure, stacked for vectorised evaluation.

    Attributes:
        chains: ``(g,)`` chain indices (positions in the actuator's ``reactions``).
        columns: ``(g, k)`` velocity indices of the joints on each chain.
        signs: ``(g, k)`` +1 / -1: on {B}'s or {A}'s side of the path.
        constrained: ``(g, c)`` positions (into ``columns``) of limp or passive joints that belong
            to this chain only.
        ball_axes: rotational axes (0, 1, 2 for rx, ry, rz) of the virtual ball joint at a point
            contact, restricted to the selected axes; empty for a flat contact.
        rank: generic rank of the full chain Jacobian ``[J_i, ball_i]`` on the selected axes.
        n: the number of selected axes.
    """

    chains: np.ndarray
    columns: np.ndarray
    signs: np.ndarray
    constrained: np.ndarray
    ball_axes: np.ndarray
    rank: int
    n: int

    @property
    def size(self) -> int:
        """Number of chains in the group."""
        return len(self.chains)

    @property
    def num_constraints(self) -> int:
        """``l``: natural constraints per chain."""
        return self.constrained.shape[1] + len(self.ball_axes) + (self.n - self.rank)

    @property
    def num_free(self) -> int:
        """``d = n - l``: force entries per chain not fixed by natural constraints."""
        return self.n - self.num_constraints


@dataclass
class GroupRows:
    """Natural-constraint rows of one `ChainGroup` at one configuration.

    Attributes:
        rows: ``(g, l, n)`` the ``G_i``.
        rhs: ``(g, l)`` the ``t_i`` (measured or zero torques).
    """

    rows: np.ndarray
    rhs: np.ndarray


@dataclass
class Evaluation:
    """Everything configuration-dependent that the solvers need at one ``q``.

    Attributes:
        state: Kinematic state (Jacobian rows in {O}, frame placements).
        groups: Natural-constraint rows per chain group.
        hard_rows: ``(s, p, n)`` coupling and design rows over all chains' wrenches.
        hard_rhs: ``(s,)`` their right-hand sides.
        passive_torque: ``(nv,)`` torques of passive springs at ``q`` [N m].
    """

    state: KinematicState
    groups: list[GroupRows]
    hard_rows: np.ndarray
    hard_rhs: np.ndarray
    passive_torque: np.ndarray
