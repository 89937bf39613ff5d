"""The controller: virtual components on virtual actuators, summed into joint efforts.

Per tick, for every active attachment (an actuator with its components):

1. read its sensor: pose and velocity of the action frame relative to the sensor's reaction
   frame, on the actuator's axes;
2. sum the components' wrenches;
3. map the wrench to joint torques: ``J^T F`` for a serial actuator, the partitioned
   distribution (:meth:`ParallelVirtualActuator.solve`) for a parallel one;

then add all torques, zero the limp joints, and clip to the URDF's effort limits, reporting
which joints saturated (VMC 2001, section 3: "the interactions between these components and the
robot automatically generate the desired torques").
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from ..actuators import ParallelVirtualActuator, VirtualActuator
from ..components.base import Component
from ..distribution.solution import Solution
from ..exceptions import (
    InvalidInputError,
    JointNotFoundError,
    SingularConfigurationError,
    suggestion,
)
from ..kinematics.snapshot import Snapshot
from ..kinematics.tree import tree_of
from ..robots.robot import Robot
from ..vocabulary.frames import (
    WORLD,
    as_float_array,
    check_axes_subset,
    check_flag,
    check_name,
    check_names,
    check_number,
    check_robot,
    check_sequence,
    describe,
    resolve_joint,
)

Actuator = VirtualActuator | ParallelVirtualActuator


@dataclass(repr=False)
class Attachment:
    """An actuator, the components attached to it and the sensor they read.

    Attributes:
        name: Unique name in its controller.
        actuator: The serial or parallel virtual actuator that produces the wrench.
        sensor: Serial actuator whose position and velocity the components read (for a serial
            actuator, the actuator itself).
        components: The virtual components.
        free: Axes left to the distribution (parallel actuators only).
        indices: For each component, the indices of its axes among the actuator's axes.

    """

    name: str
    actuator: Actuator
    sensor: VirtualActuator
    components: list[Component]
    free: tuple[str, ...] = ()
    indices: list[np.ndarray] = field(default_factory=list)
    unilateral: dict[int, float] = field(default_factory=dict)
    yield_mask: np.ndarray | None = None
    friction: float | None = None
    min_normal: float = 0.0
    bound_rows: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    bound_lows: np.ndarray = field(default_factory=lambda: np.zeros(0))
    force_columns: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    force_components: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))

    def __post_init__(self) -> None:
        # Each component's axes as a slice when contiguous (views instead of gathers per tick)
        self.slots = [_as_slice(index) for index in self.indices]
        # Declaration-time parts of the feasibility conditions (see Controller._constraint_rows)
        if self.yield_mask is None:
            return
        p, n = self.actuator.p, self.actuator.n
        rows = []
        for axis in self.unilateral:
            block = np.zeros((p, p, n))
            block[np.arange(p), np.arange(p), axis] = 1.0  # chain c's share on the axis
            rows.append(block.reshape(p, p * n))
        self.bound_rows = np.vstack(rows) if rows else np.zeros((0, p * n))
        self.bound_lows = np.repeat(np.array(list(self.unilateral.values()), dtype=float), p)
        force_axes = [(i, "xyz".index(a)) for i, a in enumerate(self.axes) if a in "xyz"]
        self.force_columns = np.array([i for i, _ in force_axes], dtype=int)
        self.force_components = np.array([k for _, k in force_axes], dtype=int)

    @property
    def axes(self) -> tuple[str, ...]:
        """The actuator's axes."""
        return self.actuator.axes

    def __repr__(self) -> str:
        kind = type(self.actuator).__name__
        names = ", ".join(c.name for c in self.components)
        return f"Attachment({self.name!r}, {kind} on {self.actuator.action!r}, [{names}])"


def _as_slice(index: np.ndarray) -> slice | np.ndarray:
    """``index`` as a slice if it is a contiguous increasing run, else unchanged."""
    if index.size and np.array_equal(index, np.arange(index[0], index[0] + index.size)):
        return slice(int(index[0]), int(index[0]) + index.size)
    return index


_NO_LIMP = np.zeros(0, dtype=np.intp)
_MAX_CHECKED_LIMP = 1024  # joint_indices arrays trusted by compute(); more are checked per call


def _names_tuple(active: object) -> tuple:
    """``active`` as a tuple, or an :class:`InvalidInputError` naming it."""
    if not isinstance(active, (bytes, Mapping)):
        try:
            return tuple(active)
        except TypeError:
            pass
    raise InvalidInputError(
        f"active must be a sequence of attachment names (or one name), got {describe(active)}."
    )


@dataclass(repr=False)
class ControlOutput:
    """What the controller computed in one tick.

    Attributes:
        tau: ``(nv,)`` joint efforts after limp joints and clipping [N m or N].
        tau_requested: ``(nv,)`` before clipping.
        saturated: ``(nv,)`` bool, True where the request exceeds the effort limit (and was
            clipped, unless the controller was built with ``clip=False``).
        wrenches: Requested wrench per active attachment, on its actuator's axes.
        produced: Wrench actually produced per attachment (differs from the request on free axes
            and for inadmissible requests).
        positions: Sensor position per active attachment [m, rad].
        velocities: Sensor velocity per active attachment [m/s, rad/s].
        solutions: Distribution per parallel attachment.
        failed: Attachments whose distribution was singular at this configuration (they
            contribute no torque) with the error message.
        active: Names of the attachments evaluated.
        joint_names: Names of the velocity entries (for reports).

    """

    tau: np.ndarray
    tau_requested: np.ndarray
    saturated: np.ndarray
    wrenches: dict[str, np.ndarray]
    produced: dict[str, np.ndarray]
    positions: dict[str, np.ndarray]
    velocities: dict[str, np.ndarray]
    solutions: dict[str, Solution]
    failed: dict[str, str]
    active: tuple[str, ...]
    joint_names: tuple[str, ...]

    @property
    def saturated_joints(self) -> list[str]:
        """Names of the velocity entries whose effort was clipped."""
        return [self.joint_names[i] for i in np.flatnonzero(self.saturated)]

    def __repr__(self) -> str:
        return (
            f"ControlOutput(active={self.active}, |tau|={np.linalg.norm(self.tau):.3g}, "
            f"saturated={self.saturated_joints}, failed={list(self.failed)})"
        )


def velocity_names(robot: Robot) -> tuple[str, ...]:
    """Name of every velocity entry: the joint's name, with ``[i]`` for multi-dof joints."""
    model = robot.model
    names: list[str] = []
    for joint_id in range(1, model.njoints):
        name, nv = model.names[joint_id], model.joints[joint_id].nv
        names.extend([name] if nv == 1 else [f"{name}[{i}]" for i in range(nv)])
    return tuple(names)


class Controller:
    """Evaluate virtual components on virtual actuators and return joint efforts.

    Args:
        robot: The robot.
        clip: Clip the efforts to the URDF's effort limits (joints without a positive finite
            limit are never clipped).
        on_singular: ``"raise"`` (default) re-raises :class:`SingularConfigurationError` from a
            parallel actuator; ``"skip"`` drops that actuator's torques for the tick and reports
            it in :attr:`ControlOutput.failed`.

    Raises:
        InvalidInputError: ``robot`` is not a robot, ``clip`` is not a bool, or a bad
            ``on_singular``.

    """

    def __init__(self, robot: Robot, clip: bool = True, on_singular: str = "raise") -> None:
        check_robot(robot, "Controller")
        if on_singular not in ("raise", "skip"):
            raise InvalidInputError(f"on_singular must be 'raise' or 'skip', got {on_singular!r}.")
        self.robot = robot
        self.clip = check_flag(clip, "clip")
        self.on_singular = on_singular
        self.attachments: dict[str, Attachment] = {}
        #: id -> index arrays made by joint_indices (read-only, in range): compute() trusts them
        self._checked_limp: dict[int, np.ndarray] = {}
        model = robot.model
        self.joint_names = velocity_names(robot)
        limits = np.full(model.nv, np.inf)
        for joint_id in range(1, model.njoints):
            joint = model.joints[joint_id]
            if joint.nv == 1:
                limit = float(model.effortLimit[joint.idx_v])
                if np.isfinite(limit) and limit > 0.0:
                    limits[joint.idx_v] = limit
        self.effort_limits = limits  # [N m or N], inf where unlimited (read-only; assign anew)

    @property
    def effort_limits(self) -> np.ndarray:
        """``(nv,)`` effort limits [N m or N], ``inf`` where unlimited (read-only array).

        Assign a new array to change them; it is checked and copied.

        Raises:
            InvalidInputError: (on assignment) not ``nv`` numbers, or a NaN or negative entry.

        """
        return self._upper_limits

    @effort_limits.setter
    def effort_limits(self, limits: object) -> None:
        nv = self.robot.model.nv
        expected = f"{nv} numbers >= 0 (inf where unlimited)"
        upper = as_float_array(limits, "effort_limits", expected, copy=True)
        if upper.shape != (nv,) or np.isnan(upper).any() or (upper < 0.0).any():
            raise InvalidInputError(f"effort_limits must be {expected}, got {upper}.")
        lower = -upper
        upper.setflags(write=False)
        lower.setflags(write=False)
        self._upper_limits, self._lower_limits = upper, lower

    def add(
        self,
        name: str,
        actuator: Actuator,
        components: Sequence[Component] = (),
        *,
        sensor: VirtualActuator | None = None,
        free: Sequence[str] = (),
        unilateral: Mapping[str, float] | None = None,
        yield_axes: Sequence[str] = (),
        friction: float | None = None,
        min_normal: float = 0.0,
    ) -> Attachment:
        """Attach components to an actuator under a unique name.

        Args:
            name: Unique name (states refer to it).
            actuator: A :class:`VirtualActuator` or :class:`ParallelVirtualActuator` of this
                controller's robot.
            components: Components whose axes are subsets of the actuator's axes (a sequence,
                or one component).
            sensor: What the components read. Default: the actuator itself if serial; for a
                parallel actuator, a serial actuator from ``"world"`` to its action frame on its
                axes and reference (the body's pose in the world, as a state estimator gives).
            free: Axes left to the distribution (parallel actuators), e.g. ``("x",)`` on one
                leg with a limp ankle (VMC eq. 5-7).
            unilateral: Parallel actuators: ``{axis: minimum}``, every chain's share on that axis
                must stay at or above the minimum, e.g. ``{"z": 5.0}`` so that no foot pulls on
                the ground [N]. When a request would break it, the request on ``yield_axes``
                is scaled down (the most that keeps every share feasible; the distribution is
                linear in the wrench) and :attr:`ControlOutput.produced` shows the result.
            yield_axes: Axes of the request given up first to meet ``unilateral`` and the
                friction cone.
            friction: Parallel actuators: friction coefficient ``mu`` of a contact cone at
                every reaction frame: each chain's share, seen in its reaction frame (a foot on
                sloped ground: normal along the frame's z), must keep its tangential part
                within ``mu`` times its normal part, the normal part at least ``min_normal``.
                The ground's slope comes from the reaction frame's orientation, so a limp foot
                lying on a slope tells it from the joint angles alone. Violations are met by
                scaling ``yield_axes`` like ``unilateral``. None: no cone.
            min_normal: Least normal force of the cone [N] (with ``friction``).

        Returns:
            The :class:`Attachment`.

        Raises:
            InvalidInputError: The name is not a str or is taken; the actuator or sensor is not
                a virtual actuator or belongs to another robot; the sensor's axes differ from
                the actuator's; a component is not a :class:`Component`; ``unilateral`` is not
                a dict of finite numbers; ``friction`` is not a finite number > 0 or
                ``min_normal`` not a finite number >= 0.
            InvalidAxisError: A component acts on an axis the actuator does not have, or
                ``free``, ``unilateral`` or ``yield_axes`` are not axes it has.

        """
        check_name(name, "Controller.add: name")
        where = f"Attachment {name!r}"
        if not isinstance(actuator, (VirtualActuator, ParallelVirtualActuator)):
            raise InvalidInputError(
                f"{where}: actuator must be a va.VirtualActuator or va.ParallelVirtualActuator, "
                f"got {describe(actuator)}."
            )
        if sensor is not None and not isinstance(sensor, VirtualActuator):
            raise InvalidInputError(
                f"{where}: sensor must be a va.VirtualActuator or None, got {describe(sensor)}."
            )
        components = list(
            check_sequence(
                components, f"{where}: components", "va.Component", Component, single=Component
            )
        )
        if friction is not None:
            friction = check_number(friction, f"{where}: friction", positive=True)
        min_normal = check_number(min_normal, f"{where}: min_normal [N]", minimum=0.0)
        if unilateral is not None and not isinstance(unilateral, Mapping):
            raise InvalidInputError(
                f"{where}: unilateral must be a dict {{axis: minimum [N]}}, got "
                f"{describe(unilateral)}."
            )
        if name in self.attachments:
            raise InvalidInputError(f"An attachment named {name!r} already exists.")
        if actuator.robot.model is not self.robot.model:
            raise InvalidInputError(f"Attachment {name!r}: the actuator is for another robot.")
        free_axes = check_axes_subset(free, actuator.axes, "free")
        if free_axes and isinstance(actuator, VirtualActuator):
            raise InvalidInputError(
                f"Attachment {name!r}: free axes need a ParallelVirtualActuator; a serial "
                "actuator produces every axis."
            )
        if sensor is None:
            if isinstance(actuator, VirtualActuator):
                sensor = actuator
            else:
                sensor = VirtualActuator(
                    self.robot, actuator.action, WORLD, actuator.reference, actuator.axes
                )
        if sensor.robot.model is not self.robot.model:
            raise InvalidInputError(f"Attachment {name!r}: the sensor is for another robot.")
        if sensor.axes != actuator.axes:
            raise InvalidInputError(
                f"Attachment {name!r}: sensor axes {sensor.axes} differ from the actuator's "
                f"{actuator.axes}."
            )
        indices = []
        for component in components:
            check_axes_subset(component.axes, actuator.axes, f"{component.name} axes")
            indices.append(np.array([actuator.axes.index(a) for a in component.axes]))
        limits: dict[int, float] = {}
        yield_mask = None
        constrained = bool(unilateral) or friction is not None
        yielded = check_axes_subset(yield_axes, actuator.axes, "yield_axes")
        if constrained or yielded:
            if isinstance(actuator, VirtualActuator) or not constrained or not yielded:
                raise InvalidInputError(
                    f"Attachment {name!r}: unilateral (or friction) and yield_axes go "
                    "together, on a ParallelVirtualActuator."
                )
            if friction is not None and not {"x", "y", "z"} & set(actuator.axes):
                raise InvalidInputError(
                    f"Attachment {name!r}: a friction cone needs force axes (x, y or z) among "
                    f"{actuator.axes}."
                )
            for axis in check_axes_subset(tuple(unilateral or {}), actuator.axes, "unilateral"):
                limits[actuator.axes.index(axis)] = check_number(
                    unilateral[axis], f"{where}: unilateral[{axis!r}]"
                )
            yield_mask = np.array([a in yielded for a in actuator.axes])
        attachment = Attachment(
            name,
            actuator,
            sensor,
            components,
            free_axes,
            indices,
            limits,
            yield_mask,
            friction,
            min_normal,
        )
        self.attachments[name] = attachment
        return attachment

    def joint_indices(self, joints: Iterable[str]) -> np.ndarray:
        """Velocity indices of joints given by name (one name, or a collection of names).

        Returns:
            The indices, a read-only integer array that :meth:`compute` accepts as ``limp``
            without checking it again.

        Raises:
            InvalidInputError: ``joints`` is not a name or a collection of names.
            JointNotFoundError: A name is not a joint of the model (with close matches).

        """
        model = self.robot.model
        out = []
        for joint in check_names(joints, "joints", JointNotFoundError, ordered=False):
            joint_id = resolve_joint(model, joint)
            out.extend(
                range(
                    model.joints[joint_id].idx_v,
                    model.joints[joint_id].idx_v + model.joints[joint_id].nv,
                )
            )
        index = np.array(out, dtype=np.intp)
        index.flags.writeable = False
        if len(self._checked_limp) < _MAX_CHECKED_LIMP:
            self._checked_limp[id(index)] = index  # kept alive: its id is never reused
        return index

    def reset(self, names: Iterable[str], q: np.ndarray | Snapshot, time: float) -> None:
        """Call every component's :meth:`~Component.reset` hook for the named attachments.

        Args:
            names: Attachment names (or one name).
            q: Configuration, or the tick's :class:`~virtual_actuators.Snapshot`.
            time: Controller time [s].

        Raises:
            InvalidInputError: ``names`` is not a collection of names, an unknown attachment
                name, a bad ``q``, or a ``time`` that is not a finite number.

        """
        names = check_names(names, "names (attachment names)", ordered=False)
        if not (isinstance(time, float) and -math.inf < time < math.inf):
            time = check_number(time, "time [s]")
        snapshot = q if isinstance(q, Snapshot) else Snapshot(self.robot, q)
        for name in names:
            attachment = self._get(name)
            position = attachment.sensor.position(snapshot)
            for component, index in zip(attachment.components, attachment.indices, strict=True):
                component.reset(position[index], time)

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

        One kinematics pass serves the whole tick: every sensor and actuator reads the same
        :class:`~virtual_actuators.Snapshot` (pass one built with ``v`` to share it with events
        and your own code too).

        Args:
            q: Configuration ``(nq,)``, or the tick's snapshot built with a velocity.
            v: Velocity ``(nv,)`` (omit it when ``q`` is a snapshot).
            time: Controller time [s] (components such as the dogtrack bunny use it), a finite
                number.
            active: Names of the attachments to evaluate (default: all), or one name.
            limp: Velocity indices forced to zero effort, integers in ``[0, nv)`` (an array
                from :meth:`joint_indices` is used as is; anything else is checked).

        Returns:
            The :class:`ControlOutput`.

        Raises:
            InvalidInputError: Bad ``q``, ``v``, ``time`` or ``limp``, ``active`` that is not a
                collection of names, or an unknown or repeated attachment name.
            SingularConfigurationError: A parallel actuator is singular here and
                ``on_singular="raise"``.

        """
        nv = self.robot.model.nv
        if not (isinstance(time, float) and -math.inf < time < math.inf):
            time = check_number(time, "time [s]")
        if self._checked_limp.get(id(limp)) is not limp:  # joint_indices' arrays: checked
            limp = _NO_LIMP if type(limp) is tuple and not limp else self._check_limp(limp)
        if isinstance(q, Snapshot):
            snapshot = q
            if snapshot.tree is not tree_of(self.robot) or snapshot.v is None:
                raise InvalidInputError(
                    "compute() needs a snapshot of this controller's robot built with v."
                )
        else:
            if v is None:
                raise InvalidInputError("compute(q, v, ...) needs a velocity v.")
            snapshot = Snapshot(self.robot, q, v)
        if active is None:
            names = tuple(self.attachments)
        else:
            if type(active) is not tuple:  # a state's active names are a tuple already
                active = (active,) if isinstance(active, str) else _names_tuple(active)
            names = active
            if len(set(names)) != len(names):
                raise InvalidInputError(f"active names an attachment twice: {names}.")
        tau = None
        wrenches, produced, positions, velocities = {}, {}, {}, {}
        solutions: dict[str, Solution] = {}
        failed: dict[str, str] = {}
        for name in names:
            attachment = self._get(name)
            sensor = attachment.sensor
            jacobian, position, velocity = sensor.kinematics.sense(snapshot, velocity=True)
            wrench = self._evaluate(attachment, position, velocity, time)
            positions[name], velocities[name], wrenches[name] = position, velocity, wrench
            actuator = attachment.actuator
            if isinstance(actuator, VirtualActuator):
                jacobian_act = jacobian if actuator is sensor else actuator.jacobian(snapshot)
                effort = jacobian_act.T @ wrench
                tau = effort if tau is None else tau + effort
                produced[name] = wrench
                continue
            try:
                solution = actuator.solve(snapshot, wrench, free=attachment.free)
                if attachment.yield_mask is not None:
                    solution = self._enforce_unilateral(attachment, snapshot, wrench, solution)
            except SingularConfigurationError as error:
                if self.on_singular == "raise":
                    raise
                failed[name] = str(error)
                continue
            tau = solution.tau.copy() if tau is None else tau + solution.tau
            solutions[name] = solution
            produced[name] = solution.wrench
        if tau is None:
            tau = np.zeros(nv)
        if limp.size:
            tau[limp] = 0.0
        requested = tau  # a fresh array: the clipped efforts are another one
        if self.clip:
            tau = np.minimum(np.maximum(requested, self._lower_limits), self._upper_limits)
            saturated = tau != requested  # clipped exactly where the request exceeds a limit
        else:
            tau = requested.copy()
            saturated = np.abs(requested) > self._upper_limits
        return ControlOutput(
            tau=tau,
            tau_requested=requested,
            saturated=saturated,
            wrenches=wrenches,
            produced=produced,
            positions=positions,
            velocities=velocities,
            solutions=solutions,
            failed=failed,
            active=names,
            joint_names=self.joint_names,
        )

    @staticmethod
    def _evaluate(
        attachment: Attachment, position: np.ndarray, velocity: np.ndarray, time: float
    ) -> np.ndarray:
        """Sum of the attachment's component wrenches on its actuator's axes (checked finite)."""
        components = attachment.components
        n = len(attachment.axes)
        wrench = None
        if len(components) == 1 and attachment.slots[0] == slice(0, n):  # one on every axis
            wrench = components[0].compute_wrench(position, velocity, time)
            if type(wrench) is not np.ndarray or wrench.shape != (n,) or wrench.dtype != float:
                wrench = None  # a scalar, list or other dtype: the general path below
        if wrench is None:
            wrench = np.zeros(n)
            for component, slot in zip(components, attachment.slots, strict=True):
                result = component.compute_wrench(position[slot], velocity[slot], time)
                try:
                    wrench[slot] += result
                except (TypeError, ValueError):
                    raise InvalidInputError(
                        f"Attachment {attachment.name!r}: component {component.name!r} returned "
                        f"{describe(result)}; expected {len(component.axes)} numbers (its axes "
                        f"{component.axes})."
                    ) from None
        if not math.isfinite(wrench @ wrench) and not np.all(np.isfinite(wrench)):
            raise InvalidInputError(
                f"Attachment {attachment.name!r}: a component returned a non-finite wrench "
                f"{wrench}."
            )
        return wrench

    def _check_limp(self, limp: object) -> np.ndarray:
        """``limp`` as an integer index array with every entry in ``[0, nv)``."""
        nv = self.robot.model.nv
        expected = f"velocity indices, integers in [0, {nv}) (see Controller.joint_indices)"
        if isinstance(limp, (str, bytes, Mapping)) or limp is None:
            raise InvalidInputError(f"limp must be {expected}, got {describe(limp)}.")
        try:
            index = np.asarray(limp)
        except (TypeError, ValueError):
            raise InvalidInputError(f"limp must be {expected}, got {describe(limp)}.") from None
        if index.size == 0:
            return _NO_LIMP
        if index.dtype.kind not in "iu" or index.ndim != 1:
            raise InvalidInputError(f"limp must be {expected}, got {describe(limp)}.")
        if index.min() < 0 or index.max() >= nv:
            raise InvalidInputError(f"limp must be {expected}, got {index.tolist()}.")
        return index

    @staticmethod
    def _constraint_rows(
        attachment: Attachment, snapshot: Snapshot
    ) -> tuple[np.ndarray, np.ndarray]:
        """Linear conditions ``rows @ forces.ravel() >= lows`` on the chains' shares.

        ``unilateral`` gives one row per chain and axis (built at declaration); a friction
        cone gives, per chain, the normal force (the reaction frame's z in {O}) ``>=
        min_normal`` and ``mu n.f -+ t.f >= 0`` for both tangents (a pyramid; a tangent outside
        the actuator's force axes gives a row implied by the normal one). The reaction frames'
        orientations are read from the tick's snapshot.
        """
        if attachment.friction is None:
            return attachment.bound_rows, attachment.bound_lows
        actuator = attachment.actuator
        p, n = actuator.p, actuator.n
        state = actuator.kinematics.compute(snapshot)
        rotation_o, rotations = state.rotation_o, state.rotation_a
        # reaction frames' axes in {O}, restricted to the actuator's force axes: (p, m, 3)
        frames_o = (rotation_o.T @ rotations)[:, attachment.force_components, :]
        normal, first, second = frames_o[..., 2], frames_o[..., 0], frames_o[..., 1]
        mu_normal = attachment.friction * normal
        vectors = np.stack(
            (normal, mu_normal - first, mu_normal + first, mu_normal - second, mu_normal + second),
            axis=1,
        )  # (p, 5, m)
        cone = np.zeros((p, 5, p, n))
        chains = np.arange(p)[:, None, None]
        cone[chains, np.arange(5)[None, :, None], chains, attachment.force_columns] = vectors
        cone_lows = np.tile([attachment.min_normal, 0.0, 0.0, 0.0, 0.0], p)
        rows = np.vstack((attachment.bound_rows, cone.reshape(5 * p, p * n)))
        return rows, np.concatenate((attachment.bound_lows, cone_lows))

    def _enforce_unilateral(
        self, attachment: Attachment, q: Snapshot, wrench: np.ndarray, solution: Solution
    ) -> Solution:
        """Scale the request on the yield axes until every chain's share is feasible.

        Feasible: ``unilateral`` minima and the friction cone (see :meth:`add`). The
        distribution is linear in the wrench, so the shares are ``base + alpha (full - base)``
        with ``base`` the request without its yield axes: the largest feasible ``alpha`` in
        ``[0, 1]`` comes from one extra solve and a ratio test.
        """
        rows, lows = self._constraint_rows(attachment, q)
        full = rows @ solution.forces.ravel()
        if np.all(full >= lows - 1e-9):
            return solution
        base = np.where(attachment.yield_mask, 0.0, wrench)
        fallback = attachment.actuator.solve(q, base, free=attachment.free)
        start = rows @ fallback.forces.ravel()
        slope = full - start
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = (lows - start) / slope
        upper = np.where(slope < 0.0, ratio, np.inf).min(initial=1.0)
        lower = np.where(slope > 0.0, ratio, -np.inf).max(initial=0.0)
        stuck = np.any((slope == 0.0) & (start < lows))  # no alpha helps that condition
        alpha = 0.0 if stuck or lower > upper else float(min(upper, 1.0))
        if alpha <= 0.0:
            return fallback
        return attachment.actuator.solve(
            q, np.where(attachment.yield_mask, alpha * wrench, wrench), free=attachment.free
        )

    def __repr__(self) -> str:
        return (
            f"Controller(robot={self.robot.name!r}, attachments={list(self.attachments)}, "
            f"clip={self.clip})"
        )
