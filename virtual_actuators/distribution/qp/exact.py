"""The QP's exact final step on the active set that ProxQP's multipliers name: the core's or Python.

With ``D x = d`` the design rows, ``A x = w`` the request's rows (weights ``omega``) and the
active inequalities at their bounds ``C_W x = b_W``: the request exactly (``exact=True``) is the
least-norm ``x`` of ``D``, ``C_W``, ``A``; the closest wrench (``exact=False``) minimises
``sum_a omega_a (A x - w)_a^2`` on ``D``, ``C_W`` with the least norm among the minimisers.
The KKT conditions are checked and the active set corrected one row at a time (the C++ port:
``src/core/exact.hpp``).
"""

from __future__ import annotations

import numpy as np

from ... import core
from ..tolerances import DEPENDENT_TOL, EXACT_TOL, NEARLY_DEPENDENT_TOL

#: Active-set changes allowed before ProxQP's answer is kept.
EXACT_STEPS = 16


def _add_row(
    rows: np.ndarray,
    index: int,
    rank: int,
    defer: bool,
    basis: np.ndarray,
    lower: np.ndarray,
    kept: np.ndarray,
    coefficients: np.ndarray,
) -> tuple[int, bool]:
    """Gram-Schmidt of row ``index`` against the ``rank`` rows kept: ``(rank, deferred)``.

    The row is dropped if it depends on the kept rows, deferred if ``defer`` and what it adds is
    below `NEARLY_DEPENDENT_TOL` of its norm.
    """
    row = rows[index].copy()
    norm = np.sqrt(row @ row)
    if norm == 0.0:
        return rank, False
    coefficients[:rank] = 0.0
    rest = norm
    for _ in range(3):  # Gram-Schmidt, again while a sweep removes much of the row
        before = rest
        for b in range(rank):
            dot = basis[b] @ row
            coefficients[b] += dot
            row -= dot * basis[b]
        rest = np.sqrt(row @ row)
        if rank == 0 or rest > 0.7 * before or rest <= DEPENDENT_TOL * norm:
            break
    if rest <= DEPENDENT_TOL * norm:
        return rank, False
    if defer and rest <= NEARLY_DEPENDENT_TOL * norm:
        return rank, True
    basis[rank] = row / rest
    lower[rank, :rank] = coefficients[:rank]
    lower[rank, rank] = rest
    kept[rank] = index
    return rank + 1, False


def _factor(
    rows: np.ndarray,
    k: int,
    design: int,
    side: np.ndarray,
    basis: np.ndarray,
    lower: np.ndarray,
    kept: np.ndarray,
) -> tuple[int, int]:
    """Gram-Schmidt on the design rows, the active inequality rows, then the request rows.

    Writes ``basis`` and ``lower`` with ``row kept[r] = sum_b lower[r, b] basis[b]``; returns
    ``(rank, rank of the design and active rows)``. Deferred rows are retried after their group.
    """
    size = basis.shape[1]
    active = k + np.flatnonzero(side != 0)
    order = np.concatenate((np.arange(design), active, np.arange(design, k))).tolist()
    fixed = design + len(active)
    coefficients = np.empty(size)
    rank, rank_fixed = 0, 0
    for number, group in enumerate((order[:fixed], order[fixed:])):
        deferred = []
        for index in group:
            if rank == size:
                break  # every later row depends on the kept ones (checked by the caller)
            rank, later = _add_row(rows, index, rank, True, basis, lower, kept, coefficients)
            if later:
                deferred.append(index)
        for index in deferred:
            if rank == size:
                break
            rank, _ = _add_row(rows, index, rank, False, basis, lower, kept, coefficients)
        if number == 0:
            rank_fixed = rank
    return rank, rank_fixed


def _back(lower: np.ndarray, start: int, stop: int, rhs: np.ndarray, out: np.ndarray) -> None:
    """``lower[start:stop, start:stop]^T out = rhs`` (``out`` and ``rhs`` over ``start:stop``)."""
    for r in range(stop - 1, start - 1, -1):
        out[r] = (rhs[r] - lower[r + 1 : stop, r] @ out[r + 1 : stop]) / lower[r, r]


def _solve(
    rows: np.ndarray,
    k: int,
    equality_rhs: np.ndarray,
    design: int,
    weights: np.ndarray,
    bounds: np.ndarray,
    side: np.ndarray,
    exact: bool,
    x: np.ndarray,
    fit: np.ndarray,
    norm: np.ndarray,
) -> None:
    """The answer on one active set, and its multipliers.

    Writes ``x``, ``fit`` (the weighted least squares' multipliers; 0 when ``exact``) and ``norm``
    (the least norm's: ``x = sum rows^T norm``), both over ``rows = [equality; inequality]``.
    """
    size = rows.shape[1]
    basis = np.zeros((size, size))
    lower = np.zeros((size, size))
    kept = np.empty(size, dtype=np.int64)
    rank, fixed = _factor(rows, k, design, side, basis, lower, kept)
    targets = np.concatenate((equality_rhs, bounds))
    combination = np.zeros(size)  # x = basis^T combination
    for r in range(fixed):  # the design and active rows exactly: forward substitution
        combination[r] = (targets[kept[r]] - lower[r, :r] @ combination[:r]) / lower[r, r]
    # the request on what it adds (basis rows fixed:rank), weighted least squares
    spread = rows[design:k] @ basis[:rank].T  # each request row on the basis
    root = np.sqrt(weights)
    target = root * (equality_rhs[design:] - spread[:, :fixed] @ combination[:fixed])
    columns = (root[:, None] * spread[:, fixed:]).T.copy()  # orthonormalised below
    extra = rank - fixed
    upper = np.zeros((extra, extra))
    for c in range(extra):
        for _ in range(2):
            for b in range(c):
                dot = columns[b] @ columns[c]
                upper[b, c] += dot
                columns[c] -= dot * columns[b]
        upper[c, c] = np.sqrt(columns[c] @ columns[c])
        columns[c] /= upper[c, c]
    for c in range(extra - 1, -1, -1):  # upper combination = columns^T target
        later = upper[c, c + 1 :] @ combination[fixed + c + 1 : rank]
        combination[fixed + c] = (columns[c] @ target - later) / upper[c, c]
    x[:] = combination[:rank] @ basis[:rank]
    multipliers = np.zeros(size)
    _back(lower, 0, rank, combination, multipliers)  # lower^T norm = combination
    norm[:] = 0.0
    norm[kept[:rank]] = multipliers[:rank]
    fit[:] = 0.0
    if exact:  # the request met: no miss, no multipliers of it
        return
    miss = spread @ combination[:rank] - equality_rhs[design:]
    gradient = np.zeros(size)  # the weighted miss's gradient on the fixed rows' basis
    gradient[:fixed] = (weights * miss) @ spread[:, :fixed]
    _back(lower, 0, fixed, gradient, multipliers)
    fit[kept[:fixed]] = multipliers[:fixed]


def exact_step(
    equality: np.ndarray,
    equality_rhs: np.ndarray,
    design: int,
    weights: np.ndarray,
    inequality: np.ndarray,
    lows: np.ndarray,
    uppers: np.ndarray,
    guess: np.ndarray,
    exact: bool,
    active_tol: float,
    tol: float,
    max_steps: int,
) -> tuple[bool, np.ndarray, np.ndarray]:
    """The exact answer on the active set that ProxQP's multipliers name.

    Args:
        equality: ``(k, d)`` the design rows, then the request's rows.
        equality_rhs: ``(k,)`` their right-hand sides.
        design: How many design rows.
        weights: ``(k - design,)`` the request rows' weights (``exact=False``).
        inequality: ``(m, d)`` rows bounded on both sides.
        lows: ``(m,)`` lower bounds.
        uppers: ``(m,)`` upper bounds.
        guess: ``(m,)`` ProxQP's inequality multipliers (< 0 at a lower bound, > 0 at an upper
            one): the first active set, rows with ``|guess| > active_tol``.
        exact: The request exactly (else the closest wrench, then the least norm).
        active_tol: See ``guess``.
        tol: Tolerance of the KKT checks (on the scaled problem).
        max_steps: Active-set changes allowed.

    Returns:
        ``(ok, x, z)``: whether the KKT conditions hold, the answer, and the inequalities'
        multipliers in ProxQP's sign convention (nonzero: active).
    """
    k, m, size = equality.shape[0], inequality.shape[0], equality.shape[1]
    rows = np.vstack((equality, inequality))
    side = np.zeros(m, dtype=np.int64)
    side[guess < -active_tol] = -1
    side[guess > active_tol] = 1
    x = np.zeros(size)
    fit = np.zeros(k + m)
    norm = np.zeros(k + m)
    checked = np.arange(k) < (k if exact else design)  # the rows that must hold
    for _ in range(max_steps + 1):
        bounds = np.where(side < 0, lows, uppers)
        _solve(rows, k, equality_rhs, design, weights, bounds, side, exact, x, fit, norm)
        # a multiplier of the wrong sign (>= 0 at a lower bound, <= 0 at an upper one) leaves:
        # the least norm's, or for the closest wrench the weighted miss's first
        by_norm = exact | (np.abs(fit[k:]) <= tol)
        wrong = side * np.where(by_norm, norm[k:], fit[k:])
        wrong = np.where((side != 0) & (wrong > tol), wrong, -np.inf)
        if m and wrong.max() > -np.inf:
            side[int(np.argmax(wrong))] = 0
            continue
        # the most violated inequality enters first: on an active set that still misses rows x
        # can be large, its rows met only to round-off of |x| (checked on the answer below)
        values = rows @ x
        below = np.where(side == 0, lows - values[k:], -np.inf)
        above = np.where(side == 0, values[k:] - uppers, -np.inf)
        violation = np.fmax(below, above)
        violation = np.where(violation > tol, violation, -np.inf)
        if m and violation.max() > -np.inf:
            enter = int(np.argmax(violation))
            side[enter] = -1 if below[enter] > tol else 1
            continue
        # every row: design rows (and dropped ones) and active rows to tol, the request to tol
        # when exact, the other inequalities inside their bounds
        held = np.abs(values[:k] - equality_rhs)[checked] <= tol
        bound = np.abs(values[k:] - bounds)[side != 0] <= tol
        if not (np.all(held) and np.all(bound)):
            break
        return True, x, side * (np.abs(fit[k:]) + np.abs(norm[k:]))
    return False, x, np.zeros(m)


#: `exact_step` as the library calls it: the compiled core's port when it is built.
_EXACT_STEP = core.kernel("exact_step", exact_step)


def exact_answer(
    equality: np.ndarray,
    equality_rhs: np.ndarray,
    design: int,
    weights: np.ndarray,
    inequality: np.ndarray,
    lows: np.ndarray,
    uppers: np.ndarray,
    x: np.ndarray,
    guess: np.ndarray,
    exact: bool,
    active_tol: float,
) -> tuple[bool, np.ndarray, np.ndarray]:
    """`exact_step`'s ``(True, x, z)`` if its KKT checks pass, else ``(False, x, guess)``."""
    ok, exact_x, z = _EXACT_STEP(
        equality, equality_rhs, design, weights, inequality, lows, uppers, guess, exact,
        active_tol, EXACT_TOL, EXACT_STEPS,
    )  # fmt: skip
    return (True, exact_x, z) if ok else (False, x, guess)
