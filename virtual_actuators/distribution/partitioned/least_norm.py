"""The minimum-norm distribution on the chains' null spaces, rank decided at the problem's scale.

Per chain ``F_i = F0_i + N_i y_i`` (one SVD of the natural rows), so ``sum ||F_i||^2 = sum
||F0_i||^2 + ||y||^2``. A hard row ``c`` is judged against ``|c|``: one that the natural rows
imply here is dropped, one that contradicts them raises [`ConstraintError`][].
"""

from __future__ import annotations

import numpy as np

from ...exceptions import ConstraintError, SingularConfigurationError
from ..linalg import backward_tolerance, constrained_min_norm, safe_inverse, stable_norm
from ..problem import DistributionProblem
from ..problem.structure import Evaluation
from ..tolerances import DEGENERATE, ILL_CONDITIONED


def least_norm_forces(
    problem: DistributionProblem, ev: Evaluation, wrench: np.ndarray, keep: np.ndarray
) -> np.ndarray:
    """``(p, n)`` forces of least ``sum ||F_i||^2``, exact rows met, the request as close as can be.

    Raises:
        SingularConfigurationError: A chain's natural rows are degenerate here (their smallest
            singular value below ``DEGENERATE`` times the largest).
        ConstraintError: The design and coupling rows contradict each other or the natural
            ones at this configuration.
    """
    n, p, k = problem.n, problem.p, int(keep.sum())
    hard = ev.hard_rows  # (s, p, n)
    bases = []  # per group the (g, n, d) orthonormal bases N_i of the natural rows' null space
    particular = np.zeros((p, n))  # the least-norm solutions F0_i of the natural rows
    soft_blocks, hard_blocks = [], []
    for group, rows in zip(problem.groups, ev.groups, strict=True):
        g, l_, d = group.size, group.num_constraints, group.num_free
        if not l_:
            basis = np.broadcast_to(np.eye(n), (g, n, n))
        else:
            u, s, vt = np.linalg.svd(rows.rows, full_matrices=True)
            bad = np.flatnonzero(~(s[:, -1] > DEGENERATE * s[:, 0]))
            if len(bad):
                chain = problem.reactions[group.chains[bad[0]]]
                raise SingularConfigurationError(
                    f"The natural constraints of the chain to {chain!r} are degenerate at this "
                    f"configuration (singular values {s[bad[0], -1]:.1e} and {s[bad[0], 0]:.1e})."
                )
            basis = vt[:, l_:, :].transpose(0, 2, 1)
            coefficients = np.einsum("gji,gj->gi", u, rows.rhs) / s
            particular[group.chains] = np.einsum("gin,gi->gn", vt[:, :l_, :], coefficients)
        bases.append(basis)
        soft_blocks.append(basis[:, keep, :].transpose(1, 0, 2).reshape(k, g * d))
        block = np.einsum("spn,pnd->spd", hard[:, group.chains, :], basis)
        hard_blocks.append(block.reshape(hard.shape[0], g * d))
    soft = np.hstack(soft_blocks)
    soft_rhs = wrench[keep] - particular[:, keep].sum(axis=0)
    # each hard row measured against its own size before the elimination
    norms = np.sqrt(np.einsum("spn,spn->s", hard, hard))
    norms = np.where(norms > 0.0, norms, 1.0)
    hard_y = np.hstack(hard_blocks) / norms[:, None]
    hard_rhs = (ev.hard_rhs - np.einsum("spn,pn->s", hard, particular)) / norms
    y, _ = constrained_min_norm(
        hard_y, hard_rhs, soft, soft_rhs, hard_scale=1.0, soft_scale=float(np.sqrt(p))
    )
    forces = problem.forces(bases, y, particular)
    if hard.shape[0]:
        rows = hard.reshape(hard.shape[0], p * n)
        residual = stable_norm(rows @ forces.ravel() - ev.hard_rhs)
        if residual > backward_tolerance(rows, forces.ravel(), ev.hard_rhs):
            raise ConstraintError(
                f"The design and coupling constraints ({', '.join(problem.hard_names)}) "
                "contradict each other or the chains' natural constraints at this "
                f"configuration (residual {residual:.2e}); a passive spring or limp joint "
                "that no selected axis loads cannot be balanced."
            )
    return forces


def projected_forces(
    problem: DistributionProblem, ev: Evaluation, wrench: np.ndarray, keep: np.ndarray
) -> np.ndarray | None:
    """Minimum of ``sum ||F_i||^2`` subject to every constraint (VAC 2.5.2), or None.

    ``F_i = P_i R_i^T lambda + G_i^+ t_i`` with ``P_i = I - G_i^+ G_i`` and ``R_i`` the rows that
    involve ``F_i``: one ``(n + s)`` square solve for ``lambda``, never the ``pn x pn`` matrix.
    None when that system is ill-conditioned (the least-squares path decides).
    """
    n, p = problem.n, problem.p
    projectors = np.tile(np.eye(n), (p, 1, 1))  # a chain without natural rows: I and 0
    particular = np.zeros((p, n))
    for group, rows in zip(problem.groups, ev.groups, strict=True):
        g_rows = rows.rows
        if g_rows.shape[1]:
            gram_inv, cond = safe_inverse(g_rows @ g_rows.transpose(0, 2, 1))
            if np.any(cond > ILL_CONDITIONED):
                return None
            pseudo = g_rows.transpose(0, 2, 1) @ gram_inv
            projectors[group.chains] = np.eye(n) - pseudo @ g_rows
            particular[group.chains] = (pseudo @ rows.rhs[:, :, None])[:, :, 0]
    hard = ev.hard_rows  # (s, p, n)
    kept = projectors[:, keep, :]  # (p, k, n) = S P_i
    top_left = kept[:, :, keep].sum(axis=0)
    target = wrench[keep] - particular[:, keep].sum(axis=0)
    hard_target = ev.hard_rhs - np.einsum("spn,pn->s", hard, particular)
    hp = np.einsum("spn,pnm->psm", hard, projectors)  # C_i P_i
    top_right = np.einsum("pkn,spn->ks", kept, hard)
    bottom_right = np.einsum("psm,tpm->st", hp, hard)
    kkt = np.block([[top_left, top_right], [top_right.T, bottom_right]])
    kkt_inverse, cond = safe_inverse(kkt)
    if cond > ILL_CONDITIONED:
        return None
    multipliers = kkt_inverse @ np.concatenate((target, hard_target))
    k = int(keep.sum())
    # F_i = P_i (S^T lambda_w + C_i^T lambda_h) + G_i^+ t_i
    forces = kept.transpose(0, 2, 1) @ multipliers[:k] + particular
    if len(ev.hard_rhs):
        forces += np.einsum("psm,s->pm", hp, multipliers[k:])
    return forces
