"""Which wrenches a parallel actuator can produce here, and letting the others give way."""

from __future__ import annotations

import weakref
from typing import NamedTuple

import numpy as np

from .. import core
from ..distribution.problem import DistributionProblem
from ..kinematics.kernels import skew
from ..kinematics.relative import RelativeKinematics
from ..kinematics.snapshot import Snapshot

#: Singular values below this fraction of the largest count as zero (the rank decision).
RANK_TOL = 1e-9


def _null_space(matrix: np.ndarray) -> np.ndarray:
    """Orthonormal basis ``(columns, k)`` of the null space of ``matrix``."""
    columns = matrix.shape[1]
    if matrix.shape[0] == 0:
        return np.eye(columns)
    _, s, vt = np.linalg.svd(matrix, full_matrices=True)
    rank = int(np.sum(s > RANK_TOL * max(float(s[0]) if s.size else 0.0, 1e-300)))
    return vt[rank:].T


class Directions(NamedTuple):
    """The wrench space of an actuator split in two (orthonormal columns, together a basis).

    Attributes:
        producible: ``(n, r)`` what the chains can produce here.
        missing: ``(n, n - r)`` the rest (the orthogonal complement).
    """

    producible: np.ndarray
    missing: np.ndarray


def _split(matrix: np.ndarray) -> Directions:
    """The column space of ``matrix`` and its orthogonal complement."""
    rows = matrix.shape[0]
    if matrix.size == 0:
        return Directions(np.zeros((rows, 0)), np.eye(rows))
    u, s, _ = np.linalg.svd(matrix, full_matrices=True)
    rank = int(np.sum(s > RANK_TOL * s[0])) if s.size and s[0] > 0.0 else 0
    return Directions(u[:, :rank], u[:, rank:])


def producible_directions(
    kinematics: RelativeKinematics, problem: DistributionProblem, q: np.ndarray | Snapshot
) -> Directions:
    """The wrenches a parallel actuator's chains can produce at ``q``, and the others.

    Forces [N] and moments [N m] about {B}'s origin, in {O}'s axes.

    Raises:
        InvalidInputError: A bad ``q`` or a snapshot of another robot.
    """
    snapshot = kinematics.snapshot(q)
    if _points_only(problem):  # the frames' positions only (no Jacobian)
        if len(kinematics.reaction_ids) == 2 and _TWO_POINTS is not None:
            found = _TWO_POINTS(snapshot.frame_table, kinematics.frame_rows)
            if found.size:
                return Directions(found[:30].reshape(6, 5), found[30:].reshape(6, 1))
        action = snapshot.frame_position(kinematics.action_id)
        reactions = np.array([snapshot.frame_position(int(r)) for r in kinematics.reaction_ids])
        offsets = (action - reactions) @ snapshot.frame_rotation(kinematics.reference_id)
        return _split(_point_columns(offsets))
    evaluation = problem.evaluate(snapshot, check_singular=False)
    natural, _ = problem.block_natural(evaluation)
    p, n = problem.p, problem.n
    hard = np.asarray(evaluation.hard_rows, dtype=float).reshape(-1, p * n)
    allowed = _null_space(np.vstack((natural, hard)))  # chain wrenches meeting every row
    total = np.tile(np.eye(n), p)  # (n, p n): the stacked chain wrenches to their sum
    return _split(total @ allowed)


def _points_only(problem: object) -> bool:
    """Every chain a point contact on a full-rank leg, six axes, no limp joint, no design row.

    Then chain ``i`` exerts exactly the forces through its contact point: ``(f, r_i x f)``.
    """
    known = _POINTS_ONLY.get(problem)
    if known is None:
        known = _POINTS_ONLY[problem] = (
            len(problem.axes) == 6
            and problem.num_hard == 0
            and all(kind == "point" for kind in problem.contacts)
            and all(g.rank == 6 and not g.constrained.shape[1] for g in problem.groups)
        )
    return known


#: :func:`_points_only` per declared problem.
_POINTS_ONLY: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


#: Two point contacts in closed form (the core's ``two_points``), or None without the core
_TWO_POINTS = core.kernel("two_points", None)
#: `give_way` with one missing direction in closed form (``give_way_one``), or None
_GIVE_WAY_ONE = core.kernel("give_way_one", None)


def _point_columns(offsets: np.ndarray) -> np.ndarray:
    """``(6, 3 p)``: per chain, the wrenches about {B} of unit forces at its contact point.

    ``offsets`` ``(p, 3)`` go from each contact to {B}, in {O} [m].
    """
    count = len(offsets)
    moments = skew(-offsets)  # the moment (-d) x f about {B}
    columns = np.empty((6, 3 * count))
    columns[:3] = np.tile(np.eye(3), count)
    columns[3:] = moments.transpose(1, 0, 2).reshape(3, 3 * count)
    return columns


def give_way(
    basis: np.ndarray,
    wrench: np.ndarray,
    yielding: np.ndarray | None = None,
    missing: np.ndarray | None = None,
) -> np.ndarray:
    """The producible wrench closest to ``wrench`` that differs from it along ``yielding`` only.

    The least move along ``yielding`` into the span of ``basis``; what it cannot absorb is
    removed by the orthogonal projection onto that span.

    Args:
        basis: ``(n, r)`` orthonormal producible directions (`producible_directions`).
        wrench: ``(n,)`` request.
        yielding: ``(n, m)`` directions allowed to give way first; None: projection alone.
        missing: ``(n, n - r)`` orthogonal complement of ``basis`` (None: computed).

    Returns:
        ``(n,)`` a producible wrench (``wrench`` itself when it already is).
    """
    n, r = basis.shape
    if r == n:
        return np.array(wrench, dtype=float)
    wrench = np.asarray(wrench, dtype=float)
    one = missing is not None and missing.shape[1] == 1 and yielding is not None
    if one and _GIVE_WAY_ONE is not None:
        out = np.empty(n)
        if _GIVE_WAY_ONE(wrench, yielding, missing, out):
            return out
    if yielding is not None and yielding.shape[1]:
        if missing is None:
            missing = np.linalg.svd(basis, full_matrices=True)[0][:, r:]
        across = missing.T @ yielding  # (n - r, m): how the yielding move the missing part
        gap = missing.T @ wrench
        norm2 = float(across[0] @ across[0]) if across.shape[0] == 1 else 0.0
        if norm2 > 1e-12:  # one missing direction: the closed form of the least move
            wrench = wrench - yielding @ (across[0] * (gap[0] / norm2))
        else:  # the least move (least squares when the yielding cannot absorb it all)
            shift, *_ = np.linalg.lstsq(across, gap, rcond=None)
            wrench = wrench - yielding @ shift
    if missing is not None:
        return wrench - missing @ (missing.T @ wrench)
    return basis @ (basis.T @ wrench)


def moment_directions(axes: tuple[str, ...]) -> np.ndarray:
    """``(n, m)`` unit columns of the rotational axes among ``axes`` (the default yielding)."""
    rotational = [i for i, axis in enumerate(axes) if axis.startswith("r")]
    return np.eye(len(axes))[:, rotational]
