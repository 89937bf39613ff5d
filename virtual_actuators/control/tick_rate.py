"""How much a controller's springs and dampers change the robot's velocity in one tick.

`tick_rate` measures a state's rate, `bound_tick_rate` scales derived gains down to `RATE_LIMIT`;
the model and the rule are in docs/reference/control.md ("Efforts a motor can follow").
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..actuators import ParallelVirtualActuator
from ..components.gains import Gains
from ..exceptions import InvalidInputError
from ..kinematics.snapshot import Snapshot
from ..vocabulary.arguments import check_number
from ..vocabulary.axes import resolve_frame

#: The largest per-tick rate a state's derived gains may reach (module docstring).
RATE_LIMIT = 0.5

#: Scaling rounds before the last, uniform one (`bound_tick_rate`).
_ROUNDS = 60

#: The least entry of the mass matrix's diagonal [kg or kg m^2]: a degree of freedom a URDF leaves
#: without inertia (a massless finger) is then very fast instead of singular (as the simulation
#: bounds it).
_INERTIA_FLOOR = 1e-10

#: An entry with less than this fraction of the largest share of the fastest direction is
#: not scaled in that round.
_SHARE = 0.01


@dataclass(frozen=True)
class TickRate:
    """The fastest per-tick rate of one state's springs and dampers (module docstring).

    Attributes:
        rate: The largest eigenvalue of the state's rate matrix [-]; a velocity error in that
            direction is multiplied by ``1 - rate`` each tick.
        period: The control period [s].
        labels: The entries: ``"attachment.axis"`` or ``"posture.joint"``.
        participation: ``(len(labels),)`` each entry's share of the fastest direction (sums
            to 1; zeros when no entry has a gain).
    """

    rate: float
    period: float
    labels: tuple[str, ...]
    participation: np.ndarray

    def dominant(self, count: int = 3) -> list[tuple[str, float]]:
        """The ``count`` entries with the largest share of the fastest direction."""
        order = np.argsort(-self.participation, kind="stable")[:count]
        return [(self.labels[i], float(self.participation[i])) for i in order]

    def __str__(self) -> str:
        shares = ", ".join(f"{label} {share:.0%}" for label, share in self.dominant())
        return f"rate {self.rate:.3g} per tick of {self.period * 1e3:g} ms ({shares or 'no gains'})"


@dataclass(frozen=True)
class _Entry:
    """A linear element of the state: its owner, rows and gains."""

    owner: object  # a component or a posture (what `scale_gains` is called on)
    labels: tuple[str, ...]
    rows: np.ndarray  # (n, nv)
    gains: Gains


def tick_rate(
    controller: object,
    q: np.ndarray,
    active: Sequence[str] | None = None,
    support: Sequence[str] = (),
    period: float = 1e-3,
) -> TickRate:
    """The fastest per-tick rate of the active springs and dampers (module docstring).

    Args:
        controller: A [`Controller`][].
        q: The configuration to judge at (a standing pose) ``(nq,)``.
        active: The attachments and postures evaluated (default: all of them).
        support: Frames held still (the feet in support); each is a point contact unless an
            active parallel actuator declares it flat.
        period: The control period [s].

    Returns:
        The `TickRate`.

    Raises:
        InvalidInputError: A bad period, configuration or name.
        FrameNotFoundError: A support frame the robot lacks (with close matches).
    """
    period = check_number(period, "period [s]", positive=True)
    entries, mobility = _state(controller, q, active, support)
    return _rate(entries, mobility, period)


def bound_tick_rate(
    controller: object,
    q: np.ndarray,
    states: Iterable[tuple[Sequence[str], Sequence[str]]],
    period: float,
    limit: float = RATE_LIMIT,
) -> list[TickRate]:
    """Scale the gains down where a state's rate exceeds ``limit`` (module docstring).

    Each state is ``(active, support)``; the states are taken in turn, each with the gains the
    ones before left (scaling an entry down never raises another state's rate).

    Args:
        controller: A [`Controller`][] whose components have [`linear_gains`][
            virtual_actuators.Component.linear_gains].
        q: The configuration to judge at (a standing pose).
        states: ``(active, support)`` per state of the gait.
        period: The control period [s].
        limit: The largest rate allowed [-] (0 < limit < 1).

    Returns:
        Each state's `TickRate` before its scaling (the same order).

    Raises:
        InvalidInputError: A bad period, limit, configuration or name.
        FrameNotFoundError: A support frame the robot lacks.
    """
    period = check_number(period, "period [s]", positive=True)
    limit = check_number(limit, "limit", positive=True)
    if limit >= 1.0:
        raise InvalidInputError(
            f"limit must be below 1 (a rate of 1 changes a velocity's sign each tick), got {limit}."
        )
    before = []
    for active, support in states:
        entries, mobility = _state(controller, q, active, support)
        rate = _rate(entries, mobility, period)
        before.append(rate)
        if rate.rate > limit:
            _scale(entries, mobility, period, limit)
    return before


def _state(
    controller: object, q: np.ndarray, active: Sequence[str] | None, support: Sequence[str]
) -> tuple[list[_Entry], np.ndarray]:
    """The state's linear elements and the robot's mobility with the support held."""
    robot = controller.robot
    model = robot.model
    q = np.asarray(q, dtype=float)
    if q.shape != (model.nq,) or not np.isfinite(q).all():
        raise InvalidInputError(f"tick_rate: q must be {model.nq} finite numbers.")
    names = list(controller.attachments) + list(controller.postures) if active is None else active
    snapshot = Snapshot(robot, q)
    entries, kinds = [], {}
    for name in names:
        if name in controller.postures:  # a gravity compensation has no gains
            posture = controller.postures[name]
            gains = getattr(posture, "linear_gains", lambda: None)()
            if gains is not None:
                labels = tuple(f"{name}.{j}" for j in posture.joints)
                entries.append(_Entry(posture, labels, np.eye(model.nv)[posture.v_rows], gains))
            continue
        if name not in controller.attachments:
            raise InvalidInputError(f"tick_rate: the controller has no attachment {name!r}.")
        attachment = controller.attachments[name]
        if isinstance(attachment.actuator, ParallelVirtualActuator):
            kinds.update(attachment.actuator.contacts.contact)
        rows = attachment.sensor.jacobian(snapshot)
        for component, index in zip(attachment.components, attachment.indices, strict=True):
            gains = component.linear_gains()
            if gains is not None:
                labels = tuple(f"{name}.{attachment.actuator.axes[i]}" for i in index)
                entries.append(_Entry(component, labels, rows[index], gains))
    return entries, _mobility(robot, q, [(frame, kinds.get(frame, "point")) for frame in support])


def _mobility(robot: object, q: np.ndarray, held: list[tuple[str, str]]) -> np.ndarray:
    """``(nv, nv)``: the inverse mass matrix on the motions that keep ``held`` still."""
    model = robot.model
    data = model.createData()
    mass = pin.crba(model, data, q)
    mass = np.triu(mass) + np.triu(mass, 1).T
    diagonal = np.diag_indices(model.nv)
    mass[diagonal] = np.maximum(mass[diagonal], _INERTIA_FLOOR)
    inverse = np.linalg.inv(mass)
    if not held:
        return inverse
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    rows = []
    for frame, kind in held:
        frame_id = resolve_frame(model, frame, "support frame")
        jacobian = pin.getFrameJacobian(model, data, frame_id, pin.LOCAL_WORLD_ALIGNED)
        rows.append(jacobian if kind == "flat" else jacobian[:3])
    held_rows = np.vstack(rows)
    coupling = inverse @ held_rows.T
    return inverse - coupling @ np.linalg.pinv(held_rows @ coupling, rcond=1e-10) @ coupling.T


def _rate(entries: list[_Entry], mobility: np.ndarray, period: float) -> TickRate:
    labels = tuple(label for entry in entries for label in entry.labels)
    if not entries:
        return TickRate(0.0, period, labels, np.zeros(0))
    rows = np.vstack([entry.rows for entry in entries])
    gain = np.concatenate([e.gains.damping + period * e.gains.stiffness for e in entries])
    root = np.sqrt(period * gain)
    matrix = root[:, None] * (rows @ mobility @ rows.T) * root[None, :]
    values, vectors = np.linalg.eigh(0.5 * (matrix + matrix.T))
    share = vectors[:, -1] ** 2
    return TickRate(max(float(values[-1]), 0.0), period, labels, share / max(share.sum(), 1e-300))


def _scale(entries: list[_Entry], mobility: np.ndarray, period: float, limit: float) -> None:
    """Scale the entries of the fastest directions down until the rate is ``limit``.

    Each round scales every entry by ``(limit / rate) ** (share / largest share)``: the
    entry that dominates the fastest direction by the full ratio, the others by less, those
    with under `_SHARE` of the largest share not at all. The rate never rises (every factor is
    at most 1); a last uniform factor, if the rounds have not ended within the limit, does.
    """
    factors = [np.ones(len(entry.labels)) for entry in entries]
    scaled = list(entries)
    for round_ in range(_ROUNDS + 1):
        rate = _rate(scaled, mobility, period)
        if rate.rate <= limit:
            break
        ratio = limit / rate.rate
        share = rate.participation / rate.participation.max()
        share[share < _SHARE] = 0.0  # a direction's bystanders keep their gains
        exponent = share if round_ < _ROUNDS else np.ones_like(share)
        start = 0
        for k, entry in enumerate(scaled):
            stop = start + len(entry.labels)
            factor = ratio ** exponent[start:stop]
            factors[k] = factors[k] * factor
            scaled[k] = _Entry(
                entry.owner, entry.labels, entry.rows,
                Gains(entry.gains.stiffness * factor, entry.gains.damping * factor),
            )  # fmt: skip
            start = stop
    for entry, factor in zip(entries, factors, strict=True):
        if (factor < 1.0).any():
            entry.owner.scale_gains(factor)
