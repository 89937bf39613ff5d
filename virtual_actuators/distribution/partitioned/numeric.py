"""The numpy path of a parallel actuator's solve: any solver, any magnitude, typed errors only.

The right-hand sides are scaled by a power of two first: the same bits, no over- or underflow.
`DenseSolver`, the dense constraint system of VAC eq. 10-11 over all ``p n`` entries, is the
benchmarks' baseline and the partitioned solver's oracle, with the same semantics.
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np

from ...exceptions import ConstraintError, SingularConfigurationError
from ..linalg import (
    backward_tolerance,
    constrained_min_norm,
    dependent_rows_at_scale,
    power_of_two_scale,
)
from ..methods import Request
from ..problem import DistributionProblem
from ..problem.structure import Evaluation
from ..result import RawSolution, TickResult, close_tick
from ..tolerances import CONSTRAINT_TOL, ILL_CONDITIONED


def _scaled(ev: Evaluation, factor: float) -> Evaluation:
    """``ev`` with every right-hand side multiplied by ``factor``."""
    if factor == 1.0:
        return ev
    groups = [dataclasses.replace(rows, rhs=rows.rhs * factor) for rows in ev.groups]
    return dataclasses.replace(ev, groups=groups, hard_rhs=ev.hard_rhs * factor)


def constraint_error(problem: DistributionProblem, ev: Evaluation, forces: np.ndarray) -> float:
    """Largest miss of an exact row (natural or hard) by ``forces``, relative to its scale.

    Each row ``g . F = t`` is judged against ``max(max|g| max|F|, |t|)``.
    """
    peak = float(np.abs(forces).max(initial=0.0))
    blocks = [
        (np.einsum("gln,gn->gl", rows.rows, forces[group.chains]), rows.rhs, rows.rows, 2)
        for group, rows in zip(problem.groups, ev.groups, strict=True)
    ]
    blocks.append((np.einsum("spn,pn->s", ev.hard_rows, forces), ev.hard_rhs, ev.hard_rows, (1, 2)))
    worst = 0.0
    for lhs, rhs, rows, axes in blocks:
        if not lhs.size:
            continue
        size = np.maximum(np.abs(rows).max(axis=axes) * peak, np.abs(rhs))
        miss = np.abs(lhs - rhs)
        worst = max(worst, float(np.max(miss / np.where(size > 0.0, size, 1.0))))
    return worst


class DenseSolver:
    """Solve eq. 10-11 densely (``problem``: the declaration-time structure)."""

    def __init__(self, problem: DistributionProblem) -> None:
        self.problem = problem

    def solve(self, ev: Evaluation, wrench: np.ndarray, keep: np.ndarray) -> RawSolution:
        """Distribute ``wrench``; see `PartitionedSolver.solve` for the arguments.

        Raises:
            SingularConfigurationError: The square system is singular at this configuration.
            ConstraintError: The constraints contradict each other at this configuration.
        """
        p, n = self.problem.p, self.problem.n
        # K's rows: the prescribed axes of sum_i F_i (soft), the natural then design rows (hard)
        soft, soft_rhs = self.problem.sum_rows(keep), wrench[keep]
        hard, hard_rhs = self.problem.exact_rows(ev)
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
            x.reshape(p, n), method, systems=(("dense", k.shape[1], 1),), solver="dense"
        )


class NumpyBackend:
    """A numpy solver as a backend: ``"reference"`` (partitioned) or ``"dense"``.

    Args:
        problem: The declaration-time problem.
        solver: The partitioned or dense solver of that problem.
        hand_on: Return None, for the method's next backend, when ``solver`` raises
            [`SingularConfigurationError`][] or misses an exact row by more than
            ``CONSTRAINT_TOL``.
    """

    def __init__(self, problem: DistributionProblem, solver: object, hand_on: bool = False):
        self.problem, self.solver, self.hand_on = problem, solver, hand_on

    def solve(self, snapshot: object, wrench: np.ndarray, request: Request) -> TickResult | None:
        """Distribute ``wrench`` with this backend's solver at a snapshot (None: see ``hand_on``).

        Raises:
            SingularConfigurationError: No distribution can be solved at this configuration.
            ConstraintError: The constraints contradict each other at this configuration.
        """
        problem, keep = self.problem, request.keep
        ev = problem.evaluate(snapshot)
        factor = power_of_two_scale(wrench, ev.passive_torque, ev.hard_rhs)
        scaled = _scaled(ev, factor)
        try:
            raw = self.solver.solve(scaled, wrench * factor, keep)
        except SingularConfigurationError:
            # the closed form cannot decide: the dense reference does (or raises the same error)
            if self.hand_on:
                return None
            raise
        except np.linalg.LinAlgError as error:  # LAPACK gave up: as singular as it gets
            raise SingularConfigurationError(
                f"The force distribution of the chains to {list(problem.reactions)} cannot be "
                f"computed at this configuration (linear algebra failed: {error})."
            ) from error
        if self.hand_on and constraint_error(problem, scaled, raw.forces) > CONSTRAINT_TOL:
            return None  # an ill-conditioned elimination lost an exact row: the dense one keeps it
        torques = functools.partial(problem.torques, ev.state.jacobian_o)
        actuated, passive = problem.actuated_mask, ev.passive_torque
        return close_tick(raw, wrench, keep, torques, actuated, passive, factor)
