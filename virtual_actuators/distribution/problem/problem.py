"""The force distribution problem of a parallel virtual actuator (VAC eq. 8-11).

The declaration as arrays, once; eq. 11's rows at a ``q``, chain groups vectorised with numpy.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pinocchio as pin

from ...contacts.contact_set import ball_axes, parse_contacts
from ...exceptions import ConstraintError, SingularConfigurationError
from ...kinematics.kernels import skew
from ...kinematics.relative import KinematicState, RelativeKinematics
from ...kinematics.snapshot import Snapshot
from ...vocabulary.axes import AXES
from ...vocabulary.constraints import DesignConstraint
from ..tolerances import JACOBIAN_FLOOR, SINGULAR_TOL, TINY
from .checks import check_hard_rows, check_natural_rows, vacuous_joints
from .declaration import design_rows, parse_joints
from .structure import ChainGroup, Evaluation, GroupRows


class DistributionProblem:
    """Declaration-time structure of a parallel virtual actuator's force distribution.

    Args:
        kinematics: Relative kinematics of the action frame w.r.t. every reaction frame.
        reactions: Reaction frame names (one chain each).
        contact: ``"point"``, ``"flat"``, or a map from reaction name to either.
        unactuated: Names of limp joints (zero torque).
        passive: Map from joint name to ``(stiffness [N m/rad], rest angle [rad])``.
        design: Design constraints.

    Raises:
        JointNotFoundError: A limp, passive or torque-constrained joint is unknown or on no chain.
        ConstraintError: Contradictory, redundant or too many constraints; a chain with no joint.
        InvalidAxisError: A design constraint names an axis the actuator does not have.
    """

    def __init__(
        self,
        kinematics: RelativeKinematics,
        reactions: Sequence[str],
        contact: str | Mapping[str, str],
        unactuated: Sequence[str],
        passive: Mapping[str, tuple[float, float]],
        design: Sequence[DesignConstraint],
    ) -> None:
        self.kinematics = kinematics
        self.model: pin.Model = kinematics.model
        self.reactions = tuple(reactions)
        self.axes = kinematics.axes
        self.n = len(self.axes)
        self.p = len(self.reactions)
        self.contacts = parse_contacts(contact, self.reactions)
        for i, name in enumerate(self.reactions):
            if not len(kinematics.chain_columns[i]):
                raise ConstraintError(
                    f"Reaction frame {name!r} is rigidly attached to the action frame "
                    f"{self.model.frames[kinematics.action_id].name!r}: no joint lies between "
                    "them, so that chain cannot exert anything."
                )
        self.limp_v, self.passive_v = parse_joints(
            self.kinematics, self.reactions, unactuated, passive
        )
        self.actuated_mask = np.ones(self.model.nv, dtype=bool)
        self.actuated_mask[list(self.limp_v) + list(self.passive_v)] = False
        #: prescribed axes (``keep.tobytes()``) -> structurally singular
        self.structural: dict[bytes, bool] = {}
        #: limp joints no selected axis loads: their (zero) natural rows are dropped
        self.vacuous_v: tuple[int, ...] = ()
        #: ``(p, nv + 1)`` chain signs by velocity index, 0 off the chain (and at index -1)
        self.signs = np.zeros((self.p, self.model.nv + 1))
        for i, signs in enumerate(kinematics.chain_signs):
            self.signs[i, kinematics.chain_columns[i]] = signs
        self._ball_maps: dict[tuple, tuple[np.ndarray, np.ndarray]] = {}
        self._sum_rows: dict[bytes, np.ndarray] = {}
        self.constant_rows = np.zeros((0, self.p, self.n))
        self.constant_rhs = np.zeros(0)
        self.torque_pairs = np.zeros((0, 2), dtype=int)
        self._build_groups()
        self._build_design(design)

    def _build_groups(self) -> None:
        counts = np.zeros(self.model.nv, dtype=int)
        for columns in self.kinematics.chain_columns:
            counts[columns] += 1
        constrained_v = set(self.limp_v) | set(self.passive_v)
        #: velocity indices of limp/passive joints shared by several chains (coupling rows)
        self.coupled_v = sorted(v for v in constrained_v if counts[v] > 1)
        rot_axes = np.array([k for k in range(3) if AXES[3 + k] in self.axes], dtype=int)
        per_chain = []
        for i in range(self.p):
            columns = self.kinematics.chain_columns[i]
            own = [j for j, v in enumerate(columns) if v in constrained_v and counts[v] == 1]
            ball = ball_axes(self.contacts[i], rot_axes)
            per_chain.append((columns, np.array(own, dtype=int), ball))
        generic = self.generic_configurations()
        states = [self.kinematics.compute(q) for q in generic]
        vacuous = vacuous_joints(per_chain, states, self.axes, self.coupled_v, self.passive_v)
        if vacuous:
            self.vacuous_v = tuple(sorted(vacuous))
            self.coupled_v = [v for v in self.coupled_v if v not in vacuous]
            per_chain = [
                (cols, np.array([j for j in own if int(cols[j]) not in vacuous], dtype=int), ball)
                for cols, own, ball in per_chain
            ]
        ranks = [self._rank(states, i, cols, ball) for i, (cols, _, ball) in enumerate(per_chain)]
        keys: dict[tuple, list[int]] = {}
        for i, (columns, own, ball) in enumerate(per_chain):
            keys.setdefault((len(columns), len(own), tuple(ball), ranks[i]), []).append(i)
        self.groups: list[ChainGroup] = []
        for (k, _, ball, rank), members in keys.items():
            own = np.array([per_chain[i][1] for i in members], dtype=int).reshape(len(members), -1)
            columns = np.array([per_chain[i][0] for i in members], dtype=int).reshape(-1, k)
            signs = np.array([self.kinematics.chain_signs[i] for i in members], float)
            group = ChainGroup(
                chains=np.array(members, dtype=int),
                columns=columns,
                signs=signs.reshape(-1, k),
                constrained=own,
                ball_axes=np.array(ball, dtype=int),
                rank=rank,
                n=self.n,
            )
            self.groups.append(group)
        specs = [(v, *s[1:]) for v, s in self.passive_v.items()]
        kinds = enumerate((int, float, float, int, int))
        self._springs = tuple(np.array([r[k] for r in specs], dtype=t) for k, t in kinds)
        rows = self.evaluate(generic[0], check_singular=False).groups
        check_natural_rows(self.groups, rows, self.reactions, self.joint_name)

    def _rank(
        self, states: list[KinematicState], chain: int, columns: np.ndarray, ball: np.ndarray
    ) -> int:
        """A chain's generic rank: of ``[J_i, ball_i]``, singular values over ``SINGULAR_TOL``."""
        jacobians = [s.jacobian_o[:, columns] * self.kinematics.chain_signs[chain] for s in states]
        balls = [self._ball_columns(s.offsets_o()[chain : chain + 1], ball)[0] for s in states]
        s = np.linalg.svd(np.concatenate((jacobians, balls), axis=2), compute_uv=False)
        return int((s > SINGULAR_TOL * s[:, :1]).sum(axis=1).max())

    def _ball_columns(self, offsets_o: np.ndarray, ball: np.ndarray) -> np.ndarray:
        """``(g, n, len(ball))`` twists of {B} for rotations about {O}'s axes at each {A_i}.

        Column ``k``: linear part ``e_k x d``, angular part ``e_k``, ``d`` from {A} to {B} in {O}.
        """
        key = tuple(ball)
        maps = self._ball_maps.get(key)
        if maps is None:
            basis = np.zeros((3, 6, 3))  # d_j -> twist rows x ball axes
            basis[:, :3, :] = -skew(np.eye(3))  # -skew(e_j) for each j
            constant = np.eye(6, 3, k=-3)  # angular part e_k
            rows = self.kinematics.rows
            linear = basis[:, rows][:, :, ball].reshape(3, -1)
            maps = self._ball_maps[key] = (linear, constant[rows][:, ball].ravel())
        linear, constant = maps
        return (offsets_o @ linear + constant).reshape(offsets_o.shape[0], self.n, len(ball))

    def generic_configurations(self, count: int = 3, seed: int = 7) -> list[np.ndarray]:
        """Random valid configurations used to find generic ranks and well-conditioned sets."""
        rng = np.random.default_rng(seed)
        model = self.model
        lower, upper = model.lowerPositionLimit, model.upperPositionLimit
        finite = (np.abs(lower) < 1e3) & (np.abs(upper) < 1e3) & (upper > lower)
        low, high = np.where(finite, lower, 0.0), np.where(finite, upper, 0.0)
        out = []
        for _ in range(count):
            q = pin.integrate(model, pin.neutral(model), rng.uniform(-0.8, 0.8, model.nv))
            inside = low + (high - low) * rng.uniform(0.2, 0.8, model.nq)
            out.append(pin.normalize(model, np.where(finite, inside, q)))
        return out

    def joint_name(self, v: int) -> str:
        """Name of the joint that owns velocity index ``v``."""
        return self.model.names[int(self.kinematics.tree.joint_tables.velocity_joint[v])]

    def _build_design(self, design: Sequence[DesignConstraint]) -> None:
        rows = design_rows(design, self.kinematics, self.reactions, self.axes)
        self.constant_rows, self.constant_rhs, self.torque_pairs = rows[:3]
        coupled_names = [f"torque of shared joint {self.joint_name(v)!r}" for v in self.coupled_v]
        self.hard_names = coupled_names + rows.constant_names + rows.torque_names
        self.num_hard = len(self.hard_names)
        #: True when no hard row depends on the configuration
        self.constant_hard = not self.coupled_v and not len(self.torque_pairs)
        self.check_counts(np.zeros(self.n, dtype=bool))
        if self.num_hard:
            ev = self.evaluate(self.generic_configurations()[1], check_singular=False)
            check_hard_rows(*self.exact_rows(ev), self.hard_names)

    def evaluate(self, state: np.ndarray | Snapshot, check_singular: bool = True) -> Evaluation:
        """Evaluate the natural, coupling and design rows at a snapshot (or a configuration).

        Args:
            state: A [`Snapshot`][] of the robot, or ``q``.
            check_singular: Raise when a chain's full Jacobian loses rank.

        Raises:
            SingularConfigurationError: A chain's Jacobian is singular at ``q``.
            InvalidInputError: A bad ``q`` or a snapshot of another robot.
        """
        state = self.kinematics.compute(state)
        q = state.snapshot.q
        jac = state.jacobian_o
        offsets = state.offsets_o()
        passive = np.zeros(self.model.nv)
        if self.passive_v:
            v, stiffness, rest, idx_q, continuous = self._springs
            angle = np.where(continuous, np.arctan2(q[idx_q + continuous], q[idx_q]), q[idx_q])
            passive[v] = -stiffness * (angle - rest)
        groups = [
            self._group_rows(group, jac, offsets, passive, check_singular) for group in self.groups
        ]
        hard_rows, hard_rhs = self._hard_rows(jac, passive)
        return Evaluation(state, groups, hard_rows, hard_rhs, passive)

    def _group_rows(
        self,
        group: ChainGroup,
        jac: np.ndarray,
        offsets: np.ndarray,
        passive: np.ndarray,
        check_singular: bool,
    ) -> GroupRows:
        """One group's natural rows and right-hand sides (eq. 11) at a configuration."""
        jacobians = jac[:, group.columns].transpose(1, 0, 2) * group.signs[:, None, :]
        balls = self._ball_columns(offsets[group.chains], group.ball_axes)
        full = np.concatenate((jacobians, balls), axis=2)
        chain_index = np.arange(group.size)[:, None]
        blocks = [
            jacobians.transpose(0, 2, 1)[chain_index, group.constrained],
            balls.transpose(0, 2, 1),
        ]
        null_dim = self.n - group.rank
        ratio = None
        if null_dim or (check_singular and full.shape[2] != group.rank):
            u, s, _ = np.linalg.svd(full, full_matrices=True)
            if group.rank:
                needed = s[:, group.rank - 1]
                ratio = needed / np.maximum(s[:, 0], TINY)
                ratio[needed <= JACOBIAN_FLOOR] = 0.0  # produces nothing: absolute floor
        elif check_singular and group.rank:
            # square, full rank: Hadamard ratio |det| / prod(column norms) is 0 iff singular
            norms = np.sqrt(np.einsum("gnk,gnk->gk", full, full))
            ratio = np.abs(np.linalg.det(full)) / np.maximum(norms.prod(axis=1), TINY)
            # a column below the floor produces nothing (absolute floor)
            ratio[norms.min(axis=1) <= JACOBIAN_FLOOR] = 0.0
        if check_singular and ratio is not None and np.any(ratio < SINGULAR_TOL):
            chain = int(group.chains[int(np.argmin(ratio))])
            raise SingularConfigurationError(
                f"The chain from {self.reactions[chain]!r} to the action frame is "
                f"singular at this configuration (its Jacobian loses rank: ratio "
                f"{float(ratio.min()):.2e}), e.g. a straight knee; the distribution is "
                "not determined. Bend the chain or change the axes."
            )
        if null_dim:
            blocks.append(u[:, :, group.rank :].transpose(0, 2, 1))
        rows = np.concatenate(blocks, axis=1)
        rhs = np.zeros(rows.shape[:2])
        c = group.constrained.shape[1]
        if c:
            rhs[:, :c] = passive[group.columns[chain_index, group.constrained]]
        return GroupRows(rows=rows, rhs=rhs)

    def _hard_rows(self, jac: np.ndarray, passive: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(s, p, n)`` coupling and design rows over the chains' forces, and their rhs."""

        def torque(v: Sequence[int] | np.ndarray) -> np.ndarray:  # each joint's torque row
            return np.einsum("ps,ns->spn", self.signs[:, v], jac[:, v])

        hard_rows, hard_rhs = [self.constant_rows], [self.constant_rhs]
        if self.coupled_v:
            hard_rows.insert(0, torque(self.coupled_v))
            hard_rhs.insert(0, passive[self.coupled_v])
        if len(self.torque_pairs):
            hard_rows.append(torque(self.torque_pairs[:, 0]) - torque(self.torque_pairs[:, 1]))
            hard_rhs.append(np.zeros(len(self.torque_pairs)))
        return np.concatenate(hard_rows, axis=0), np.concatenate(hard_rhs)

    def sum_rows(self, keep: np.ndarray) -> np.ndarray:
        """``(k, p n)``: the rows summing the chains' forces on the prescribed axes ``keep``."""
        key = keep.tobytes()
        if key not in self._sum_rows:  # the sets of axes recur tick after tick
            self._sum_rows[key] = np.tile(np.eye(self.n), (1, self.p))[keep]
        return self._sum_rows[key]

    def block_natural(self, ev: Evaluation) -> tuple[np.ndarray, np.ndarray]:
        """Dense block-diagonal natural-constraint matrix over all ``p n`` force entries."""
        total = sum(g.size * g.num_constraints for g in self.groups)
        matrix = np.zeros((total, self.p * self.n))
        rhs = np.zeros(total)
        row = 0
        for group, rows in zip(self.groups, ev.groups, strict=True):
            l_ = group.num_constraints
            for j, chain in enumerate(group.chains):
                matrix[row : row + l_, chain * self.n : (chain + 1) * self.n] = rows.rows[j]
                rhs[row : row + l_] = rows.rhs[j]
                row += l_
        return matrix, rhs

    def exact_rows(self, ev: Evaluation) -> tuple[np.ndarray, np.ndarray]:
        """Every exact row over all ``p n`` force entries: the natural, then the hard rows."""
        natural, natural_rhs = self.block_natural(ev)
        hard = ev.hard_rows.reshape(-1, self.p * self.n)
        return np.vstack((natural, hard)), np.concatenate((natural_rhs, ev.hard_rhs))

    def forces(self, bases: list[np.ndarray], y: np.ndarray, offset: np.ndarray) -> np.ndarray:
        """``(p, n)`` forces ``F_i = offset_i + B_i y_i``: ``bases`` per group ``(g, n, d)``."""
        forces = offset.copy()
        start = 0
        for group, basis in zip(self.groups, bases, strict=True):
            g, d = group.size, group.num_free
            local = y[start : start + g * d].reshape(g, d)
            forces[group.chains] += np.einsum("gnd,gd->gn", basis, local)
            start += g * d
        return forces

    def torques(self, jacobian_o: np.ndarray, forces: np.ndarray) -> np.ndarray:
        """Total joint torques ``sum_i J_i^T F_i`` of a distribution ``forces`` ``(p, n)``.

        Args:
            jacobian_o: ``(n, nv)`` from `KinematicState.jacobian_o`.
            forces: ``(p, n)`` chain wrenches.
        """
        tau = np.zeros(self.model.nv)
        for group in self.groups:
            # (g, k): sign * J[:, column] . F_chain, scattered onto the columns
            jac = jacobian_o[:, group.columns]  # (n, g, k)
            share = np.einsum("ngk,gn->gk", jac, forces[group.chains]) * group.signs
            tau += np.bincount(group.columns.ravel(), share.ravel(), minlength=self.model.nv)
        return tau

    def structurally_singular(self, keep: np.ndarray) -> bool:
        """Whether the square system is singular at every (random) configuration for ``keep``.

        E.g. two point feet and a moment about the line between them: least squares then.

        Args:
            keep: ``(n,)`` bool, the prescribed (not free) axes.
        """
        key = keep.tobytes()
        cached = self.structural.get(key)
        if cached is None:
            cached = True
            for q in self.generic_configurations():
                ev = self.evaluate(q, check_singular=False)
                k = np.vstack((self.sum_rows(keep), self.exact_rows(ev)[0]))
                if k.shape[0] == k.shape[1] and np.linalg.matrix_rank(k) == k.shape[0]:
                    cached = False
                    break
            self.structural[key] = cached
        return cached

    def check_counts(self, keep: np.ndarray) -> None:
        """Raise if there are more design/coupling constraints than redundancies for ``keep``.

        Raises:
            ConstraintError: ``s > sum(d) - (number of prescribed axes)``.
        """
        m = sum(g.size * g.num_free for g in self.groups)
        k, s = int(keep.sum()), self.num_hard
        if s and s > m - k:
            names = [a for a, kept in zip(self.axes, keep, strict=True) if kept]
            prescribed = f" minus the {k} prescribed axes {names}" if k else ""
            raise ConstraintError(
                f"Too many constraints: {s} design/coupling constraints but only {m - k} "
                f"redundancies (sum of d over the chains = {m}{prescribed}). Remove "
                f"{s - (m - k)}{' or leave more axes free' if k else ''}."
            )
