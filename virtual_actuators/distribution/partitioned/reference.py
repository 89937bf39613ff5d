"""The extended Partitioned Actuator Set method (VAC 2.5.1-2.5.2), chosen automatically.

Per chain the natural constraints are solved for the Constrained Force Set (eq. 12-13); the
reduced system (eq. 14) is square (RFS eliminated, one MFS solve: eq. 16-18), has fewer design
constraints (the least-norm KKT solve: "pseudo-inverse") or more rows (`least_norm`:
"least-squares").
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ...exceptions import SingularConfigurationError
from ..linalg import safe_inverse, scaled_condition, select_columns
from ..problem import DistributionProblem
from ..problem.structure import Evaluation
from ..result import RawSolution
from ..tolerances import ILL_CONDITIONED
from .least_norm import least_norm_forces, projected_forces


@dataclass
class SquarePlan:
    """Cached RFS/MFS choice for a square reduced system and one set of free axes."""

    rfs: np.ndarray
    mfs: np.ndarray
    gain: np.ndarray | None = None  # -H_r^-1 H_m when the hard rows are constant
    rfs_inverse: np.ndarray | None = None  # H_r^-1 when the hard rows are constant


def plan_square(h: np.ndarray, constant: bool) -> SquarePlan:
    """The RFS (``s`` columns of the hard rows ``h`` by pivoted QR) and the MFS (the rest).

    Args:
        h: ``(s, m)`` reduced hard rows over the ``m`` reduced unknowns.
        constant: The hard rows do not depend on the configuration: factor the gain once.
    """
    s = h.shape[0]
    rfs = np.sort(select_columns(h, s)) if s else np.array([], dtype=int)
    mfs = np.setdiff1d(np.arange(h.shape[1]), rfs)
    plan = SquarePlan(rfs=rfs, mfs=mfs)
    if s and constant:
        inverse, cond = safe_inverse(h[:, rfs])
        if cond < ILL_CONDITIONED:
            plan.gain = -inverse @ h[:, mfs]
            plan.rfs_inverse = inverse
    return plan


def rfs_gain(
    h: np.ndarray, h_rhs: np.ndarray, plan: SquarePlan, scale: np.ndarray
) -> tuple[np.ndarray | None, np.ndarray | None]:
    """``(gain, bias)`` of ``f_r = gain f_m + bias`` here; ``(None, None)``: ill-conditioned."""
    block = h[:, plan.rfs]
    inverse, cond = safe_inverse(block)
    if cond > ILL_CONDITIONED or not scale.all():
        return None, None
    if scaled_condition(block, inverse, scale) > ILL_CONDITIONED:
        return None, None
    return -inverse @ h[:, plan.mfs], inverse @ h_rhs


@dataclass
class _Reduced:
    """The reduced system at one configuration (after eliminating the CFS)."""

    transforms: list[np.ndarray]  # per group (g, n, d): F_i = T_i f_ia + w_i
    offsets: np.ndarray  # (p, n) the w_i
    wrench_rows: np.ndarray  # (n, m)
    hard_rows: np.ndarray  # (s, m)
    hard_rhs: np.ndarray  # (s,)
    offset_sum: np.ndarray  # (n,)
    cfs: list[np.ndarray]  # per group (g, l): the CFS used at this configuration
    free: list[np.ndarray]  # per group (g, d): the other entries
    #: (s,) per hard row ``c``, ``sum_i |c_i|_1 max|T_i|``: the size of what cancels in it
    hard_scale: np.ndarray
    repicked: bool  # True when some chain's CFS was re-picked at this configuration


class Elimination(NamedTuple):
    """A group's natural rows solved for its CFS: ``Q_i``, ``u_i``, CFS and free entries used."""

    q_matrix: np.ndarray
    u: np.ndarray
    cfs: np.ndarray
    free: np.ndarray


class PartitionedSolver:
    """Solve the force distribution by partitioning into MFS / RFS / CFS.

    Args:
        problem: The declaration-time structure of the distribution.
        preferred: ``(p, n)`` weights in (0, 1]; entries with small weights (those named by
            design constraints) are kept out of the Constrained Force Set when possible.
    """

    def __init__(self, problem: DistributionProblem, preferred: np.ndarray) -> None:
        self.problem = problem
        self.preferred = preferred
        ev = problem.evaluate(problem.generic_configurations()[0], check_singular=False)
        #: evaluation at a fixed random configuration, where the sets are chosen
        self._generic = ev
        self.cfs: list[np.ndarray] = []
        self.free_entries: list[np.ndarray] = []
        for group, rows in zip(problem.groups, ev.groups, strict=True):
            picks = [
                np.sort(select_columns(rows.rows[j], group.num_constraints, preferred[chain]))
                for j, chain in enumerate(group.chains)
            ]
            cfs = np.array(picks, dtype=int).reshape(group.size, -1)
            self.cfs.append(cfs)  # fixed from here on: a re-pick serves one call only
            self.free_entries.append(self._complement(cfs))
        self._reported_sets: dict[tuple, dict] = {}
        self.num_free_entries = sum(g.size * g.num_free for g in problem.groups)
        #: the ``systems`` every solve inverts: each group's CFS blocks
        self.cfs_systems = tuple(
            ("CFS", g.num_constraints, g.size) for g in problem.groups if g.num_constraints
        )

    def sets(
        self, mfs: np.ndarray, rfs: np.ndarray, free: list | None = None, cfs: list | None = None
    ) -> dict[str, list[tuple[str, str]]]:
        """The MFS and RFS (indices of the reduced unknowns ``free``) and the CFS, labelled."""
        labels = self.labels(free)
        return {
            "MFS": [labels[i] for i in mfs],
            "RFS": [labels[i] for i in rfs],
            "CFS": self.labels(self.cfs if cfs is None else cfs),
        }

    def labels(self, entries: list[np.ndarray] | None = None) -> list[tuple[str, str]]:
        """Labels of the reduced unknowns ``f_a`` (or of ``entries``), in the solver's order."""
        entries = self.free_entries if entries is None else entries
        out = []
        for group, chosen in zip(self.problem.groups, entries, strict=True):
            for j, chain in enumerate(group.chains):
                out += [(self.problem.reactions[chain], self.problem.axes[x]) for x in chosen[j]]
        return out

    def _reduce(self, ev: Evaluation) -> _Reduced:
        problem = self.problem
        n = problem.n
        transforms, wrench_blocks, hard_blocks = [], [], []
        offsets = np.zeros((problem.p, n))
        used_cfs, used_free = [], []
        hard_rhs = ev.hard_rhs.copy()
        offset_sum = np.zeros(n)
        hard_scale = np.zeros(len(hard_rhs))
        repicked = False
        for index, (group, rows) in enumerate(zip(problem.groups, ev.groups, strict=True)):
            g, l_, d = group.size, group.num_constraints, group.num_free
            transform = np.zeros((g, n, d))
            offset = np.zeros((g, n))
            chains = np.arange(g)[:, None]
            cfs, free = self.cfs[index], self.free_entries[index]
            if l_:
                q_matrix, u, cfs, free = self.eliminate(index, rows.rows, rows.rhs)
                repicked |= cfs is not self.cfs[index]
                transform[chains, cfs, :] = q_matrix
                offset[chains, cfs] = u
            used_cfs.append(cfs)
            used_free.append(free)
            transform[chains, free, np.arange(d)[None, :]] = 1.0
            transforms.append(transform)
            offsets[group.chains] = offset
            offset_sum += offset.sum(axis=0)
            wrench_blocks.append(transform.transpose(1, 0, 2).reshape(n, g * d))
            hard = ev.hard_rows[:, group.chains, :]
            hard_block = np.einsum("spn,pnd->spd", hard, transform)
            hard_blocks.append(hard_block.reshape(hard.shape[0], g * d))
            hard_rhs -= np.einsum("spn,pn->s", hard, offset)
            size = np.abs(transform).max(axis=(1, 2), initial=0.0)  # (g,) max |T_i|
            hard_scale += np.einsum("spn,p->s", np.abs(hard), size)
        return _Reduced(
            transforms=transforms,
            offsets=offsets,
            wrench_rows=np.hstack(wrench_blocks),
            hard_rows=np.hstack(hard_blocks),
            hard_rhs=hard_rhs,
            offset_sum=offset_sum,
            cfs=used_cfs,
            free=used_free,
            hard_scale=hard_scale,
            repicked=repicked,
        )

    def eliminate(self, index: int, rows: np.ndarray, rhs: np.ndarray) -> Elimination:
        """``Q_i = -G_b^-1 G_a``, ``u_i = G_b^-1 t_i`` and the CFS / free entries used.

        A chain whose declared CFS block is ill-conditioned here gets a CFS re-picked for this call.

        Raises:
            SingularConfigurationError: No well-conditioned CFS exists for some chain.
        """
        cfs, free = self.cfs[index], self.free_entries[index]
        for attempt in range(2):
            chains = np.arange(cfs.shape[0])[:, None, None]
            all_rows = np.arange(rows.shape[1])[None, :, None]
            blocks = rows[chains, all_rows, cfs[:, None, :]]
            inverse, cond = safe_inverse(blocks)
            bad = np.flatnonzero(cond > ILL_CONDITIONED)
            if not len(bad):
                others = rows[chains, all_rows, free[:, None, :]]
                u = np.einsum("gij,gj->gi", inverse, rhs)
                return Elimination(-inverse @ others, u, cfs, free)
            if attempt:
                break
            group = self.problem.groups[index]
            cfs = cfs.copy()
            for j in bad:
                weights = self.preferred[group.chains[j]]
                cfs[j] = np.sort(select_columns(rows[j], cfs.shape[1], weights))
            free = self._complement(cfs)
        chain = self.problem.reactions[self.problem.groups[index].chains[bad[0]]]
        raise SingularConfigurationError(
            f"The natural constraints of the chain to {chain!r} are degenerate at this "
            "configuration (no well-conditioned Constrained Force Set, condition "
            f"{cond[bad[0]]:.1e})."
        )

    def _complement(self, cfs: np.ndarray) -> np.ndarray:
        """``(g, d)`` entries of each chain's wrench outside its CFS, increasing."""
        mask = np.ones((cfs.shape[0], self.problem.n), dtype=bool)
        np.put_along_axis(mask, cfs, False, axis=1)
        return np.array([np.flatnonzero(m) for m in mask], dtype=int).reshape(cfs.shape[0], -1)

    def solve(self, ev: Evaluation, wrench: np.ndarray, keep: np.ndarray) -> RawSolution:
        """Distribute ``wrench`` over the chains.

        Args:
            ev: Evaluation at the current configuration.
            wrench: ``(n,)`` requested wrench (entries of free axes are ignored).
            keep: ``(n,)`` bool, the axes whose wrench is prescribed (not free).

        Raises:
            SingularConfigurationError: The square system is singular at this configuration.
            ConstraintError: Too many constraints for the free axes, or constraints that
                contradict each other at this configuration.
        """
        m, s, k = self.num_free_entries, len(ev.hard_rhs), int(keep.sum())
        systems = self.cfs_systems
        if k + s < m:
            forces = projected_forces(self.problem, ev, wrench, keep)
            if forces is not None:
                sets = self.reported_sets(keep)
                systems += (("KKT", k + s, 1),)
                return RawSolution(forces, "pseudo-inverse", sets, systems)
        if k + s == m and not self.problem.structurally_singular(keep):
            reduced = self._reduce(ev)
            a = reduced.wrench_rows[keep]
            rhs = wrench[keep] - reduced.offset_sum[keep]
            square = self._solve_square(reduced, a, rhs)
            if square is not None:  # None: the hard rows are dependent here
                f, sets, plan, rfs_solved = square
                if rfs_solved:
                    systems += (("RFS", len(plan.rfs), 1),)
                systems += (("MFS", len(plan.mfs), 1),)
                forces = self.problem.forces(reduced.transforms, f, reduced.offsets)
                return RawSolution(forces=forces, method="partitioned", sets=sets, systems=systems)
        # constraints exact, the request as close as possible, then the least norm
        forces = least_norm_forces(self.problem, ev, wrench, keep)
        systems += (("least-squares", m, 1),)
        sets = self.reported_sets(keep)
        return RawSolution(forces=forces, method="least-squares", sets=sets, systems=systems)

    def reported_sets(self, keep: np.ndarray) -> dict[str, list[tuple[str, str]]]:
        """MFS / RFS / CFS of a non-square system at a generic ``q``: the MFS spans the wrench."""
        free_key = keep.tobytes()
        sets = self._reported_sets.get(free_key)
        if sets is None:
            a = self._reduce(self._generic).wrench_rows[keep]
            count = min(a.shape)
            mfs = np.sort(select_columns(a, count)) if count else np.array([], dtype=int)
            rfs = np.setdiff1d(np.arange(a.shape[1]), mfs)
            sets = self._reported_sets[free_key] = self.sets(mfs, rfs)
        return sets

    @functools.cached_property
    def square_plan(self) -> SquarePlan:
        """The RFS / MFS choice of the square system (the hard rows', whatever the free axes)."""
        return plan_square(self._reduce(self._generic).hard_rows, self._hard_rows_constant())

    def _solve_square(
        self, reduced: _Reduced, a: np.ndarray, rhs: np.ndarray
    ) -> tuple[np.ndarray, dict, SquarePlan, bool] | None:
        """``(f, sets, plan, RFS inverted here)`` by eq. 16-18; None: hard rows dependent here.

        The declaration's plan serves unless its design block is ill-conditioned here (judged by
        `scaled_condition`): then a plan picked here serves this call only.
        """
        h, h_rhs = reduced.hard_rows, reduced.hard_rhs
        m = a.shape[1]
        plan = self.square_plan
        rfs_solved = False
        if len(plan.rfs):
            if plan.gain is not None and not reduced.repicked:
                # constant hard rows avoid every CFS entry, so h_rhs is the design rhs here
                gain, bias = plan.gain, plan.rfs_inverse @ h_rhs
            else:
                rfs_solved = True
                gain, bias = rfs_gain(h, h_rhs, plan, reduced.hard_scale)
                if gain is None:
                    plan = plan_square(h, constant=False)
                    gain, bias = rfs_gain(h, h_rhs, plan, reduced.hard_scale)
                    if gain is None:
                        return None
            a_r = a[:, plan.rfs]
            mfs_matrix = a[:, plan.mfs] + a_r @ gain
            mfs_rhs = rhs - a_r @ bias
        else:
            mfs_matrix, mfs_rhs = a[:, plan.mfs], rhs
        inverse, cond = safe_inverse(mfs_matrix)
        if cond > ILL_CONDITIONED:
            raise SingularConfigurationError(
                f"The {len(plan.mfs)} x {len(plan.mfs)} Minimum Force Set system is singular at "
                f"this configuration (condition {cond:.1e}): the constraints leave the wrench "
                "undetermined or unreachable here (e.g. a straight knee, or feet in line)."
            )
        f = np.empty(m)
        f[plan.mfs] = inverse @ mfs_rhs
        if len(plan.rfs):
            f[plan.rfs] = gain @ f[plan.mfs] + bias
        return f, self.sets(plan.mfs, plan.rfs, reduced.free, reduced.cfs), plan, rfs_solved

    def _hard_rows_constant(self) -> bool:
        """Hard rows are constant if they are declaration-only and avoid every CFS entry."""
        problem = self.problem
        if not problem.constant_hard:
            return False
        for group, cfs in zip(problem.groups, self.cfs, strict=True):
            rows = problem.constant_rows[:, group.chains, :]
            index = np.broadcast_to(cfs[None], (rows.shape[0], *cfs.shape))
            if np.any(np.take_along_axis(rows, index, axis=2)):
                return False
        return True
