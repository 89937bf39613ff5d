"""The QP's exact final step on the active set that ProxQP's multipliers name: the core's or Python.

With ``D x = d`` the design rows, ``A x = w`` the request's rows (weights ``omega``) and the
active inequalities at their bounds ``C_W x = b_W``: the request exactly (``exact=True``) is the
least-norm ``x`` of ``D``, ``C_W``, ``A``; the closest wrench (``exact=False``) minimises
``sum_a omega_a (A x - w)_a^2`` on ``D``, ``C_W`` with the least norm among the minimisers.
The KKT conditions are checked and the active set corrected one row at a time; plain loops
(``src/core/exact.hpp`` is their C++ port).
"""

from __future__ import annotations

import numpy as np

from ... import core
from ..tolerances import DEPENDENT_TOL, EXACT_TOL, NEARLY_DEPENDENT_TOL

#: Active-set changes allowed before ProxQP's answer is kept.
EXACT_STEPS = 16


def _row(equality: np.ndarray, inequality: np.ndarray, index: int, out: np.ndarray) -> None:
    """Row ``index`` of ``[equality; inequality]`` into ``out``."""
    k = equality.shape[0]
    for j in range(out.shape[0]):
        out[j] = equality[index, j] if index < k else inequality[index - k, j]


def _add_row(
    equality: np.ndarray,
    inequality: np.ndarray,
    index: int,
    rank: int,
    defer: bool,
    basis: np.ndarray,
    lower: np.ndarray,
    kept: np.ndarray,
    row: np.ndarray,
    coefficients: np.ndarray,
) -> tuple[int, bool]:
    """Gram-Schmidt of row ``index`` against the ``rank`` rows kept: ``(rank, deferred)``.

    The row is dropped if it depends on the kept rows, deferred if ``defer`` and what it adds is
    below `NEARLY_DEPENDENT_TOL` of its norm.
    """
    size = basis.shape[1]
    _row(equality, inequality, index, row)
    norm = 0.0
    for j in range(size):
        norm += row[j] * row[j]
    norm = np.sqrt(norm)
    if norm == 0.0:
        return rank, False
    coefficients[:rank] = 0.0
    rest = norm
    for _ in range(3):  # Gram-Schmidt, again while a sweep removes much of the row
        before = rest
        for b in range(rank):
            dot = 0.0
            for j in range(size):
                dot += basis[b, j] * row[j]
            coefficients[b] += dot
            for j in range(size):
                row[j] -= dot * basis[b, j]
        rest = 0.0
        for j in range(size):
            rest += row[j] * row[j]
        rest = np.sqrt(rest)
        if rank == 0 or rest > 0.7 * before or rest <= DEPENDENT_TOL * norm:
            break
    if rest <= DEPENDENT_TOL * norm:
        return rank, False
    if defer and rest <= NEARLY_DEPENDENT_TOL * norm:
        return rank, True
    for j in range(size):
        basis[rank, j] = row[j] / rest
    for b in range(rank):
        lower[rank, b] = coefficients[b]
    lower[rank, rank] = rest
    kept[rank] = index
    return rank + 1, False


def _factor(
    equality: np.ndarray,
    design: int,
    inequality: np.ndarray,
    side: np.ndarray,
    basis: np.ndarray,
    lower: np.ndarray,
    kept: np.ndarray,
) -> tuple[int, int]:
    """Gram-Schmidt on the design rows, the active inequality rows, then the request rows.

    Writes ``basis`` and ``lower`` with ``row kept[r] = sum_b lower[r, b] basis[b]``; returns
    ``(rank, rank of the design and active rows)``. Deferred rows are retried after their group.
    """
    k, size = equality.shape[0], equality.shape[1]
    order = np.empty(k + inequality.shape[0], dtype=np.int64)
    count = 0
    for index in range(design):
        order[count] = index
        count += 1
    for r in range(inequality.shape[0]):
        if side[r] != 0:
            order[count] = k + r
            count += 1
    fixed = count
    for index in range(design, k):
        order[count] = index
        count += 1
    row = np.empty(size)
    coefficients = np.empty(size)
    deferred = np.empty(count, dtype=np.int64)
    rank, rank_fixed = 0, 0
    for group in range(2):
        start, stop = (0, fixed) if group == 0 else (fixed, count)
        waiting = 0
        for position in range(start, stop):
            if rank == size:
                break  # every later row depends on the kept ones (checked by the caller)
            rank, later = _add_row(equality, inequality, order[position], rank, True, basis,
                                   lower, kept, row, coefficients)  # fmt: skip
            if later:
                deferred[waiting] = order[position]
                waiting += 1
        for position in range(waiting):
            if rank == size:
                break
            rank, _ = _add_row(equality, inequality, deferred[position], rank, False, basis,
                               lower, kept, row, coefficients)  # fmt: skip
        if group == 0:
            rank_fixed = rank
    return rank, rank_fixed


def _back(lower: np.ndarray, start: int, stop: int, rhs: np.ndarray, out: np.ndarray) -> None:
    """``lower[start:stop, start:stop]^T out = rhs`` (``out`` and ``rhs`` over ``start:stop``)."""
    for r in range(stop - 1, start - 1, -1):
        acc = rhs[r]
        for b in range(r + 1, stop):
            acc -= lower[b, r] * out[b]
        out[r] = acc / lower[r, r]


def _solve(
    equality: np.ndarray,
    equality_rhs: np.ndarray,
    design: int,
    weights: np.ndarray,
    inequality: np.ndarray,
    bounds: np.ndarray,
    side: np.ndarray,
    exact: bool,
    x: np.ndarray,
    fit: np.ndarray,
    norm: np.ndarray,
) -> None:
    """The answer on one active set, and its multipliers.

    Writes ``x``, ``fit`` (the weighted least squares' multipliers; 0 when ``exact``) and ``norm``
    (the least norm's: ``x = sum rows^T norm``), both over ``[equality; inequality]``.
    """
    k, size = equality.shape[0], equality.shape[1]
    basis = np.zeros((size, size))
    lower = np.zeros((size, size))
    kept = np.empty(size, dtype=np.int64)
    rank, fixed = _factor(equality, design, inequality, side, basis, lower, kept)
    combination = np.zeros(size)  # x = basis^T combination
    for r in range(fixed):  # the design and active rows exactly: forward substitution
        index = kept[r]
        acc = equality_rhs[index] if index < k else bounds[index - k]
        for b in range(r):
            acc -= lower[r, b] * combination[b]
        combination[r] = acc / lower[r, r]
    # the request on what it adds (basis rows fixed:rank), weighted least squares
    requests, extra = k - design, rank - fixed
    row = np.empty(size)
    spread = np.zeros((requests, size))  # each request row on the basis
    target = np.empty(requests)
    for i in range(requests):
        _row(equality, inequality, design + i, row)
        for b in range(rank):
            dot = 0.0
            for j in range(size):
                dot += basis[b, j] * row[j]
            spread[i, b] = dot
        acc = equality_rhs[design + i]
        for b in range(fixed):
            acc -= spread[i, b] * combination[b]
        root = np.sqrt(weights[i])
        target[i] = root * acc
    columns = np.empty((extra, requests))  # columns of the weighted system, orthonormalised
    upper = np.zeros((extra, extra))
    for c in range(extra):
        for i in range(requests):
            columns[c, i] = np.sqrt(weights[i]) * spread[i, fixed + c]
        for _ in range(2):
            for b in range(c):
                dot = 0.0
                for i in range(requests):
                    dot += columns[b, i] * columns[c, i]
                upper[b, c] += dot
                for i in range(requests):
                    columns[c, i] -= dot * columns[b, i]
        length = 0.0
        for i in range(requests):
            length += columns[c, i] * columns[c, i]
        upper[c, c] = np.sqrt(length)
        for i in range(requests):
            columns[c, i] /= upper[c, c]
    for c in range(extra - 1, -1, -1):  # upper combination = columns^T target
        acc = 0.0
        for i in range(requests):
            acc += columns[c, i] * target[i]
        for b in range(c + 1, extra):
            acc -= upper[c, b] * combination[fixed + b]
        combination[fixed + c] = acc / upper[c, c]
    for j in range(size):
        acc = 0.0
        for b in range(rank):
            acc += basis[b, j] * combination[b]
        x[j] = acc
    multipliers = np.zeros(size)
    _back(lower, 0, rank, combination, multipliers)  # lower^T norm = combination
    norm[:] = 0.0
    for r in range(rank):
        norm[kept[r]] = multipliers[r]
    fit[:] = 0.0
    if exact:  # the request met: no miss, no multipliers of it
        return
    gradient = np.zeros(size)  # the weighted miss's gradient on the fixed rows' basis
    for i in range(requests):
        acc = -equality_rhs[design + i]
        for b in range(rank):
            acc += spread[i, b] * combination[b]
        for b in range(fixed):
            gradient[b] += weights[i] * acc * spread[i, b]
    _back(lower, 0, fixed, gradient, multipliers)
    for r in range(fixed):
        fit[kept[r]] = multipliers[r]


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
    side = np.zeros(m, dtype=np.int64)
    for r in range(m):
        if guess[r] < -active_tol:
            side[r] = -1
        elif guess[r] > active_tol:
            side[r] = 1
    x = np.zeros(size)
    fit = np.zeros(k + m)
    norm = np.zeros(k + m)
    bounds = np.empty(m)
    for _ in range(max_steps + 1):
        for r in range(m):
            bounds[r] = lows[r] if side[r] < 0 else uppers[r]
        _solve(equality, equality_rhs, design, weights, inequality, bounds, side, exact, x, fit,
               norm)  # fmt: skip
        # a multiplier of the wrong sign (>= 0 at a lower bound, <= 0 at an upper one) leaves:
        # the least norm's, or for the closest wrench the weighted miss's first
        worst, leave = tol, -1
        for r in range(m):
            if side[r] == 0:
                continue
            if exact or abs(fit[k + r]) <= tol:
                wrong = side[r] * norm[k + r]
            else:
                wrong = side[r] * fit[k + r]
            if wrong > worst:
                worst, leave = wrong, r
        if leave >= 0:
            side[leave] = 0
            continue
        # every row: design rows (and dropped ones) and active rows to tol, the request to tol
        # when exact, the other inequalities inside their bounds (the most violated enters)
        worst, enter, enter_side = tol, -1, 0
        consistent = True
        for r in range(k + m):
            acc = 0.0
            if r < k:
                for j in range(size):
                    acc += equality[r, j] * x[j]
            else:
                for j in range(size):
                    acc += inequality[r - k, j] * x[j]
            if r < design or (r < k and exact):
                consistent &= abs(acc - equality_rhs[r]) <= tol
            elif r < k:
                continue
            elif side[r - k] != 0:
                consistent &= abs(acc - bounds[r - k]) <= tol
            elif lows[r - k] - acc > worst:
                worst, enter, enter_side = lows[r - k] - acc, r - k, -1
            elif acc - uppers[r - k] > worst:
                worst, enter, enter_side = acc - uppers[r - k], r - k, 1
        if not consistent:
            break
        if enter < 0:
            z = np.zeros(m)
            for r in range(m):
                if side[r] != 0:
                    z[r] = side[r] * (abs(fit[k + r]) + abs(norm[k + r]))
            return True, x, z
        side[enter] = enter_side
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


__all__ = ["EXACT_STEPS", "exact_answer", "exact_step"]
