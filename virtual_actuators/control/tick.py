"""One controller tick: its arguments' checks, its sums and its [`ControlOutput`][]."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

import numpy as np

from ..distribution.result import Solution
from ..exceptions import InvalidInputError
from ..kinematics.snapshot import Snapshot
from ..kinematics.tree import KinematicTree
from ..models.robot import Robot
from ..vocabulary.arguments import check_names, describe


@dataclass(frozen=True, slots=True)
class AttachmentFailure:
    """One attachment's failure in a tick and what the controller did.

    Attributes:
        reason: ``"wrench"`` (the components gave no finite wrench), ``"singular"``,
            ``"constraint"``, ``"inadmissible"``, ``"distribution"`` or ``"effort"``
            (non-finite joint efforts).
        error: The exception's type name, e.g. ``"ConstraintError"``.
        message: The exception's message.
        action: ``"skip"`` (zero effort) or ``"fallback"`` (the clipped partitioned
            least-squares answer).
        fallback_error: Why the fallback was not used (then ``action`` is ``"skip"``), or None.
    """

    reason: str
    error: str
    message: str
    action: str
    fallback_error: str | None = None

    def __str__(self) -> str:
        text = f"{self.reason} ({self.error}: {self.message}) -> {self.action}"
        return text if self.fallback_error is None else f"{text} ({self.fallback_error})"


@dataclass(repr=False, slots=True)
class ControlOutput:
    """What the controller computed in one tick.

    Attributes:
        tau: ``(nv,)`` joint efforts after limp joints and clipping [N m or N].
        tau_requested: ``(nv,)`` before clipping.
        saturated: ``(nv,)`` bool, True where the request exceeds the effort limit.
        wrenches: Requested wrench per active attachment, on its actuator's axes.
        produced: Wrench produced per attachment (not the request on free axes, inadmissible).
        positions: Sensor position per active attachment [m, rad].
        velocities: Sensor velocity per active attachment [m/s, rad/s].
        solutions: Distribution per parallel attachment.
        failed: Attachments left at zero effort this tick, with the error message.
        active: Names of the attachments evaluated.
        joint_names: Names of the velocity entries (for reports).
        failures: Every attachment whose failure policy fired this tick ([`AttachmentFailure`][]).
        rate_limited: ``(nv,)`` bool, True where the ``effort_rate_limit`` held the effort back.
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
    failures: dict[str, AttachmentFailure] = field(default_factory=dict)
    rate_limited: np.ndarray | None = None

    def __post_init__(self) -> None:
        if self.rate_limited is None:
            self.rate_limited = np.zeros(self.tau.shape, dtype=bool)

    def wrench_of(self, name: str) -> np.ndarray | None:
        """The requested wrench of attachment ``name``, None when it is not active."""
        return self.wrenches.get(name)

    @property
    def saturated_joints(self) -> list[str]:
        """Names of the velocity entries whose effort was clipped."""
        return [self.joint_names[i] for i in np.flatnonzero(self.saturated)]

    @property
    def rate_limited_joints(self) -> list[str]:
        """Names of the velocity entries the effort rate limit held back."""
        return [self.joint_names[i] for i in np.flatnonzero(self.rate_limited)]

    def __repr__(self) -> str:
        fallback = [name for name, f in self.failures.items() if f.action == "fallback"]
        return (
            f"ControlOutput(active={self.active}, |tau|={np.linalg.norm(self.tau):.3g}, "
            f"saturated={self.saturated_joints}, failed={list(self.failed)}"
            + (f", rate_limited={self.rate_limited_joints}" if self.rate_limited.any() else "")
            + (f", fallback={fallback})" if fallback else ")")
        )


@dataclass(slots=True)
class TickSums:
    """One tick's results per attachment ([`ControlOutput`][]'s dicts), the sum and its parts."""

    tau: np.ndarray | None = None
    wrenches: dict[str, np.ndarray] = field(default_factory=dict)
    produced: dict[str, np.ndarray] = field(default_factory=dict)
    positions: dict[str, np.ndarray] = field(default_factory=dict)
    velocities: dict[str, np.ndarray] = field(default_factory=dict)
    solutions: dict[str, Solution] = field(default_factory=dict)
    failed: dict[str, str] = field(default_factory=dict)
    failures: dict[str, AttachmentFailure] = field(default_factory=dict)
    parts: list[tuple[str, np.ndarray]] = field(default_factory=list)

    def add(self, name: str, effort: np.ndarray, fresh: bool) -> None:
        """Add an attachment's efforts (``fresh``: an array of its own, kept as the first sum)."""
        if self.tau is None:
            self.tau = effort if fresh else effort.copy()
        else:
            self.tau = self.tau + effort
        self.parts.append((name, effort))


def velocity_names(robot: Robot) -> tuple[str, ...]:
    """Name of every velocity entry: the joint's name, with ``[i]`` for multi-dof joints."""
    model = robot.model
    return tuple(
        name if nv == 1 else f"{name}[{i}]"
        for name, nv in ((model.names[j], model.joints[j].nv) for j in range(1, model.njoints))
        for i in range(nv)
    )


#: No limp joints.
NO_LIMP = np.zeros(0, dtype=np.intp)


def active_names(active: Iterable[str] | str) -> tuple[str, ...]:
    """``compute``'s ``active`` as a checked tuple of names (one name, or a collection).

    Raises:
        InvalidInputError: Not a name or a collection of names, an entry that is not a str,
            or a name repeated.
    """
    names = check_names(active, "active", ordered=False)
    if len(set(names)) != len(names):
        raise InvalidInputError(f"active names an attachment twice: {names}.")
    return names


def tick_snapshot(
    robot: Robot, tree: KinematicTree, q: np.ndarray | Snapshot, v: np.ndarray | None
) -> Snapshot:
    """The tick's snapshot: ``q`` itself (checked against ``tree`` and ``v``), or built.

    Raises:
        InvalidInputError: No ``v`` beside a configuration; a snapshot of another robot, or
            built without a velocity, or with one that differs from ``v``; a bad ``q`` or ``v``.
    """
    if not isinstance(q, Snapshot):
        if v is None:
            raise InvalidInputError("compute(q, v, ...) needs a velocity v.")
        return Snapshot(robot, q, v)
    if q.tree is not tree or q.v is None:
        raise InvalidInputError(
            "compute() needs a snapshot of this controller's robot built with v."
        )
    # v must equal the snapshot's velocity (never ignored; array_equal is False on a non-array)
    if v is not None and v is not q.v and not np.array_equal(v, q.v):
        raise InvalidInputError(
            "compute(snapshot, v): v differs from the velocity the snapshot was built with; "
            "omit v (the snapshot's is used) or build the snapshot with this v."
        )
    return q


def check_limp(limp: object, nv: int) -> np.ndarray:
    """``limp`` as an integer index array with every entry in ``[0, nv)``.

    Raises:
        InvalidInputError: Not a 1-D collection of integers in range.
    """
    if type(limp) is np.ndarray:  # the usual case (Controller.joint_indices): no conversion
        index = limp
    elif isinstance(limp, (str, bytes, Mapping)) or limp is None:
        raise _bad_limp(limp, nv)
    else:
        try:
            index = np.asarray(limp)
        except (TypeError, ValueError):
            raise _bad_limp(limp, nv) from None
    if index.size == 0:
        return NO_LIMP
    if index.dtype.kind not in "iu" or index.ndim != 1:
        raise _bad_limp(limp, nv)
    entries = index.tolist()  # a few entries: Python's min and max beat numpy's reductions
    if min(entries) < 0 or max(entries) >= nv:
        raise _bad_limp(entries, nv)
    return index


def _bad_limp(limp: object, nv: int) -> InvalidInputError:
    expected = f"velocity indices, integers in [0, {nv}) (see Controller.joint_indices)"
    shown = limp if isinstance(limp, list) else describe(limp)
    return InvalidInputError(f"limp must be {expected}, got {shown}.")
