"""Parallel virtual actuators (VAC 2.5, VMC 4): one action frame, several reaction chains."""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping, Sequence

import numpy as np

from ..contacts import declare
from ..distribution.methods import METHODS, Backend, Request, dispatch
from ..distribution.partitioned.compiled import (
    CompiledDistribution,
    ConfigurationSolve,
    SnapshotSolve,
)
from ..distribution.partitioned.numeric import DenseSolver, NumpyBackend
from ..distribution.partitioned.reference import PartitionedSolver
from ..distribution.problem import DistributionProblem
from ..distribution.problem.declaration import check_passive
from ..distribution.qp import ContactLimits, QPDistribution, check_weights
from ..distribution.result import Solution, inadmissible
from ..exceptions import InvalidInputError, JointNotFoundError, VirtualActuatorError
from ..kinematics.relative import RelativeKinematics
from ..kinematics.snapshot import Snapshot
from ..models.robot import Robot
from ..vocabulary.arguments import check_flag, check_names, check_robot, check_sequence, describe
from ..vocabulary.axes import check_axes_subset, parse_axes, resolve_frame
from ..vocabulary.constraints import DesignConstraint
from .parallel_checks import check_forces, check_free, preferred_entries, resolve_chains
from .producible import give_way, producible_directions
from .serial import check_tolerance, wrench_array

_PRESCRIBED: tuple[str, ...] = ()  # solve's default free axes (the one empty tuple of CPython)
_ARRAY = np.ndarray


class ParallelVirtualActuator:
    """One action frame {B}, several reaction frames {A_i}: a wrench distributed over chains.

    Args:
        robot: The robot.
        action: Name of the action frame {B}.
        reactions: Names of the reaction frames, one serial chain each (or one name).
        reference: Name of the reference frame {O}.
        axes: Ordered subset of ``("x", "y", "z", "rx", "ry", "rz")``, or one axis name.
        contact: ``"point"`` (no moment about a reaction frame's origin), ``"flat"`` (any
            wrench), or a dict from reaction to either.
        unactuated: Names of limp joints (torque 0), or one name.
        passive: ``{joint: (stiffness [N m/rad], rest angle [rad])}``: measured torque
            ``-stiffness * (angle - rest)``.
        design: Design constraints ([`Equal`][], [`Linear`][], [`EqualTorque`][]), or one.
        friction: ``method="qp"``: friction coefficient ``mu`` of every contact's pyramid.
        min_normal: ``method="qp"``: least normal force of every contact [N].
        torque_limits: ``method="qp"``: ``True`` for the URDF effort limits, or ``(nv,)``.
        normals: Contact normal per reaction frame: a world vector, or ``"frame"`` (the
            reaction frame's z, read every tick); ``"frames"`` for all. Default: world z.
        soles: ``method="qp"``: ``(half_length, half_width)`` [m] of flat soles, by reaction.
        weights: ``method="qp"``: per-axis weights of the closest reachable wrench (a dict by
            axis, 1 for the others, or one finite number > 0 per axis).

    Raises:
        InvalidInputError: ``robot`` is not a robot; ``reactions``, ``unactuated``, ``passive``
            or ``design`` is not a collection of the documented kind; a bad ``friction``,
            ``min_normal``, ``torque_limits``, ``normals``, ``soles`` or ``weights``.
        FrameNotFoundError: A frame name is not a str or not in the model.
        JointNotFoundError: A joint name is not a str, unknown or not on any chain.
        InvalidAxisError: Bad axes, or ``weights`` names an axis the actuator lacks.
        ConstraintError: Constraints that contradict or repeat each other or are too many; a
            reaction frame with no joint to the action frame, or repeated; a bad ``contact``;
            a ``passive`` value that is not two finite real numbers; a design entry that is not
            a design constraint.
    """

    def __init__(
        self,
        robot: Robot,
        action: str,
        reactions: Sequence[str],
        reference: str = "world",
        axes: Sequence[str] = ("x", "y", "z", "rx", "ry", "rz"),
        contact: str | Mapping[str, str] = "point",
        unactuated: Sequence[str] = (),
        passive: Mapping[str, tuple[float, float]] | None = None,
        design: Sequence[DesignConstraint] = (),
        friction: float | None = None,
        min_normal: float = 0.0,
        torque_limits: bool | Sequence[float] | np.ndarray = False,
        normals: Mapping[str, Sequence[float] | str] | str | None = None,
        soles: Mapping[str, Sequence[float]] | None = None,
        weights: Mapping[str, float] | Sequence[float] | np.ndarray | None = None,
    ) -> None:
        check_robot(robot, "ParallelVirtualActuator")
        self.robot = robot
        self.action, self.reference = action, reference
        self.reactions, action_id, reaction_ids = resolve_chains(robot, action, reactions)
        self.axes = parse_axes(axes)
        model = robot.model
        unactuated = check_names(unactuated, "unactuated", JointNotFoundError, ordered=False)
        passive = check_passive(passive)
        kinds = "design constraints (va.Equal, va.Linear, va.EqualTorque)"
        self.design = tuple(check_sequence(design, "design", kinds, single=DesignConstraint))
        self.kinematics = RelativeKinematics(
            robot, action_id, reaction_ids, resolve_frame(model, reference, "reference"), self.axes
        )
        #: the contacts as declared, read by the QP and by a controller's yield policy
        self.contacts = declare(
            self.reactions, self.axes, contact, friction, min_normal, normals, soles
        )
        self.problem = DistributionProblem(
            self.kinematics, self.reactions, self.contacts.contact, unactuated, passive, self.design
        )
        preferred = preferred_entries(self.reactions, self.axes, self.design)
        self.partitioner = PartitionedSolver(self.problem, preferred)
        self.compiled = CompiledDistribution(self.problem, self.partitioner)
        self.dense = DenseSolver(self.problem)
        self.contact_limits = ContactLimits(self.problem, self.contacts, torque_limits)
        self.qp = QPDistribution(self.problem, self.contact_limits, weights)
        self._free_sets: dict[tuple, tuple[tuple[str, ...], np.ndarray]] = {}  # by free axes
        self._floating = model.nv >= 6 and model.joints[1].shortname() == "JointModelFreeFlyer"

    @property
    def n(self) -> int:
        """Number of axes (dimension of the wrench)."""
        return len(self.axes)

    @property
    def p(self) -> int:
        """Number of chains."""
        return len(self.reactions)

    def sizes(self) -> dict[str, int]:
        """Return the seed's constants: n, p, natural constraints, free entries, redundancy r."""
        l_total = sum(g.size * g.num_constraints for g in self.problem.groups)
        d_total = self.partitioner.num_free_entries
        return {
            "n": self.n,
            "p": self.p,
            "l_total": l_total,
            "d_total": d_total,
            "r": d_total - self.n,
            "design": self.problem.num_hard,
        }

    def solve(
        self,
        q: np.ndarray | Snapshot,
        wrench: np.ndarray,
        free: Sequence[str] = (),
        strict: bool = False,
        tol: float = 1e-6,
        method: str = "partitioned",
        compiled: bool = True,
        weights: Mapping[str, float] | Sequence[float] | np.ndarray | None = None,
    ) -> Solution:
        """Distribute ``wrench`` over the chains and map it to joint efforts.

        Args:
            q: Configuration ``(model.nq,)``, or the tick's [`Snapshot`][].
            wrench: ``(n,)`` wrench on {B}; entries of ``free`` axes are ignored.
            free: Axes left to the solver, or one axis name.
            strict: Raise [`InadmissibleWrenchError`][] if the wrench cannot be produced.
            tol: Admissibility tolerance on the residual, relative to the larger of ``|wrench|``
                and ``|produced|`` on the prescribed axes.
            method: ``"partitioned"``, ``"dense"`` (eq. 10-11) or ``"qp"`` (contact inequalities).
            compiled: Use the compiled per-tick kernels when they apply (False: numpy).
            weights: ``method="qp"``: this solve's per-axis weights (None: the constructor's).

        Raises:
            InvalidInputError: Bad ``q``, ``wrench``, ``tol``, ``method`` or ``weights``, or
                ``strict`` or ``compiled`` that is not a bool.
            InvalidAxisError: ``free`` is not a collection of the actuator's axes, or
                ``weights`` names an axis it lacks.
            SingularConfigurationError: No distribution can be solved at this configuration.
            ConstraintError: Too many constraints for the free axes, or constraints that
                contradict each other here.
            InadmissibleWrenchError: With ``strict=True``, if the residual exceeds ``tol``.
        """
        if not (isinstance(tol, float) and 0.0 <= tol < math.inf):
            tol = check_tolerance(tol)
        if strict is not False and strict is not True:
            strict = check_flag(strict, "strict")
        if compiled is not True and compiled is not False:
            compiled = check_flag(compiled, "compiled")
        if (
            free is _PRESCRIBED
            and compiled
            and weights is None
            and method == "partitioned"
            and type(q) is _ARRAY
            and type(wrench) is _ARRAY
        ):
            configuration_solve = self._configuration_solve
            if configuration_solve is not None:
                solution = configuration_solve(q, wrench, tol)
                if solution is not None:
                    if strict and not solution.admissible:
                        raise inadmissible(wrench, self.axes, solution)
                    return solution
        return self._solve_planned(q, wrench, free, strict, tol, method, compiled, weights)

    def _solve_planned(
        self,
        q: np.ndarray | Snapshot,
        wrench: np.ndarray,
        free: Sequence[str],
        strict: bool,
        tol: float,
        method: str,
        compiled: bool,
        weights: Mapping[str, float] | Sequence[float] | np.ndarray | None,
    ) -> Solution:
        """[`solve`][] past its one-call path (``strict``, ``tol``, ``compiled`` checked)."""
        plain, kinematics = not isinstance(q, Snapshot), self.kinematics
        state = kinematics.tree.check_configuration(q) if plain else kinematics.snapshot(q)
        wrench = wrench_array(wrench, self.axes)
        request = self.plan(free, method, compiled, weights)
        tick = None
        if plain:
            solver = self.qp if request.method == "qp" else self.compiled
            tick = solver.solve_configuration(state, wrench, request)
        if tick is None:
            snapshot = Snapshot(self.robot, state) if plain else state
            tick = dispatch(self.backends, snapshot, wrench, request)
        solution = Solution.from_tick(
            tick, tol, self.reactions, self.axes, request.free, self._floating
        )
        if strict and not solution.admissible:
            raise inadmissible(wrench, self.axes, solution)
        return solution

    @functools.cached_property
    def _configuration_solve(self) -> ConfigurationSolve | None:
        """The default request's one-call solve from ``q`` (None: no core, or no such solve)."""
        try:
            request = self.plan()
        except VirtualActuatorError:  # too many constraints: the general path raises it
            return None
        if self.kinematics.tree.core_tree is None:
            return None
        return self.compiled.buffer_solve(
            ConfigurationSolve, request, self.reactions, self.axes, self._floating
        )

    def solve_checked(
        self, snapshot: Snapshot, wrench: np.ndarray, request: Request, tol: float = 1e-6
    ) -> tuple[Solution, bool]:
        """``(solution, missed)`` of [`solve`][] on arguments checked already (per tick).

        ``missed``: the residual exceeds ``tol``.

        Raises:
            SingularConfigurationError: No distribution can be solved at this configuration.
            ConstraintError: Constraints that contradict each other here.
        """
        tick = dispatch(self.backends, snapshot, wrench, request)
        solution = Solution.from_tick(
            tick, tol, self.reactions, self.axes, request.free, self._floating
        )
        return solution, not solution.admissible

    def snapshot_solve(self, request: Request) -> SnapshotSolve | None:
        """A checked request's one-call solve on a snapshot (then [`solve_checked`][] if None).

        None without a compiled core, or for a request not of the compiled partitioned method.
        """
        return self.compiled.buffer_solve(
            SnapshotSolve, request, self.reactions, self.axes, self._floating
        )

    def plan(
        self,
        free: Sequence[str] = (),
        method: str = "partitioned",
        compiled: bool = True,
        weights: Mapping[str, float] | Sequence[float] | np.ndarray | None = None,
    ) -> Request:
        """The checked `Request` of a solve with ``free``, ``method`` and ``weights``.

        Raises:
            InvalidAxisError: ``free`` is not a collection of the actuator's axes, or ``weights``
                names an axis it lacks.
            InvalidInputError: Unknown ``method``, or bad ``weights``.
            ConstraintError: Too many constraints for those free axes.
        """
        free, keep = check_free(free, self.axes, self.problem, self._free_sets)
        if not isinstance(method, str) or method not in METHODS:
            raise InvalidInputError(
                f"method must be one of {list(METHODS)}, got {describe(method)}."
            )
        if weights is not None:
            weights = check_weights(weights, self.axes)
        return Request(method, free, keep, compiled, weights)

    @functools.cached_property
    def backends(self) -> dict[str, Backend]:
        """The solver backends by name (`METHODS` lists each method's, in order)."""
        return {
            "compiled": self.compiled,
            "reference": NumpyBackend(self.problem, self.partitioner, hand_on=True),
            "dense": NumpyBackend(self.problem, self.dense),
            "qp": self.qp,
        }

    @property
    def methods(self) -> tuple[str, ...]:
        """The names ``solve(method=...)`` accepts (the first is the default)."""
        return tuple(METHODS)

    def producible(self, q: np.ndarray | Snapshot) -> np.ndarray:
        """``(n, r)`` orthonormal basis of the wrenches producible at ``q`` (``r == n``: all).

        Raises:
            InvalidInputError: A bad ``q`` or a snapshot of another robot.
        """
        return producible_directions(self.kinematics, self.problem, q).producible

    def give_way(
        self, q: np.ndarray | Snapshot, wrench: np.ndarray, axes: Sequence[str] = ("x", "y")
    ) -> np.ndarray:
        """``wrench`` made producible at ``q`` by moving it along ``axes`` only (`give_way`).

        Raises:
            InvalidAxisError: ``axes`` not among the actuator's axes.
            InvalidInputError: A bad ``q`` or ``wrench``.
        """
        chosen = check_axes_subset(axes, self.axes, "give way axes")
        wrench = wrench_array(wrench, self.axes)
        directions = producible_directions(self.kinematics, self.problem, q)
        yielding = np.eye(self.n)[:, [self.axes.index(a) for a in chosen]]
        return give_way(directions.producible, wrench, yielding, directions.missing)

    def torques(self, q: np.ndarray | Snapshot, forces: np.ndarray) -> np.ndarray:
        """Joint torques ``sum_i J_i^T F_i`` of a given distribution ``forces`` ``(p, n)``.

        Raises:
            InvalidInputError: Bad ``q``, or ``forces`` that are not ``(p, n)`` finite real
                numbers.
        """
        forces = check_forces(forces, self.p, self.n)
        return self.problem.torques(self.kinematics.compute(q).jacobian_o, forces)

    def __repr__(self) -> str:
        return (
            f"ParallelVirtualActuator(action={self.action!r}, reactions={list(self.reactions)}, "
            f"reference={self.reference!r}, axes={self.axes}, design={len(self.design)})"
        )
