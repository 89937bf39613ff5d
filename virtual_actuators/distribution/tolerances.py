"""Every threshold of the force distribution, once, with its reason.

The numpy paths and the compiled kernels read the same names, so that a tick the kernel hands
back is decided by the same numbers. Solver budgets (iteration counts, batch sizes) stay with
their solver (the QP's in `qp.stages`, `qp.exact`, `qp.conflict`).
"""

from __future__ import annotations

#: Singular values of a chain's Jacobian below this [m/rad, m/m or rad/rad] mean the chain
#: produces nothing in that direction, whatever their ratio to the largest one.
JACOBIAN_FLOOR = 1e-12

#: A residual below this fraction of the largest chain force is rounding, whatever the
#: request: chain forces that cancel each other leave about ``cond * eps * |F|`` behind.
ROUNDING = 1e-12

#: Condition estimate above which a system is treated as singular (the partitioner re-picks its
#: sets, the compiled kernel hands the tick to numpy).
ILL_CONDITIONED = 1e10

#: A partitioned answer that misses an exact row (limp or spring torque, zero moment at a point
#: foot, coupling or design row) by more than this fraction of ``|row| max|F| + |rhs|`` came
#: from an ill-conditioned elimination: the dense reference solves that tick instead.
CONSTRAINT_TOL = 1e-10

#: A chain is singular when its smallest needed singular value falls below this fraction of its
#: largest one (the problem's evaluation raises SingularConfigurationError).
SINGULAR_TOL = 1e-9

#: The compiled path hands a tick to numpy when a chain's worst singular-value ratio is below
#: this: closer to singular than the kernels decide alone (numpy re-picks or raises).
NEAR_SINGULAR = 1e-7

#: Relative singular-value cut-off of the rank decisions (least norm, the dense reference, the
#: serial actuator's pseudo-inverse): below it a direction counts as missing.
RCOND = 1e-10

#: A chain whose natural rows' smallest singular value is below this fraction of the largest
#: has degenerate natural constraints here (the partitioned closed form cannot decide).
DEGENERATE = 1e-10

#: A limp or passive joint's natural-constraint row is structurally zero (no selected axis loads
#: the joint) when its norm stays below this fraction of the chain's largest Jacobian column.
VACUOUS_TOL = 1e-10

#: A row depends on the rows before it when pivoted QR leaves less than this fraction of its
#: norm (declaration-time checks of the natural and design rows; the QP's exact step drops such
#: a row from its solve and checks its residual).
DEPENDENT_TOL = 1e-9

#: The QP's exact step takes a row again after the other rows of its group when what it adds to
#: the rows before it is below this fraction of its norm (but above ``DEPENDENT_TOL``): rows
#: nearly dependent in the order given (two feet whose request rows miss one direction, say)
#: would leave a direction of rounding and a wrong least norm; taken later, such a row is
#: dependent on the rows that complete it.
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

#: ProxQP's absolute accuracy (residuals and duality gap) in the closest-wrench stages (cold
#: starts, on infeasible requests only): the closest wrench to ~1e-10 of the request.
CLOSEST_EPS_ABS = 1e-12

#: An answer that misses a row by more than this (scaled) is not feasible: ProxQP meets the rows
#: only to its accuracy, and an infeasible request can look solved.
FEASIBILITY_TOL = 1e-8

#: A multiplier above this (scaled) marks its inequality active.
ACTIVE_TOL = 1e-9

#: The KKT checks' tolerance of the exact step on an active set (rows, bounds and multipliers
#: ~1): an answer that passes is the optimum to rounding, else ProxQP's answer stands.
EXACT_TOL = 1e-11

#: A row that cannot hold is named when its bound moves by at least this share of the largest
#: shift (the least squared shift that lets the rows hold together).
CONFLICT_SHARE = 1e-6

#: The compiled QP hands a tick to numpy when a pivot of a chain's elimination falls below this
#: fraction of the chain's largest column (closer to singular than the kernel decides alone).
RANK_TOL = 1e-7
