"""Contact-aware distribution as a quadratic program (``solve(q, w, method="qp")``).

The natural and design constraints stay equalities; the contacts add inequalities:

- a **friction pyramid** at each chain: with ``n`` the contact normal (world z unless one is given
  per reaction, expressed in {O}) and ``t1, t2`` two tangents, ``n . f >= min_normal`` and
  ``|t_k . f| <= mu n . f`` (four faces: an inner pyramid of the cone, exact along ``t1``, ``t2``);
- a **centre of pressure inside the sole** for flat contacts given a sole ``(half_length,
  half_width)``: the moment about the reaction frame's origin, in that frame, satisfies
  ``|m_x| <= half_width f_n`` and ``|m_y| <= half_length f_n``, and the yaw moment
  ``|m_z| <= mu min(half_length, half_width) f_n`` (a conservative contact wrench cone);
- **torque limits** ``|tau_j| <= limit_j`` at the actuated joints (the URDF effort limits, or an
  array).

Objective, on a problem scaled to ``|w| ~ 1``: first the request exactly with the least force
norm, ``min |F|^2`` subject to ``sum_i F_i = w`` on the prescribed axes (the usual case: one
solve, and with no inequality active exactly the partitioned minimum-norm answer); if that has no
solution, the closest feasible wrench, ``min |sum_i F_i - w|^2 + DELTA |F|^2``, and
``sol.residual`` reports the miss. Solved by ProxQP (proxsuite, dense), warm-started from the
previous solve of the same thread.
"""

from __future__ import annotations

import threading
from collections.abc import Mapping, Sequence

import numpy as np

from ..exceptions import ConstraintError, InvalidInputError
from ..vocabulary.frames import AXES
from .linalg import ROUNDING, stable_norm
from .partitioner import RawSolution
from .problem import DistributionProblem

#: Weight of the force norm against the miss when the request is infeasible (scaled problem).
DELTA = 1e-6
#: An answer that misses a row by more than this (scaled) is not feasible.
FEASIBILITY_TOL = 1e-8
#: ProxQP's absolute accuracy on the scaled problem.
EPS_ABS = 1e-10
#: ProxQP's iteration budget (outer and inner): a tick never waits on a degenerate problem.
MAX_ITER = 300
#: ProxQP's "no bound".
INFINITY = 1e20
#: Effort limits at or above this [N m, N] mean "unlimited".
UNLIMITED = 1e30
#: A multiplier above this (scaled) marks its inequality active.
ACTIVE_TOL = 1e-9


class ContactLimits:
    """The inequalities of a parallel actuator's QP, declared once.

    Args:
        problem: The distribution problem.
        friction: Friction coefficient ``mu`` of every contact, or None for no cone.
        min_normal: Least normal force of every contact [N].
        normals: World-frame contact normal per reaction frame (default: world z).
        soles: ``(half_length, half_width)`` [m] of flat contacts' soles, by reaction frame.
        torque_limits: False (none), True (URDF effort limits) or ``(nv,)`` limits [N m, N].

    Raises:
        InvalidInputError: Bad values (a negative limit, a zero normal, an unknown reaction).

    """

    def __init__(
        self,
        problem: DistributionProblem,
        friction: float | None,
        min_normal: float,
        normals: Mapping[str, Sequence[float]] | None,
        soles: Mapping[str, Sequence[float]] | None,
        torque_limits: bool | Sequence[float] | np.ndarray,
    ) -> None:
        self.problem = problem
        self.friction = friction
        self.min_normal = float(min_normal)
        reactions = problem.reactions
        self.normals_world = np.tile([0.0, 0.0, 1.0], (problem.p, 1))
        for name, normal in dict(normals or {}).items():
            index = self._reaction(name, "normals")
            vector = np.asarray(normal, dtype=float).reshape(-1)
            size = float(np.linalg.norm(vector)) if vector.shape == (3,) else 0.0
            if not size or not np.isfinite(size):
                raise InvalidInputError(
                    f"normals[{name!r}] must be a nonzero 3-vector (world frame), got {normal!r}."
                )
            self.normals_world[index] = vector / size
        self.soles: dict[int, tuple[float, float]] = {}
        for name, sole in dict(soles or {}).items():
            index = self._reaction(name, "soles")
            values = np.asarray(sole, dtype=float).reshape(-1)
            if values.shape != (2,) or not np.all(np.isfinite(values)) or np.any(values <= 0):
                raise InvalidInputError(
                    f"soles[{name!r}] must be (half_length, half_width) > 0 [m], got {sole!r}."
                )
            if problem.contacts[index] != "flat":
                raise InvalidInputError(
                    f"soles[{name!r}]: {name!r} is a point contact; a sole needs contact='flat'."
                )
            self.soles[index] = (float(values[0]), float(values[1]))
        model = problem.model
        if torque_limits is True:
            limits = np.asarray(model.effortLimit, dtype=float).copy()
            limits[(limits <= 0) | ~np.isfinite(limits)] = np.inf
        elif torque_limits is False or torque_limits is None:
            limits = np.full(model.nv, np.inf)
        else:
            limits = np.asarray(torque_limits, dtype=float).reshape(-1)
            if limits.shape != (model.nv,) or np.any(np.isnan(limits)) or np.any(limits < 0):
                raise InvalidInputError(
                    f"torque_limits must be True, False or {model.nv} numbers >= 0, got "
                    f"{torque_limits!r}."
                )
        limits = np.where(limits >= UNLIMITED, np.inf, limits)  # URDFs write "none" as 1e308
        limited = problem.actuated_mask & np.isfinite(limits)
        self.limited_v = np.flatnonzero(limited)
        self.limits = limits[self.limited_v]
        axes = problem.axes
        self.force_axes = [axes.index(a) for a in AXES[:3] if a in axes]
        self.force_components = [AXES.index(a) for a in AXES[:3] if a in axes]
        self.moment_axes = [axes.index(a) for a in AXES[3:] if a in axes]
        self.moment_components = [AXES.index(a) - 3 for a in AXES[3:] if a in axes]
        self.names = reactions
        #: rows of the cone (normal bound, friction faces) when the actuator has force axes
        self._cone = bool(self.force_axes) and (
            self.friction is not None or self.min_normal > 0.0 or bool(self.soles)
        )
        self._row_names: list[str] | None = None
        # the cone's scatter into (chain, face, p n) and its bounds depend on the declaration only
        faces = 5 if self.friction is not None else 1
        chains = np.arange(problem.p)[:, None, None]
        self._cone_index = (
            chains,
            np.arange(faces)[None, :, None],
            chains * problem.n + np.asarray(self.force_axes, dtype=int)[None, None, :],
        )
        self._cone_lows = np.tile([self.min_normal] + [0.0] * (faces - 1), problem.p)

    def _reaction(self, name: object, what: str) -> int:
        if name not in self.problem.reactions:
            raise InvalidInputError(
                f"{what} names {name!r}, not a reaction frame; reactions are "
                f"{list(self.problem.reactions)}."
            )
        return self.problem.reactions.index(name)

    @property
    def any(self) -> bool:
        """Whether there is at least one inequality."""
        return (
            self.friction is not None
            or bool(self.soles)
            or bool(self.limited_v.size)
            or (self.min_normal > 0.0)
        )

    def _names(self) -> list[str]:
        """The inequality rows' names, in the order :meth:`rows` builds them."""
        names: list[str] = []
        if self._cone:
            for reaction in self.names:
                names.append(f"{reaction}: normal >= {self.min_normal:g} N")
                if self.friction is not None:
                    names += [f"{reaction}: friction {w}" for w in ("+t1", "-t1", "+t2", "-t2")]
        for i, (half_length, half_width) in self.soles.items():
            if not self.moment_axes:
                continue
            mu = self.friction if self.friction is not None else 0.0
            for label, half in (("x", half_width), ("y", half_length), ("z", mu * min(
                half_length, half_width))):  # fmt: skip
                names.append(f"{self.names[i]}: moment {label} <= {half:g} f_n")
                names.append(f"{self.names[i]}: moment {label} >= -{half:g} f_n")
        for v, limit in zip(self.limited_v, self.limits, strict=True):
            names.append(f"torque {self.problem.joint_name(int(v))}: |tau| <= {limit:g}")
        return names

    def rows(
        self, state: object, torque_map: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[str]]:
        """``lows <= C x <= uppers`` over ``x = forces.ravel()``, with a name per row.

        Args:
            state: The tick's kinematic state (rotations, offsets, Jacobian rows in {O}).
            torque_map: ``(nv, p n)`` joint torques of ``x``.

        """
        p, n = self.problem.p, self.problem.n
        blocks: list[np.ndarray] = []
        lows: list[np.ndarray] = []
        rotation_o = state.rotation_o
        normals_o = self.normals_world @ rotation_o  # rows: R_O^T n, per chain
        if self._cone:
            helper = np.where(np.abs(normals_o[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
            tangent1 = _cross(normals_o, helper)
            tangent1 /= np.linalg.norm(tangent1, axis=1, keepdims=True)
            tangent2 = _cross(normals_o, tangent1)
            vectors = [normals_o]
            if self.friction is not None:
                mu_normal = self.friction * normals_o
                vectors += [mu_normal - tangent1, mu_normal + tangent1]
                vectors += [mu_normal - tangent2, mu_normal + tangent2]
            stacked = np.stack(vectors, axis=1)  # (p, faces, 3)
            cone = np.zeros((p, stacked.shape[1], p * n))
            cone[self._cone_index] = stacked[:, :, self.force_components]
            blocks.append(cone.reshape(-1, p * n))
            lows.append(self._cone_lows)
        if self.soles and self.moment_axes:
            offsets = state.offsets_o()  # (p, 3): from {A_i} to {B} in {O}
            for i, sole in self.soles.items():
                sole_rows = self._sole_rows(i, sole, normals_o[i], offsets[i], rotation_o, state)
                blocks.append(sole_rows)
                lows.append(np.zeros(len(sole_rows)))
        one_sided = sum(len(low) for low in lows)
        if self.limited_v.size:
            blocks.append(torque_map[self.limited_v])  # two-sided: -limit <= tau <= limit
            lows.append(-self.limits)
        if not blocks:
            return np.zeros((0, p * n)), np.zeros(0), np.zeros(0), []
        if self._row_names is None:
            self._row_names = self._names()
        low = np.concatenate(lows)
        upper = np.full(len(low), INFINITY)
        upper[one_sided:] = self.limits
        return np.vstack(blocks), low, upper, self._row_names

    def _sole_rows(self, i, sole, normal, offset, rotation_o, state) -> np.ndarray:
        """Centre of pressure inside the sole and a bounded yaw moment (flat contact ``i``)."""
        p, n = self.problem.p, self.problem.n
        half_length, half_width = sole
        # the reaction frame's axes in {O}; moments about {A_i}'s origin: m_A = m_B + d x f
        frame_o = rotation_o.T @ state.rotation_a[i]  # columns: the frame's x, y, z in {O}
        force_cols = i * n + np.array(self.force_axes)
        moment_cols = i * n + np.array(self.moment_axes)
        normal_row = np.zeros(p * n)  # the force along the sole's normal (its frame's z)
        normal_row[force_cols] = frame_o[self.force_components, 2]
        mu = self.friction if self.friction is not None else 0.0
        out = []
        for column, half in ((0, half_width), (1, half_length), (2, mu * min(sole))):
            axis_o = frame_o[:, column]
            row = np.zeros(p * n)  # axis . m_A = axis . m_B + f . (axis x d)
            row[moment_cols] = axis_o[self.moment_components]
            row[force_cols] += _cross(axis_o, offset)[self.force_components]
            out += [half * normal_row - row, half * normal_row + row]
        return np.array(out)


def _kinds(names: Sequence[str]) -> list[str]:
    """The kinds of inequality among row names: friction, normal, moment, torque."""
    words = ("friction", "normal", "moment", "torque")
    return [word for name in names for word in words if word in name] or ["none"]


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross products of ``(..., 3)`` arrays (np.cross costs ~10 us a call)."""
    return np.stack(
        (
            a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
            a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
            a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0],
        ),
        axis=-1,
    )


def torque_map(problem: DistributionProblem, jacobian_o: np.ndarray) -> np.ndarray:
    """``(nv, p n)``: the joint torques ``sum_i J_i^T F_i`` as a matrix over ``F.ravel()``."""
    p, n = problem.p, problem.n
    matrix = np.zeros((problem.model.nv, p * n))
    for group in problem.groups:
        columns = group.columns  # (g, k): each chain's velocity columns
        targets = group.chains[:, None, None] * n + np.arange(n)[None, None, :]
        share = jacobian_o[:, columns].transpose(1, 2, 0) * group.signs[:, :, None]  # (g, k, n)
        matrix[columns[:, :, None], targets] += share
    return matrix


class QPDistribution:
    """The QP distribution of one parallel actuator (one ProxQP workspace per thread).

    Args:
        problem: The distribution problem.
        limits: The inequalities.

    Raises:
        InvalidInputError: proxsuite is not installed.

    """

    def __init__(self, problem: DistributionProblem, limits: ContactLimits) -> None:
        try:
            import proxsuite  # noqa: F401  (checked here: a clear error at declaration)
        except ImportError as error:  # pragma: no cover - proxsuite is a dependency
            raise InvalidInputError(
                "method='qp' needs proxsuite (pip install proxsuite)."
            ) from error
        self.problem = problem
        self.limits = limits
        self._local = threading.local()
        self._identity = np.eye(problem.p * problem.n)
        #: per set of prescribed axes: the rows summing the chains' forces on them
        self._selects: dict[bytes, np.ndarray] = {}

    def _workspace(self, stage: str, n_var: int, n_eq: int, n_in: int) -> list:
        from proxsuite import proxqp

        key = (stage, n_var, n_eq, n_in)
        cache = getattr(self._local, "qps", None)
        if cache is None:
            cache = self._local.qps = {}
        qp = cache.get(key)
        if qp is None:
            qp = proxqp.dense.QP(n_var, n_eq, n_in)
            qp.settings.eps_abs = EPS_ABS
            qp.settings.eps_rel = 0.0
            qp.settings.max_iter = MAX_ITER
            qp.settings.max_iter_in = MAX_ITER
            qp.settings.verbose = False
            qp = cache[key] = [qp, True]  # the workspace, and whether it needs init()
        return qp

    def _run(self, stage, hessian, gradient, equality, equality_rhs, inequality, lows, uppers):
        """Solve one QP in this thread's workspace (warm-started); None if it has no solution."""
        from proxsuite import proxqp

        workspace = self._workspace(stage, hessian.shape[0], len(equality_rhs), len(lows))
        qp, fresh = workspace
        if fresh:
            qp.init(hessian, gradient, equality, equality_rhs, inequality, lows, uppers)
            workspace[1] = False
        else:
            qp.settings.initial_guess = proxqp.InitialGuess.WARM_START_WITH_PREVIOUS_RESULT
            qp.update(hessian, gradient, equality, equality_rhs, inequality, lows, uppers)
        qp.solve()
        status = qp.results.info.status
        solved = status == proxqp.QPSolverOutput.PROXQP_SOLVED
        # the closest wrench is an approximation anyway: a feasible answer out of iterations is
        # kept (the request exactly, never: it goes on to the closest wrench)
        usable = solved or (
            stage == "closest" and status == proxqp.QPSolverOutput.PROXQP_MAX_ITER_REACHED
        )
        if not usable:
            workspace[1] = True  # start the next solve afresh
            return None
        # ProxQP's answer meets the rows to EPS_ABS: an infeasible request can look solved
        x = np.asarray(qp.results.x)
        slack = float(np.abs(equality @ x - equality_rhs).max(initial=0.0))
        if len(lows):
            values = inequality @ x
            slack = max(slack, float(np.max(lows - values)), float(np.max(values - uppers)))
        if slack > FEASIBILITY_TOL:
            return None
        return qp

    def solve(
        self, snapshot: object, wrench: np.ndarray, keep: np.ndarray
    ) -> tuple[RawSolution, tuple]:
        """Distribute ``wrench`` with the QP at a snapshot.

        Returns:
            ``(raw solution, (tau, passive torques, produced, requested, residual, scale,
            rounding))`` like the other paths, ``raw.method == "qp"``, ``raw.active`` the names
            of the active inequalities.

        Raises:
            ConstraintError: No distribution meets the equalities and the inequalities here.

        """
        problem = self.problem
        p, n = problem.p, problem.n
        ev = problem.evaluate(snapshot, check_singular=False)
        state = ev.state
        natural, natural_rhs = problem.block_natural(ev)
        hard = ev.hard_rows.reshape(len(ev.hard_rhs), p * n)
        equality = np.vstack((natural, hard))
        equality_rhs = np.concatenate((natural_rhs, ev.hard_rhs))
        tmap = torque_map(problem, state.jacobian_o)
        inequality, lows, uppers, names = self.limits.rows(state, tmap)
        # scale: the request, spring torques and bounds to ~1 (homogeneous answers)
        kept = np.flatnonzero(keep)
        scale = max(
            float(np.abs(wrench[kept]).max(initial=0.0)),
            float(np.abs(equality_rhs).max(initial=0.0)),
            float(np.abs(lows).max(initial=0.0)),
            1e-300,
        )
        target = wrench[kept] / scale
        select = self._selects.get(keep.tobytes())
        if select is None:
            select = np.zeros((len(kept), p * n))
            for r, axis in enumerate(kept):
                select[r, axis::n] = 1.0
            self._selects[keep.tobytes()] = select
        identity = self._identity
        # 1. the request exactly, least force norm (the usual case: one solve)
        qp = self._run(
            "exact", identity, np.zeros(p * n), np.vstack((equality, select)),
            np.concatenate((equality_rhs / scale, target)), inequality, lows / scale,
            np.minimum(uppers / scale, INFINITY),
        )  # fmt: skip
        if qp is None:
            # 2. infeasible: the closest wrench, then (weighted by DELTA) the least force norm
            qp = self._run(
                "closest", select.T @ select + DELTA * identity, -select.T @ target, equality,
                equality_rhs / scale, inequality, lows / scale,
                np.minimum(uppers / scale, INFINITY),
            )  # fmt: skip
        if qp is None:
            raise ConstraintError(
                f"No distribution over the chains to {list(problem.reactions)} meets every "
                "constraint at this configuration: the natural and design equalities and the "
                f"inequalities ({', '.join(sorted(set(_kinds(names))))}) cannot all hold (e.g. "
                "min_normal with tight torque limits)."
            )
        x = np.array(qp.results.x) * scale
        active = tuple(
            name
            for name, z in zip(names, np.array(qp.results.z), strict=True)
            if abs(z) > ACTIVE_TOL
        )
        forces = x.reshape(p, n)
        tau_total = tmap @ x
        tau = np.where(problem.actuated_mask, tau_total, 0.0)
        produced = forces.sum(axis=0)
        residual = stable_norm((produced - wrench)[kept])
        request = stable_norm(wrench[kept])
        output = stable_norm(produced[kept])
        rounding = ROUNDING * float(np.abs(forces).max(initial=0.0)) + EPS_ABS * 10 * scale
        requested = np.where(keep, wrench, produced)
        raw = RawSolution(forces=forces, method="qp", solver="qp", active=active)
        return raw, (tau, ev.passive_torque, produced, requested, residual,
                     max(request, output), rounding)  # fmt: skip


__all__ = ["ContactLimits", "QPDistribution", "torque_map"]
