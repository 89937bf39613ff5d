"""Every threshold of the numpy force distribution, once (``src/core`` mirrors them).

Solver budgets (iteration counts) stay with their solver (`qp.stages`, `qp.exact`).
"""

from __future__ import annotations

#: Singular values of a chain's Jacobian below this [m/rad, m/m or rad/rad]: it produces nothing
JACOBIAN_FLOOR = 1e-12

#: A residual below this fraction of the largest chain force is rounding (forces that cancel)
ROUNDING = 1e-12

#: Condition estimate above which a system is singular (sets re-picked, the tick to numpy)
ILL_CONDITIONED = 1e10

#: A partitioned answer that misses an exact row by more than this fraction of
#: ``|row| max|F| + |rhs|`` is solved again by the dense reference
CONSTRAINT_TOL = 1e-10

#: A chain is singular when its smallest needed singular value is below this fraction of its
#: largest (SingularConfigurationError)
SINGULAR_TOL = 1e-9

#: Relative singular-value cut-off of the rank decisions (least norm, dense, pseudo-inverse)
RCOND = 1e-10

#: Natural rows whose smallest singular value is below this fraction of the largest: degenerate
DEGENERATE = 1e-10

#: A limp or passive joint's natural row below this fraction of the chain's largest Jacobian
#: column is structurally zero (no selected axis loads the joint)
VACUOUS_TOL = 1e-10

#: A row depends on the rows before it when pivoted QR leaves less than this fraction of its norm
DEPENDENT_TOL = 1e-9

#: The QP's exact step defers a row that adds less than this fraction of its norm (but more than
#: ``DEPENDENT_TOL``) to the rows before it, until the rest of its group is in
NEARLY_DEPENDENT_TOL = 1e-6
#: A dependent design row is implied by the others (rather than contradicting them) when their
#: least-squares solution meets it within this fraction of ``1 + max|rhs|``.
IMPLIED_TOL = 1e-9

#: Floor of a denominator that may be zero (a ratio of norms of an all-zero matrix is 0).
TINY = 1e-300

# -- the QP (qp/): on the problem divided by its scale, so rows, bounds and multipliers are ~1 --

#: ProxQP's "no bound" (its dense API takes finite bounds): bounds beyond it are clipped to it.
INFINITY = 1e20

#: ProxQP's absolute accuracy on the scaled problem (the exact stage, warm-started).
EPS_ABS = 1e-10

#: ProxQP's absolute accuracy (residuals and duality gap) in the closest-wrench stages
CLOSEST_EPS_ABS = 1e-12

#: An answer that misses a row by more than this (scaled) is not feasible
FEASIBILITY_TOL = 1e-8

#: A multiplier above this (scaled) marks its inequality active.
ACTIVE_TOL = 1e-9

#: The KKT checks' tolerance of the exact step on an active set (rows, bounds, multipliers ~1)
EXACT_TOL = 1e-11

#: A row that cannot hold is named when its bound moves by at least this share of the largest
#: shift (the least squared shift that lets the rows hold together).
CONFLICT_SHARE = 1e-6
