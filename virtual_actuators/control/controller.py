"""The controller: virtual components on virtual actuators, summed into joint efforts (VMC 3)."""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Iterable, Mapping, Sequence

import numpy as np

from ..actuators import ParallelVirtualActuator, VirtualActuator
from ..components.base import Component
from ..components.gravity import GravityCompensation
from ..components.posture import Posture
from ..exceptions import InvalidInputError, JointNotFoundError, VirtualActuatorError, suggestion
from ..kinematics.kernels import finite, velocity_of_point
from ..kinematics.snapshot import Snapshot, thread_data
from ..kinematics.tree import tree_of
from ..models.robot import Robot
from ..vocabulary.arguments import check_flag, check_names, check_number, check_robot
from ..vocabulary.axes import resolve_joint
from .attachment import Actuator, Attachment
from .effort_limits import (
    EffortRateLimit,
    LimitFraction,
    RateSpec,
    check_effort_limits,
    clip_efforts,
    effort_rates,
    urdf_effort_limits,
)
from .failures import check_policy, drop_non_finite, largest_scale, least_margin, run_attachment
from .tick import ControlOutput, TickSums, active_names, check_limp, tick_snapshot, velocity_names

#: What ``Controller.add`` keeps as a joint-space term (``torques(snapshot)`` each tick)
JointTerm = Posture | GravityCompensation


class Controller:
    """Evaluate virtual components on virtual actuators and return joint efforts.

    Args:
        robot: The robot.
        clip: Clip the efforts to the URDF's effort limits (joints without a positive finite
            limit are never clipped).
        on_singular: Alias of ``on_failure``; give one of the two.
        on_failure: What a failing attachment does: ``"raise"`` (default) the typed error,
            ``"skip"`` drops its efforts for the tick, ``"fallback"`` uses the partitioned
            least-squares answer clipped to [`effort_limits`][]; reported in
            `ControlOutput.failures`.
        effort_rate_limit: Largest change of effort per second after the clip [N m/s]: a
            number, ``(nv,)``, ``{joint: rate}``, a
            [`LimitFraction`][virtual_actuators.LimitFraction], or None.

    Raises:
        InvalidInputError: ``robot`` is not a robot, ``clip`` is not a bool, a bad
            ``on_failure`` or ``on_singular``, or both given with different values, or a bad
            ``effort_rate_limit``.
        JointNotFoundError: ``effort_rate_limit`` names a joint the robot lacks.
    """

    def __init__(
        self,
        robot: Robot,
        clip: bool = True,
        on_singular: str | None = None,
        on_failure: str | None = None,
        effort_rate_limit: RateSpec = None,
    ) -> None:
        check_robot(robot, "Controller")
        self.on_failure = check_policy(on_failure, on_singular)
        self.robot = robot
        self.clip = check_flag(clip, "clip")
        self.attachments: dict[str, Attachment] = {}
        #: Joint-space terms (Posture, GravityCompensation) by name
        self.postures: dict[str, JointTerm] = {}
        self._tree = tree_of(robot)
        self.joint_names = velocity_names(robot)
        self._rate_spec: RateSpec = None
        self.effort_limits = urdf_effort_limits(robot)
        self.effort_rate_limit = effort_rate_limit

    @property
    def effort_limits(self) -> np.ndarray:
        """``(nv,)`` effort limits [N m or N], ``inf`` where unlimited; assign to change.

        Raises:
            InvalidInputError: (on assignment) not ``nv`` numbers, or a NaN or negative entry.
        """
        return self._upper_limits

    @effort_limits.setter
    def effort_limits(self, limits: object) -> None:
        self._lower_limits, self._upper_limits = check_effort_limits(limits, self.robot.model.nv)
        if isinstance(self._rate_spec, LimitFraction):  # its rates follow the limits
            self.effort_rate_limit = self._rate_spec

    @property
    def effort_rate_limit(self) -> RateSpec:
        """The effort rate limit as given (None: none); assign to change.

        Raises:
            InvalidInputError: (on assignment) a bad limit (see the constructor).
            JointNotFoundError: (on assignment) a ``{joint: rate}`` naming an unknown joint.
        """
        return self._rate_spec

    @effort_rate_limit.setter
    def effort_rate_limit(self, spec: RateSpec) -> None:
        rates = effort_rates(spec, self._upper_limits, self.joint_names)
        self._rate_spec = spec
        self._rate_limit = None if rates is None else EffortRateLimit(rates)

    def limit_rate(self, tau: np.ndarray, time: float) -> tuple[np.ndarray, np.ndarray | None]:
        """``(tau, held)``: ``tau`` under the rate limit (in place); ``held`` None without one."""
        if self._rate_limit is None:
            return tau, None
        return self._rate_limit.apply(tau, time)

    def reset_effort_rate(self, tau: np.ndarray | None = None, time: float = 0.0) -> None:
        """Restart the effort rate limit from efforts ``tau`` [N m or N] at ``time`` [s], or free.

        Raises:
            InvalidInputError: No effort rate limit, or a bad ``tau`` or ``time``.
        """
        if self._rate_limit is None:
            raise InvalidInputError("reset_effort_rate: the controller has no effort_rate_limit.")
        self._rate_limit.restart(tau, time)

    def add(
        self,
        name: str,
        actuator: Actuator | JointTerm,
        components: Sequence[Component] = (),
        *,
        sensor: VirtualActuator | None = None,
        free: Sequence[str] = (),
        unilateral: Mapping[str, float] | None = None,
        yield_axes: Sequence[str] = (),
        friction: float | None = None,
        min_normal: float = 0.0,
        method: str = "partitioned",
        yield_weight: float | None = None,
    ) -> Attachment | JointTerm:
        """Attach components to an actuator (or a joint-space term) under a unique name.

        Args:
            name: Unique name (states refer to it).
            actuator: A [`VirtualActuator`][] or [`ParallelVirtualActuator`][] of this robot, or
                a joint-space term: a [`Posture`][] or a [`GravityCompensation`][].
            components: Components on subsets of the actuator's axes (or one component).
            sensor: What the components read. Default: the actuator if serial, else a serial
                actuator from ``"world"`` to its action frame on its axes and reference.
            free: Axes left to the distribution (parallel actuators; VMC eq. 5-7).
            unilateral: ``{axis: minimum}`` every chain's share must keep [N]; a request that
                breaks it is scaled down on ``yield_axes``.
            yield_axes: Axes given up first to meet ``unilateral`` and ``friction``; with
                ``method="qp"``, the axes weighted ``yield_weight`` in the closest wrench.
            friction: Friction coefficient ``mu`` of a pyramid at every reaction frame, about
                the actuator's contact normals; violations scale ``yield_axes``. None: no cone.
            min_normal: Least normal force of the cone [N].
            method: ``"partitioned"``, ``"dense"`` or ``"qp"`` (then ``unilateral`` and
                ``friction`` must be left out).
            yield_weight: ``method="qp"``: weight of ``yield_axes``, a finite number > 0; None
                for `YIELD_WEIGHT` (1e-3).

        Returns:
            The `Attachment` (the term itself for a joint-space term).

        Raises:
            InvalidInputError: The name is not a str or is taken; the actuator or sensor is not
                a virtual actuator or belongs to another robot; the sensor's axes differ from
                the actuator's; a component is not a [`Component`][]; a gravity compensation
                of another robot, or components given with a joint-space term; ``unilateral``
                is not a dict of finite numbers; ``friction`` is not a finite number > 0 or
                ``min_normal`` not a finite number >= 0; ``yield_weight`` without
                ``method="qp"`` or not a finite number > 0.
            InvalidAxisError: A component acts on an axis the actuator does not have, or
                ``free``, ``unilateral`` or ``yield_axes`` are not axes it has.
            JointNotFoundError: A posture's joint that the robot lacks (with close matches).
        """
        if isinstance(actuator, JointTerm):  # bound to the robot under ``name``
            kind = type(actuator).__name__
            if not isinstance(name, str) or name in self.attachments or name in self.postures:
                raise InvalidInputError(
                    f"{kind} {name!r}: the name must be a str not taken by another attachment."
                )
            if components not in ((), None, []):
                raise InvalidInputError(f"{kind} {name!r} takes no components: it is one.")
            self.postures[name] = actuator.bind(self.robot)
            return actuator
        attachment = self.attachments[name] = Attachment.declare(
            self.robot, name, actuator, components, sensor, free, unilateral, yield_axes,
            friction, min_normal, method, yield_weight, {**self.attachments, **self.postures},
        )  # fmt: skip
        return attachment

    def joint_indices(self, joints: Iterable[str]) -> np.ndarray:
        """Velocity indices (a read-only integer array) of joints given by name, or one name.

        Raises:
            InvalidInputError: ``joints`` is not a name or a collection of names.
            JointNotFoundError: A name is not a joint of the model (with close matches).
        """
        model = self.robot.model
        names = check_names(joints, "joints", JointNotFoundError, ordered=False)
        found = [model.joints[resolve_joint(model, joint)] for joint in names]
        index = np.array([i for j in found for i in range(j.idx_v, j.idx_v + j.nv)], dtype=np.intp)
        index.flags.writeable = False
        return index

    def reset(self, names: Iterable[str], q: np.ndarray | Snapshot, time: float) -> None:
        """Call every component's `reset` hook for the named attachments (or one name).

        Args:
            names: Attachment names.
            q: Configuration, or the tick's [`Snapshot`][].
            time: Controller time [s].

        Raises:
            InvalidInputError: ``names`` is not a collection of names, an unknown attachment
                name, a bad ``q``, or a ``time`` that is not a finite number.
        """
        names = check_names(names, "names (attachment names)", ordered=False)
        time = check_number(time, "time [s]")
        snapshot = q if isinstance(q, Snapshot) else Snapshot(self.robot, q)
        for name in names:
            if name in self.postures:
                self.postures[name].reset(snapshot)
                continue
            attachment = self._get(name)
            position = attachment.sensor.position(snapshot)
            for component, index in zip(attachment.components, attachment.indices, strict=True):
                component.reset(position[index], time)

    def warm_up(self, q: np.ndarray) -> None:
        """Run every kernel the ticks use once at ``q`` (their buffers), changing no state.

        Raises:
            InvalidInputError: A bad ``q``.
        """
        robot = self.robot
        snapshot = Snapshot(robot, q, np.zeros(robot.model.nv))
        thread_data(robot.model)
        if robot.mass > 0.0:
            robot.center_of_mass(snapshot.q)
        # a frame's velocity outside the tick's table (a frame first named mid-run)
        no_columns = np.zeros(0, dtype=np.int64)
        velocity_of_point(snapshot.jacobian_world, snapshot.v, no_columns, 0.0, 0.0, 0.0)
        for attachment in self.attachments.values():
            kinematics = attachment.sensor.kinematics
            kinematics.sense(snapshot, velocity=True)
            snapshot.frame_velocity(kinematics.action_id)
            if attachment.spring_tick is not None:  # the spring-dampers' one-call tick
                attachment.spring_tick.warm_up(snapshot)
            actuator = attachment.actuator
            if not isinstance(actuator, ParallelVirtualActuator):
                continue
            try:
                if attachment.method == "qp":
                    _on_own_thread(actuator, snapshot, attachment)
                    if attachment.plan is not None and actuator.qp.matrices.applicable:
                        actuator.qp.matrices.workspace(attachment.plan.keep)  # this thread's
                    continue
                solution = actuator.solve(
                    snapshot, np.zeros(actuator.n), attachment.free, method=attachment.method
                )
            except VirtualActuatorError:  # singular at q, say: the kernels load on the first tick
                continue
            if attachment.yield_mask is not None:
                least_margin(attachment, snapshot, solution.forces)
                largest_scale(attachment, snapshot, solution.forces, solution.forces)

    def _get(self, name: str) -> Attachment:
        try:
            return self.attachments[name]
        except (KeyError, TypeError):  # TypeError: an unhashable name
            hint = suggestion(str(name), self.attachments, "attachments")
            raise InvalidInputError(f"No attachment named {name!r}. {hint}") from None

    def compute(
        self,
        q: np.ndarray | Snapshot,
        v: np.ndarray | None = None,
        time: float = 0.0,
        active: Iterable[str] | None = None,
        limp: np.ndarray | Sequence[int] = (),
    ) -> ControlOutput:
        """Evaluate the components and return the joint efforts for one tick.

        Args:
            q: Configuration ``(nq,)``, or the tick's [`Snapshot`][] built with a velocity.
            v: Velocity ``(nv,)``; omit it with a snapshot.
            time: Controller time [s].
            active: Attachments (postures too) to evaluate (default: all).
            limp: Velocity indices forced to zero effort (e.g. from [`joint_indices`][]).

        Raises:
            InvalidInputError: Bad ``q``, ``v``, ``time``, ``limp`` or ``active`` (an unknown
                or repeated name); a snapshot with another ``v``. With ``on_failure="raise"``,
                also a component's non-finite or malformed wrench, or non-finite efforts.
            SingularConfigurationError: A parallel actuator is singular here and
                ``on_failure="raise"``.
            ConstraintError: A distribution that cannot be solved here (e.g. an infeasible
                contact QP, or one out of iterations) and ``on_failure="raise"``.
        """
        time = check_number(time, "time [s]")
        limp = check_limp(limp, self.robot.model.nv)
        snapshot = tick_snapshot(self.robot, self._tree, q, v)
        names = (*self.attachments, *self.postures) if active is None else active_names(active)
        return self.compute_checked(snapshot, time, names, limp)

    def compute_checked(
        self, snapshot: Snapshot, time: float, names: tuple[str, ...], limp: np.ndarray
    ) -> ControlOutput:
        """[`compute`][] on arguments checked already (a gait's per-tick call).

        Raises:
            InvalidInputError: An unknown attachment name, or as [`compute`][].
            SingularConfigurationError: As [`compute`][].
            ConstraintError: As [`compute`][].
        """
        nv = self.robot.model.nv
        postures = self.postures
        sums = TickSums()
        attachments = self.attachments
        on_failure, limits = self.on_failure, self._upper_limits
        for name in names:
            if postures and name in postures:  # a joint-space term
                sums.add(name, postures[name].torques(snapshot), fresh=True)
            else:
                attachment = attachments.get(name) if name.__class__ is str else None
                if attachment is None:
                    attachment = self._get(name)  # raises, naming the known attachments
                run_attachment(attachment, snapshot, time, sums, on_failure, limits)
        tau = sums.tau
        if tau is not None and not finite(tau):
            tau = drop_non_finite(self, snapshot, sums)
        if tau is None:
            tau = np.zeros(nv)
        if limp.size:
            tau[limp] = 0.0
        clipped, saturated = clip_efforts(  # tau: a fresh array, the request
            tau, self._lower_limits, self._upper_limits, self.clip
        )
        clipped, held = self.limit_rate(clipped, time)
        return ControlOutput(  # positional (a tick's cost): the fields in declaration order
            clipped, tau, saturated, sums.wrenches, sums.produced, sums.positions, sums.velocities,
            sums.solutions, sums.failed, names, self.joint_names, sums.failures, held,
        )  # fmt: skip

    def __repr__(self) -> str:
        return (
            f"Controller(robot={self.robot.name!r}, attachments={list(self.attachments)}, "
            f"clip={self.clip})"
        )


def _on_own_thread(actuator: ParallelVirtualActuator, snapshot: Snapshot, attachment) -> None:
    """A QP solve on a new thread: its kernels load, this thread's warm start is untouched."""

    def solve() -> None:
        with contextlib.suppress(VirtualActuatorError):
            zero = np.zeros(actuator.n)
            actuator.solve(snapshot, zero, attachment.free, method="qp", weights=attachment.weights)

    worker = threading.Thread(target=solve, name="va-warm-up")
    worker.start()
    worker.join()
