"""Declaration-time checks of a distribution problem's natural and hard rows."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import numpy as np

from ...exceptions import ConstraintError
from ...vocabulary.axes import AXES
from ..linalg import dependent_rows
from ..tolerances import IMPLIED_TOL, JACOBIAN_FLOOR, VACUOUS_TOL
from .declaration import Spring
from .structure import ChainGroup, GroupRows


def vacuous_joints(
    per_chain: list,
    states: list,
    axes: Sequence[str],
    coupled_v: Sequence[int],
    passive_v: Mapping[int, Spring],
) -> set[int]:
    """Velocity indices of the limp joints no selected axis loads (their rows are dropped).

    Such a joint's Jacobian column on the selected axes is below ``VACUOUS_TOL`` times the chain's
    largest at every generic configuration.

    ``per_chain``: ``(columns, own constrained joints, ball axes)`` of every chain; ``states``
    at the generic configurations; ``coupled_v``: the limp or passive joints shared by several
    chains; ``passive_v``: the springs by velocity index.

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
        for v in coupled_v
        if all(v in gone for (c, _, _), gone in zip(per_chain, unloaded, strict=True) if v in c)
    )
    for v in sorted(vacuous):
        spring = passive_v.get(v)
        if spring is not None and spring.stiffness != 0.0:
            raise ConstraintError(
                f"No selected axis {list(axes)} loads the passive joint {spring.name!r} "
                "(its lever is structurally zero): its spring torque could never be balanced "
                "by the distribution. Select axes that load it, or declare it unactuated."
            )
    return vacuous


def check_natural_rows(
    groups: Sequence[ChainGroup],
    rows: Sequence[GroupRows],
    reactions: Sequence[str],
    joint_name: Callable[[int], str],
) -> None:
    """Reject a chain whose natural constraints are redundant at a generic configuration.

    ``rows``: the groups' natural rows there; ``joint_name``: a velocity index's joint.

    Raises:
        ConstraintError: One natural row repeats what the chain's others impose.
    """
    for group, group_rows in zip(groups, rows, strict=True):
        for j, chain in enumerate(group.chains):
            bad = dependent_rows(group_rows.rows[j])
            if bad:
                raise ConstraintError(
                    f"The natural constraints of the chain to {reactions[chain]!r} "
                    f"are redundant: {_describe_natural(group, j, bad[0], joint_name)} repeats "
                    "what the others already impose (e.g. a limp joint at a point contact: use "
                    "contact='flat' for that reaction, or drop the joint from unactuated)."
                )


def _describe_natural(group: ChainGroup, j: int, row: int, joint_name: Callable[[int], str]) -> str:
    c = group.constrained.shape[1]
    if row < c:
        v = group.columns[j, group.constrained[j, row]]
        return f"the torque constraint of joint {joint_name(v)!r}"
    if row < c + len(group.ball_axes):
        return f"zero moment {AXES[3 + group.ball_axes[row - c]]} at the point contact"
    return "a direction the chain cannot produce"


def check_hard_rows(stacked: np.ndarray, rhs: np.ndarray, hard_names: Sequence[str]) -> None:
    """Reject hard rows that are implied by, or contradict, the natural ones and each other.

    ``stacked``: the dense natural rows over all ``p n`` force entries, then the coupling and
    design rows, one name each in ``hard_names``; ``rhs``: their right-hand sides.

    Raises:
        ConstraintError: A design constraint implied by, or contradicting, the others.
    """
    natural = stacked.shape[0] - len(hard_names)
    bad = [i - natural for i in dependent_rows(stacked) if i >= natural]
    if bad:
        solution = np.linalg.lstsq(stacked, rhs, rcond=None)[0]
        atol = IMPLIED_TOL * (1 + np.abs(rhs).max())
        consistent = np.allclose(stacked @ solution, rhs, atol=atol)
        verb = "is implied by" if consistent else "contradicts"
        raise ConstraintError(
            f"Design constraint {hard_names[bad[0]]} {verb} the other constraints "
            "(natural and design); remove it."
        )
