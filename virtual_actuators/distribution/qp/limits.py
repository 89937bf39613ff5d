"""The inequalities of the QP distribution, declared once (see :mod:`.qp`).

:class:`ContactLimits` checks and stores the friction pyramid, least normal force, soles and
torque limits of a parallel actuator, names every inequality row, and builds the rows with numpy
over all ``p n`` force entries (the reference path); :mod:`.compiled` reads its tables.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ...contacts import Constraint, TorqueLimits, flat, point
from ...contacts.constraint import Entries
from ...contacts.declare import parse_normals
from ...vocabulary.axes import AXES
from ..problem import DistributionProblem
from ..tolerances import INFINITY


class ContactLimits:
    """The inequalities of a parallel actuator's QP, declared once.

    Args:
        problem: The distribution problem.
        friction: Friction coefficient ``mu`` of every contact, or None for no cone.
        min_normal: Least normal force of every contact [N].
        normals: Contact normal per reaction frame: a world-frame vector (fixed), or
            ``"frame"`` for the reaction frame's own z axis in the world, read every tick (a
            flat foot lying on the ground); ``"frames"`` for that at every reaction. Default:
            world z.
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
        normals: Mapping[str, Sequence[float] | str] | str | None,
        soles: Mapping[str, Sequence[float]] | None,
        torque_limits: bool | Sequence[float] | np.ndarray,
    ) -> None:
        self.problem = problem
        self.friction = friction
        self.min_normal = float(min_normal)
        self.normals_world, self.frame_normals = parse_normals(normals, problem.reactions)
        self.soles = flat.parse_soles(soles, problem.reactions, problem.contacts)
        on_chain = np.zeros(problem.model.nv, dtype=bool)
        for columns in problem.kinematics.chain_columns:
            on_chain[columns] = True
        self.torque_limits = TorqueLimits(
            problem.model, torque_limits, on_chain, problem.actuated_mask
        )
        self.limited_v = self.torque_limits.limited_v
        self.limits = self.torque_limits.limits
        axes = problem.axes
        self.force_axes = [axes.index(a) for a in AXES[:3] if a in axes]
        self.force_components = [AXES.index(a) for a in AXES[:3] if a in axes]
        self.moment_axes = [axes.index(a) for a in AXES[3:] if a in axes]
        self.moment_components = [AXES.index(a) - 3 for a in AXES[3:] if a in axes]
        self.names = problem.reactions
        #: rows of the cone (normal bound, friction faces) when the actuator has force axes
        self._cone = bool(self.force_axes) and (
            self.friction is not None or self.min_normal > 0.0 or bool(self.soles)
        )
        #: the normal row ``n . f >= min_normal``; with a pyramid and no least normal force it is
        #: implied by the faces (``(mu n - t) + (mu n + t) = 2 mu n``) and left out
        self.normal_row = self._cone and (self.friction is None or self.min_normal > 0.0)
        # the cone's scatter into (chain, face, p n) and its bounds depend on the declaration only
        faces = point.faces(self.friction, self.normal_row)
        chains = np.arange(problem.p)[:, None, None]
        self._cone_index = (
            chains,
            np.arange(faces)[None, :, None],
            chains * problem.n + np.asarray(self.force_axes, dtype=int)[None, None, :],
        )
        self._cone_lows = np.tile(
            [self.min_normal] * self.normal_row + [0.0] * (faces - self.normal_row), problem.p
        )
        #: the declaration's tables for the compiled path
        self.tables = {
            "normals_world": self.normals_world,
            "frame_normals": self.frame_normals.astype(np.int64),
            "cone": np.array(
                [-1.0 if friction is None else friction, self.min_normal, self.normal_row]
            ),
            "soles": flat.table(self.soles, problem.p),
            "limited_v": self.limited_v,
            "limits": self.limits,
        }
        self._row_names = self._names()

    def row_names(self) -> list[str]:
        """The inequality rows' names, in the order both paths build the rows."""
        return self._row_names

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
                names += point.names(reaction, self.friction, self.min_normal, self.normal_row)
        if self.moment_axes:
            for i, sole in self.soles.items():
                names += flat.names(self.names[i], sole, self.friction)
        return names + self.torque_limits.names(self.problem.joint_name)

    def rows(
        self, state: object, torque_map: np.ndarray
    ) -> Constraint:
        """``lows <= G x <= uppers`` over ``x = forces.ravel()``, with a name per row.

        Args:
            state: The tick's kinematic state (rotations, offsets, Jacobian rows in {O}).
            torque_map: ``(nv, p n)`` joint torques of ``x``.

        """
        p, n = self.problem.p, self.problem.n
        blocks: list[np.ndarray] = []
        lows: list[np.ndarray] = []
        rotation_o = state.rotation_o
        normals_world = self.normals_world_at(state)
        normals_o = normals_world @ rotation_o  # rows: R_O^T n, per chain
        if self._cone:
            # the pyramid is the contact's: tangents fixed in the world, then turned into {O}
            stacked = point.pyramid(
                normals_world, normals_o, rotation_o, self.friction, self.normal_row
            )  # (p, faces, 3)
            cone = np.zeros((p, stacked.shape[1], p * n))
            cone[self._cone_index] = stacked[:, :, self.force_components]
            blocks.append(cone.reshape(-1, p * n))
            lows.append(self._cone_lows)
        if self.soles and self.moment_axes:
            offsets = state.offsets_o()  # (p, 3): from {A_i} to {B} in {O}
            for i, sole in self.soles.items():
                # the reaction frame's axes in {O}: columns, its x, y, z
                frame_o = rotation_o.T @ state.rotation_a[i]
                sole_rows = flat.rows(sole, self.friction, frame_o, offsets[i], self._entries(i))
                blocks.append(sole_rows)
                lows.append(np.zeros(len(sole_rows)))
        one_sided = sum(len(low) for low in lows)
        if self.limited_v.size:
            rows, low, upper = self.torque_limits.rows(torque_map)  # two-sided
            blocks.append(rows)
            lows.append(low)
        if not blocks:
            return Constraint.empty(p * n)
        low = np.concatenate(lows)
        upper = np.full(len(low), INFINITY)
        upper[one_sided:] = self.limits
        return Constraint(np.vstack(blocks), low, upper, self._row_names)

    def normals_world_at(self, state: object) -> np.ndarray:
        """``(p, 3)`` the contact normals in the world at this tick (frames' z axes read)."""
        if not self.frame_normals.any():
            return self.normals_world
        normals = self.normals_world.copy()
        normals[self.frame_normals] = state.rotation_a[self.frame_normals, :, 2]
        return normals

    def _entries(self, i: int) -> Entries:
        """Where contact ``i``'s force and moment entries sit in ``x = forces.ravel()``."""
        n = self.problem.n
        force = i * n + np.array(self.force_axes)
        moment = i * n + np.array(self.moment_axes)
        width = self.problem.p * n
        return Entries(force, moment, self.force_components, self.moment_components, width)


def kinds(names: Sequence[str]) -> list[str]:
    """The kinds of inequality among row names: friction, normal, moment, torque."""
    words = ("friction", "normal", "moment", "torque")
    return [word for name in names for word in words if word in name] or ["none"]


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


__all__ = ["ContactLimits", "kinds", "torque_map"]
