"""Virtual actuators: serial (VAC 2.1-2.4) and parallel (VAC 2.5, VMC 4).

A virtual actuator exerts a wrench on an action frame {B} from a reaction frame {A} (minus that
wrench acts on {A}), expressed in a reference frame {O}. The joint torques that emulate it are
``tau = J^T F`` (VAC eq. 5-7). A parallel actuator has one action frame and several reaction
frames, one serial chain each, and must distribute its wrench over the chains.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..declaration.constraints import DesignConstraint, Equal, Linear
from ..declaration.frames import (
    as_float_array,
    check_axes_subset,
    check_flag,
    check_name,
    check_names,
    check_number,
    check_robot,
    check_sequence,
    describe,
    parse_axes,
    resolve_frame,
)
from ..distribution.compiled import CompiledDistribution
from ..distribution.dense import DenseSolver
from ..distribution.linalg import JACOBIAN_FLOOR, stable_norm
from ..distribution.numeric import solve_numpy
from ..distribution.partitioner import PartitionedSolver
from ..distribution.problem import DistributionProblem
from ..distribution.solution import Solution
from ..exceptions import (
    ConstraintError,
    FrameNotFoundError,
    InadmissibleWrenchError,
    InvalidAxisError,
    InvalidInputError,
    JointNotFoundError,
)
from ..kinematics.relative import RelativeKinematics
from ..kinematics.snapshot import Snapshot
from ..robots.robot import Robot


def _wrench_array(wrench: np.ndarray, axes: Sequence[str]) -> np.ndarray:
    if not (isinstance(wrench, np.ndarray) and wrench.dtype == np.float64):  # slow path only
        wrench = as_float_array(
            wrench, "wrench", f"an array of {len(axes)} real numbers (axes {tuple(axes)})"
        )
    if wrench.shape != (len(axes),):
        raise InvalidInputError(
            f"The wrench has shape {wrench.shape}; this actuator's axes {tuple(axes)} need "
            f"({len(axes)},)."
        )
    if not np.isfinite(wrench).all():  # (no squares: no overflow at 1e200)
        raise InvalidInputError(f"The wrench has NaN or inf entries: {wrench}.")
    return wrench


def _tolerance(tol: object) -> float:
    """``tol`` checked: a finite real number >= 0 (the caller skips plain floats in range)."""
    return check_number(tol, "tol (the admissibility tolerance)", minimum=0.0)


def _check_contact(contact: object) -> str | dict[str, object]:
    """``contact`` as ``"point"``, ``"flat"`` or a dict keyed by reaction names (str)."""
    if isinstance(contact, str):
        return contact
    if not isinstance(contact, Mapping):
        raise ConstraintError(
            "contact must be 'point', 'flat' or a dict {reaction_frame: 'point' | 'flat'}, "
            f"got {describe(contact)}."
        )
    for name in contact:
        check_name(name, "contact: a key (a reaction frame name)", ConstraintError)
    return dict(contact)


def _check_passive(passive: object) -> dict[str, tuple[float, float]]:
    """``passive`` as ``{joint: (stiffness, rest)}`` with two finite real numbers per joint."""
    if passive is None:
        return {}
    if not isinstance(passive, Mapping):
        raise InvalidInputError(
            "passive must be a dict {joint_name: (stiffness [N m/rad], rest angle [rad])}, got "
            f"{describe(passive)}."
        )
    out: dict[str, tuple[float, float]] = {}
    for name, params in passive.items():
        check_name(name, "passive: a key (a joint name)", JointNotFoundError)
        what = f"passive[{name!r}]"
        if isinstance(params, (str, bytes, Mapping)) or not isinstance(params, Iterable):
            params = (params,)  # reported below as a wrong number of values
        params = tuple(params)
        if len(params) != 2:
            raise ConstraintError(
                f"{what} must be (stiffness, rest_angle), two real numbers, got {params!r}."
            )
        stiffness, rest = (
            check_number(x, f"{what}: {label}", error=ConstraintError)
            for x, label in zip(params, ("stiffness", "rest angle"), strict=True)
        )
        out[name] = (stiffness, rest)
    return out


@dataclass(frozen=True, repr=False)
class SensorReading:
    """One reading of a serial actuator's virtual sensor.

    Attributes:
        position: Pose of {B} relative to {A} in {O} on the actuator's axes [m, rad].
        velocity: Its rate ``jacobian @ v`` [m/s, rad/s].
        jacobian: ``(len(axes), nv)`` Jacobian.

    """

    position: np.ndarray
    velocity: np.ndarray
    jacobian: np.ndarray

    def __repr__(self) -> str:
        return f"SensorReading(position={self.position}, velocity={self.velocity})"


class VirtualActuator:
    """A serial virtual actuator between an action frame {B} and a reaction frame {A}.

    Args:
        robot: The robot.
        action: Name of the action frame {B} (the wrench acts on it).
        reaction: Name of the reaction frame {A} (minus the wrench acts on it), or ``"world"``.
        reference: Name of the reference frame {O} whose axes the wrench is expressed along.
        axes: Ordered subset of ``("x", "y", "z", "rx", "ry", "rz")``, or one axis name.

    Raises:
        InvalidInputError: ``robot`` is not a robot (e.g. None or a robot's name).
        FrameNotFoundError: A frame name is not a str or not in the model.
        ConstraintError: The action and reaction frames are the same frame.
        InvalidAxisError: Bad axes.

    """

    def __init__(
        self,
        robot: Robot,
        action: str,
        reaction: str,
        reference: str = "world",
        axes: Sequence[str] = ("x", "y", "z", "rx", "ry", "rz"),
    ) -> None:
        check_robot(robot, "VirtualActuator")
        self.robot = robot
        self.action, self.reaction, self.reference = action, reaction, reference
        self.axes = parse_axes(axes)
        model = robot.model
        action_id = resolve_frame(model, action, "action")
        reaction_id = resolve_frame(model, reaction, "reaction")
        if action_id == reaction_id:
            same = repr(action) if action == reaction else f"{action!r} (= {reaction!r})"
            raise ConstraintError(
                f"The action frame {same} is also the reaction frame; a virtual actuator acts "
                "between two different frames."
            )
        self.kinematics = RelativeKinematics(
            robot,
            action_id,
            [reaction_id],
            resolve_frame(model, reference, "reference"),
            self.axes,
        )

    def read(self, state: np.ndarray | Snapshot, v: np.ndarray | None = None) -> SensorReading:
        """Read the virtual sensor: position, velocity and Jacobian from one kinematics pass.

        Args:
            state: A :class:`~virtual_actuators.Snapshot` built with a velocity (the tick's
                shared kinematics), or a configuration ``(nq,)``.
            v: Velocity ``(nv,)`` when ``state`` is a configuration.

        Returns:
            The :class:`SensorReading`.

        Raises:
            InvalidInputError: Bad ``q`` or ``v``, no velocity given, or a snapshot of another
                robot.

        """
        if not isinstance(state, Snapshot):
            if v is None:
                raise InvalidInputError("read(q, v) needs a velocity v (or a Snapshot with v).")
            state = Snapshot(self.robot, state, v)
        jacobian, position, velocity = self.kinematics.sense(state, velocity=True)
        return SensorReading(position=position, velocity=velocity, jacobian=jacobian)

    def position(self, state: np.ndarray | Snapshot) -> np.ndarray:
        """Virtual sensor: pose of {B} relative to {A} in {O}, on the selected axes.

        Translations: ``R_O^T (p_B - p_A)`` [m]. Rotations: the rotation vector of {B} relative
        to {A}, ``log(R_A^T R_B)``, expressed in {O} [rad].

        Args:
            state: A :class:`~virtual_actuators.Snapshot` or a configuration ``(nq,)``.

        Raises:
            InvalidInputError: Bad ``q``, or a snapshot of another robot.

        """
        return self.kinematics.sense(state)[1]

    def jacobian(self, state: np.ndarray | Snapshot) -> np.ndarray:
        """``(len(axes), nv)``: twist of {B} relative to {A} at {B}'s origin, in {O}.

        Columns of joints outside the path between {A} and {B} are zero (a floating base
        cancels unless one frame is ``"world"``).

        Args:
            state: A :class:`~virtual_actuators.Snapshot` or a configuration ``(nq,)``.

        Raises:
            InvalidInputError: Bad ``q``, or a snapshot of another robot.

        """
        return self.kinematics.sense(state)[0]

    def velocity(self, state: np.ndarray | Snapshot, v: np.ndarray | None = None) -> np.ndarray:
        """Virtual sensor: ``jacobian(q) @ v`` [m/s, rad/s].

        Args:
            state: A :class:`~virtual_actuators.Snapshot` built with ``v``, or ``q``.
            v: Velocity ``(nv,)`` when ``state`` is a configuration.

        Raises:
            InvalidInputError: Bad ``q`` or ``v``, or no velocity given.

        """
        if isinstance(state, Snapshot):
            snapshot = self.kinematics.snapshot(state, need_velocity=True)
            return self.jacobian(snapshot) @ snapshot.v
        if v is None:
            raise InvalidInputError("velocity(q, v) needs a velocity v.")
        v = self.kinematics.check_velocity(v)
        return self.jacobian(state) @ v

    def torques(self, state: np.ndarray | Snapshot, wrench: np.ndarray) -> np.ndarray:
        """Joint torques ``J^T F`` that emulate ``wrench`` on {B} from {A} (VAC eq. 7).

        Raises:
            InvalidInputError: Bad ``q``, or a ``wrench`` that is not ``len(axes)`` finite real
                numbers (complex or bool entries included).

        """
        wrench = _wrench_array(wrench, self.axes)
        return self.jacobian(state).T @ wrench

    def is_admissible(
        self, q: np.ndarray | Snapshot, wrench: np.ndarray, tol: float = 1e-9
    ) -> bool:
        """Whether ``wrench`` lies in the range of the Jacobian (it can be produced).

        Args:
            q: Configuration.
            wrench: Wrench over ``axes``.
            tol: Tolerance on the part of ``wrench`` outside the range, relative to ``|wrench|``
                (scale-free: a zero wrench is admissible); a finite number >= 0.

        Raises:
            InvalidInputError: Bad ``q``, ``wrench`` or ``tol``.

        """
        if not (isinstance(tol, float) and 0.0 <= tol < math.inf):
            tol = _tolerance(tol)
        wrench = _wrench_array(wrench, self.axes)
        jac = self.jacobian(q)
        u, s, _ = np.linalg.svd(jac, full_matrices=False)
        # relative rank, with an absolute floor: a direction produced by J < 1e-12 is not
        rank = int(np.sum(s > max(1e-10 * s[0], JACOBIAN_FLOOR))) if s.size else 0
        inside = u[:, :rank] @ (u[:, :rank].T @ wrench)
        return stable_norm(wrench - inside) <= tol * stable_norm(wrench)

    def __repr__(self) -> str:
        return (
            f"VirtualActuator(action={self.action!r}, reaction={self.reaction!r}, "
            f"reference={self.reference!r}, axes={self.axes})"
        )


class ParallelVirtualActuator:
    """One action frame {B}, several reaction frames {A_i}: a wrench distributed over chains.

    Args:
        robot: The robot.
        action: Name of the action frame {B}.
        reactions: Names of the reaction frames, one serial chain each (a list or tuple; one
            name for a single chain).
        reference: Name of the reference frame {O}.
        axes: Ordered subset of ``("x", "y", "z", "rx", "ry", "rz")``, or one axis name.
        contact: ``"point"`` (no moment about a reaction frame's origin on the selected
            rotational axes), ``"flat"`` (any wrench), or a dict from reaction to either.
        unactuated: Names of limp joints (torque 0), or one name.
        passive: ``{joint: (stiffness [N m/rad], rest angle [rad])}``: torque
            ``-stiffness * (angle - rest)``, measured, not commanded; None for none.
        design: Design constraints (:class:`Equal`, :class:`Linear`, :class:`EqualTorque`), or
            one constraint.

    Raises:
        InvalidInputError: ``robot`` is not a robot; ``reactions``, ``unactuated``,
            ``passive`` or ``design`` is not a collection of the documented kind (e.g. None,
            a number, or ``passive`` given as a list).
        FrameNotFoundError: A frame name is not a str or not in the model.
        JointNotFoundError: A joint name is not a str, unknown or not on any chain.
        InvalidAxisError: Bad axes.
        ConstraintError: Constraints that contradict each other, repeat each other or are too
            many; a reaction frame with no joint to the action frame; a repeated reaction; a bad
            ``contact``; a ``passive`` value that is not two finite real numbers; a design entry
            that is not a design constraint.

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
    ) -> None:
        check_robot(robot, "ParallelVirtualActuator")
        self.robot = robot
        self.action, self.reference = action, reference
        self.reactions = check_names(reactions, "reactions", FrameNotFoundError)
        if not self.reactions:
            raise ConstraintError("A parallel virtual actuator needs at least one reaction frame.")
        if len(set(self.reactions)) != len(self.reactions):
            raise ConstraintError(f"Reaction frames repeat: {self.reactions}.")
        self.axes = parse_axes(axes)
        model = robot.model
        action_id = resolve_frame(model, action, "action")
        reaction_ids = [resolve_frame(model, r, "reaction") for r in self.reactions]
        if action_id in reaction_ids:
            raise ConstraintError(
                f"The action frame {action!r} is also a reaction frame; they must differ."
            )
        contact = _check_contact(contact)
        unactuated = check_names(unactuated, "unactuated", JointNotFoundError, ordered=False)
        passive = _check_passive(passive)
        self.design = tuple(
            check_sequence(
                design,
                "design",
                "design constraints (va.Equal, va.Linear, va.EqualTorque)",
                single=DesignConstraint,
            )
        )
        self.kinematics = RelativeKinematics(
            robot, action_id, reaction_ids, resolve_frame(model, reference, "reference"), self.axes
        )
        self.problem = DistributionProblem(
            self.kinematics, self.reactions, contact, unactuated, passive, self.design
        )
        preferred = np.ones((len(self.reactions), len(self.axes)))
        for constraint in self.design:
            if isinstance(constraint, (Equal, Linear)):
                for reaction, axis in constraint.labels():
                    preferred[self.reactions.index(reaction), self.axes.index(axis)] = 1e-3
        self.partitioner = PartitionedSolver(self.problem, preferred)
        self.compiled = CompiledDistribution(self.problem, self.partitioner)
        self.dense = DenseSolver(self.problem)
        self._keep_cache: dict[tuple, tuple[tuple[str, ...], np.ndarray]] = {}
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

    def _keep(self, free: Sequence[str]) -> tuple[tuple[str, ...], np.ndarray]:
        try:
            key = (free,) if isinstance(free, str) else tuple(free)
            cached = self._keep_cache.get(key)
        except TypeError:  # not iterable, or unhashable entries
            raise InvalidAxisError(
                f"free must be an axis name or a sequence of axis names among this actuator's "
                f"axes {self.axes}, got {describe(free)}."
            ) from None
        if cached is None:
            axes = check_axes_subset(key, self.axes, "free")
            keep = np.array([a not in axes for a in self.axes])
            self.problem.check_counts(keep)  # declaration-only: checked once per set of free axes
            cached = self._keep_cache[key] = (axes, keep)
        return cached

    def solve(
        self,
        q: np.ndarray | Snapshot,
        wrench: np.ndarray,
        free: Sequence[str] = (),
        strict: bool = False,
        tol: float = 1e-6,
        method: str = "partitioned",
        compiled: bool = True,
    ) -> Solution:
        """Distribute ``wrench`` over the chains and map it to joint efforts.

        Args:
            q: Configuration ``(model.nq,)``, or the tick's :class:`~virtual_actuators.Snapshot`
                (kinematics shared with the other actuators and sensors of the robot).
            wrench: ``(n,)`` wrench on {B}; entries of ``free`` axes are ignored.
            free: Axes left to the solver (their produced value is reported in the solution),
                or one axis name.
            strict: Raise :class:`InadmissibleWrenchError` if the wrench cannot be produced.
            tol: Admissibility tolerance on the residual, relative to the larger of ``|wrench|``
                and ``|produced|`` on the prescribed axes (scale-free: ``solve(q, s * w)`` gets
                the same label as ``solve(q, w)`` for any ``s > 0``); a finite number >= 0.
            method: ``"partitioned"`` (default) or ``"dense"`` (reference solver, eq. 10-11).
            compiled: Use the compiled per-tick kernel for the partitioned method when it
                applies (the default); False runs the numpy implementation, the reference the
                kernel is tested against. Ticks the kernel cannot decide (a near-singular
                chain, an ill-conditioned block, an inadmissible request) always go to numpy.

        Returns:
            The :class:`Solution`.

        Raises:
            InvalidInputError: Bad ``q``, ``wrench``, ``tol`` or ``method``, or ``strict`` or
                ``compiled`` that is not a bool.
            InvalidAxisError: ``free`` is not a collection of the actuator's axes.
            SingularConfigurationError: No distribution can be solved at this configuration.
            ConstraintError: Too many constraints for the free axes (more design and coupling
                constraints than redundancies), or constraints that contradict each other here.
            InadmissibleWrenchError: With ``strict=True``, if the residual exceeds ``tol``.

        """
        # cheap checks first (plain floats and bools skip the slow paths)
        if not (isinstance(tol, float) and 0.0 <= tol < math.inf):
            tol = _tolerance(tol)
        if strict is not False and strict is not True:
            strict = check_flag(strict, "strict")
        if compiled is not True and compiled is not False:
            compiled = check_flag(compiled, "compiled")
        snapshot = self.kinematics.snapshot(q)
        wrench = _wrench_array(wrench, self.axes)
        free, keep = self._keep(free)
        if method == "partitioned":
            solver = self.partitioner
        elif method == "dense":
            solver = self.dense
        else:
            raise InvalidInputError(f"method must be 'partitioned' or 'dense', got {method!r}.")
        fast = None
        if compiled and solver is self.partitioner:
            fast = self.compiled.solve(snapshot, wrench, keep)
        if fast is None:
            fast_used = False
            fallback = self.dense if solver is self.partitioner else None
            fast = solve_numpy(self.problem, solver, snapshot, wrench, keep, fallback)
        else:
            fast_used = True
        raw, (tau, passive_torque, produced, requested, residual, scale, rounding) = fast
        kind = raw.method
        if residual > tol * scale + rounding:
            kind = "least-squares"
        elif kind == "least-squares":
            kind = "pseudo-inverse"
        base_effort = tau[:6].copy() if self._floating else np.zeros(0)
        solution = Solution(
            tau=tau,
            forces=raw.forces,
            wrench=produced,
            sets=raw.sets,
            residual=residual,
            method=kind,
            requested=requested,
            reactions=self.reactions,
            axes=self.axes,
            free=free,
            tau_passive=passive_torque,
            base_effort=base_effort,
            solver=raw.solver,
            systems=raw.systems,
            compiled=fast_used,
        )
        if strict and kind == "least-squares":
            raise InadmissibleWrenchError(
                f"The wrench {wrench.tolist()} on axes {self.axes} cannot be produced at this "
                f"configuration: residual {residual:.3g} (produced {produced.round(6).tolist()}).",
                solution,
            )
        return solution

    def torques(self, q: np.ndarray | Snapshot, forces: np.ndarray) -> np.ndarray:
        """Joint torques ``sum_i J_i^T F_i`` of a given distribution ``forces`` ``(p, n)``.

        Raises:
            InvalidInputError: Bad ``q``, or ``forces`` that are not ``(p, n)`` finite real
                numbers.

        """
        expected = f"a ({self.p}, {self.n}) array of real numbers (chains x axes)"
        forces = as_float_array(forces, "forces", expected)
        if forces.shape != (self.p, self.n) or not np.all(np.isfinite(forces)):
            raise InvalidInputError(
                f"forces must be finite with shape ({self.p}, {self.n}), got shape {forces.shape}."
            )
        return self.problem.torques(self.kinematics.compute(q).jacobian_o, forces)

    def __repr__(self) -> str:
        return (
            f"ParallelVirtualActuator(action={self.action!r}, reactions={list(self.reactions)}, "
            f"reference={self.reference!r}, axes={self.axes}, design={len(self.design)})"
        )
