"""Declaration-time checks of a `DistributionProblem`, run once (or once per set of free axes)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ...exceptions import ConstraintError
from ...vocabulary.axes import AXES
from ..linalg import dependent_rows
from ..tolerances import IMPLIED_TOL, JACOBIAN_FLOOR, VACUOUS_TOL
from .structure import ChainGroup

if TYPE_CHECKING:
    from .problem import DistributionProblem


def vacuous_joints(problem: DistributionProblem, per_chain: list, states: list) -> set[int]:
    """Velocity indices of the limp joints no selected axis loads (their rows are dropped).

    Such a joint's Jacobian column on the selected axes is below ``VACUOUS_TOL`` times the chain's
    largest at every generic configuration.

    Args:
        problem: The problem being declared.
        per_chain: ``(columns, own constrained joints, ball axes)`` of every chain.
        states: Kinematic states at the generic configurations.

    Raises:
        ConstraintError: A passive joint with nonzero stiffness that no selected axis loads.
    """
    unloaded = []  # per chain: the velocity columns no selected axis loads
    for cols, _, _ in per_chain:
        norms = np.max([np.linalg.norm(s.jacobian_o[:, cols], axis=0) for s in states], axis=0)
        floor = max(JACOBIAN_FLOOR, VACUOUS_TOL * float(norms.max(initial=0.0)))
        unloaded.append(set(cols[norms <= floor].tolist()))
    vacuous = {  # velocity indices: own joints, and shared ones that no chain loads
        int(cols[j])
        for (cols, own, _), gone in zip(per_chain, unloaded, strict=True)
        for j in own
        if int(cols[j]) in gone
    }
    vacuous.update(
        v
        for v in problem.coupled_v
        if all(v in gone for (c, _, _), gone in zip(per_chain, unloaded, strict=True) if v in c)
    )
    for v in sorted(vacuous):
        spring = problem.passive_v.get(v)
        if spring is not None and spring.stiffness != 0.0:
            raise ConstraintError(
                f"No selected axis {list(problem.axes)} loads the passive joint {spring.name!r} "
                "(its lever is structurally zero): its spring torque could never be balanced "
                "by the distribution. Select axes that load it, or declare it unactuated."
            )
    return vacuous


def check_natural_rows(problem: DistributionProblem, generic: Sequence[np.ndarray]) -> None:
    """Reject a chain whose natural constraints are redundant at a generic configuration.

    Raises:
        ConstraintError: One natural row repeats what the chain's others impose.
    """
    ev = problem.evaluate(generic[0], check_singular=False)
    for group, rows in zip(problem.groups, ev.groups, strict=True):
        for j, chain in enumerate(group.chains):
            bad = dependent_rows(rows.rows[j])
            if bad:
                raise ConstraintError(
                    f"The natural constraints of the chain to {problem.reactions[chain]!r} "
                    f"are redundant: {_describe_natural(problem, group, j, bad[0])} repeats what "
                    "the others already impose (e.g. a limp joint at a point contact: use "
                    "contact='flat' for that reaction, or drop the joint from unactuated)."
                )


def _describe_natural(problem: DistributionProblem, group: ChainGroup, j: int, row: int) -> str:
    c = group.constrained.shape[1]
    if row < c:
        v = group.columns[j, group.constrained[j, row]]
        return f"the torque constraint of joint {problem.joint_name(v)!r}"
    if row < c + len(group.ball_axes):
        return f"zero moment {AXES[3 + group.ball_axes[row - c]]} at the point contact"
    return "a direction the chain cannot produce"


def check_hard_rows(problem: DistributionProblem) -> None:
    """Reject hard rows that are implied by, or contradict, the natural ones and each other.

    Raises:
        ConstraintError: A design constraint implied by, or contradicting, the others.
    """
    if not problem.num_hard:
        return
    ev = problem.evaluate(problem.generic_configurations()[1], check_singular=False)
    natural, natural_rhs = problem.block_natural(ev)
    hard = ev.hard_rows.reshape(problem.num_hard, -1)
    stacked = np.vstack((natural, hard))
    bad = [i - natural.shape[0] for i in dependent_rows(stacked) if i >= natural.shape[0]]
    if bad:
        rhs = np.concatenate((natural_rhs, ev.hard_rhs))
        solution = np.linalg.lstsq(stacked, rhs, rcond=None)[0]
        atol = IMPLIED_TOL * (1 + np.abs(rhs).max())
        consistent = np.allclose(stacked @ solution, rhs, atol=atol)
        verb = "is implied by" if consistent else "contradicts"
        raise ConstraintError(
            f"Design constraint {problem.hard_names[bad[0]]} {verb} the other constraints "
            "(natural and design); remove it."
        )


def structurally_singular(problem: DistributionProblem, keep: np.ndarray) -> bool:
    """Whether the square system is singular at every configuration for these free axes.

    Such declarations (two point feet and a moment about the line between them) get the
    minimum-norm least-squares solution; checked densely at random configurations, remembered
    in ``problem.structural``.

    Args:
        problem: The declared problem.
        keep: ``(n,)`` bool, the prescribed (not free) axes.
    """
    key = keep.tobytes()
    cached = problem.structural.get(key)
    if cached is None:
        cached = True
        n, p = problem.n, problem.p
        for q in problem.generic_configurations():
            ev = problem.evaluate(q, check_singular=False)
            natural, _ = problem.block_natural(ev)
            k = np.vstack(
                (np.tile(np.eye(n), (1, p))[keep], natural, ev.hard_rows.reshape(-1, p * n))
            )
            if k.shape[0] == k.shape[1] and np.linalg.matrix_rank(k) == k.shape[0]:
                cached = False
                break
        problem.structural[key] = cached
    return cached


def check_counts(problem: DistributionProblem, keep: np.ndarray) -> None:
    """Raise if there are more design/coupling constraints than redundancies for ``keep``.

    Raises:
        ConstraintError: ``s > sum(d) - (number of prescribed axes)``.
    """
    m = sum(g.size * g.num_free for g in problem.groups)
    k, s = int(keep.sum()), problem.num_hard
    if s and s > m - k:
        names = [a for a, kept in zip(problem.axes, keep, strict=True) if kept]
        raise ConstraintError(
            f"Too many constraints: {s} design/coupling constraints but only {m - k} "
            f"redundancies (sum of d = {m} minus the {k} prescribed axes {names}). Remove "
            f"{s - (m - k)} or leave more axes free."
        )
