"""Reference solver: the dense constraint system of VAC eq. 10-11 over all ``p n`` entries.

The benchmarks' baseline and the partitioned solver's oracle, with the same semantics.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...exceptions import ConstraintError, SingularConfigurationError
from ..linalg import backward_tolerance, constrained_min_norm, dependent_rows_at_scale
from ..problem import DistributionProblem
from ..problem.structure import Evaluation
from ..result import RawSolution, no_sets
from ..tolerances import ILL_CONDITIONED


class DenseSystem(NamedTuple):
    """The rows of K (eq. 10) over the ``p n`` force entries, and their right-hand sides.

    Attributes:
        soft: ``(k, p n)`` the request's rows (the prescribed axes of ``sum_i F_i``).
        soft_rhs: ``(k,)`` the request on them.
        hard: ``(r, p n)`` the natural rows, then the design rows.
        hard_rhs: ``(r,)`` their right-hand sides.
    """

    soft: np.ndarray
    soft_rhs: np.ndarray
    hard: np.ndarray
    hard_rhs: np.ndarray


class DenseSolver:
    """Solve eq. 10-11 densely (``problem``: the declaration-time structure)."""

    def __init__(self, problem: DistributionProblem) -> None:
        self.problem = problem

    def system(self, ev: Evaluation, wrench: np.ndarray, keep: np.ndarray) -> DenseSystem:
        """The wrench rows and the constraint rows of K (eq. 10) at this evaluation."""
        p, n = self.problem.p, self.problem.n
        soft = np.tile(np.eye(n), (1, p))[keep]
        natural, natural_rhs = self.problem.block_natural(ev)
        hard = np.vstack((natural, ev.hard_rows.reshape(-1, p * n)))
        hard_rhs = np.concatenate((natural_rhs, ev.hard_rhs))
        return DenseSystem(soft, wrench[keep], hard, hard_rhs)

    def solve(self, ev: Evaluation, wrench: np.ndarray, keep: np.ndarray) -> RawSolution:
        """Distribute ``wrench``; see `PartitionedSolver.solve` for the arguments.

        Raises:
            SingularConfigurationError: The square system is singular at this configuration.
            ConstraintError: The constraints contradict each other at this configuration.
        """
        p, n = self.problem.p, self.problem.n
        soft, soft_rhs, hard, hard_rhs = self.system(ev, wrench, keep)
        k = np.vstack((soft, hard))
        square = k.shape[0] == k.shape[1] and not self.problem.structurally_singular(keep)
        if square:
            cond = np.linalg.cond(k)
            if not np.isfinite(cond) or cond > ILL_CONDITIONED:
                if not dependent_rows_at_scale(hard):
                    raise SingularConfigurationError(
                        f"The {k.shape[0]} x {k.shape[1]} constraint matrix K (eq. 10) is "
                        f"singular at this configuration (condition {cond:.1e})."
                    )
                square = False  # exact rows implied by the others here: the minimum norm
        if square:
            x = np.linalg.solve(k, np.concatenate((soft_rhs, hard_rhs)))
            method = "partitioned"
        else:
            x, hard_residual = constrained_min_norm(hard, hard_rhs, soft, soft_rhs)
            if hard_residual > backward_tolerance(hard, x, hard_rhs):
                names = ", ".join(["natural constraints", *self.problem.hard_names])
                raise ConstraintError(
                    f"The constraints ({names}) contradict each other at this configuration "
                    f"(residual {hard_residual:.2e}); a passive spring or limp joint that no "
                    "selected axis loads cannot be balanced."
                )
            method = "pseudo-inverse" if k.shape[0] <= k.shape[1] else "least-squares"
        return RawSolution(
            forces=x.reshape(p, n),
            method=method,
            sets=no_sets(),
            systems=(("dense", k.shape[1], 1),),
            solver="dense",
        )

    def __repr__(self) -> str:
        return f"DenseSolver(p={self.problem.p}, n={self.problem.n})"
