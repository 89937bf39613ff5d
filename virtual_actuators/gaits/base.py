"""Common machinery of the planar walking gaits: a controller driven by a state machine.

A :class:`Gait` owns a :class:`~virtual_actuators.control.Controller` (actuators and components,
declared once) and a :class:`~virtual_actuators.control.StateMachine` whose states select which
attachments run. :meth:`Gait.compute` is the whole per-tick control law: update the machine on
the tick's :class:`~virtual_actuators.control.Context`, reset the components of attachments that
just became active, evaluate the active ones and return the joint efforts.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
import pinocchio as pin

from ..control.controller import Controller, ControlOutput
from ..control.state_machine import Context, Event, StateMachine
from ..exceptions import InvalidInputError
from ..kinematics.snapshot import Snapshot
from ..models.robot import Robot
from ..vocabulary.frames import resolve_frame, resolve_joint


class Gait:
    """A controller and a state machine stepped together.

    Subclasses build :attr:`controller` and :attr:`machine` in their constructor and call
    :meth:`_finish` at the end.

    Attributes:
        robot: The robot.
        controller: Actuators and components.
        machine: States and transitions.
        step_states: States whose entries count as steps (single support).
        contact_frames: Frames whose contact switches the gait reads.
        foot_contacts: Contact frames per support frame (see :meth:`support_contacts`).
        last: The last :class:`ControlOutput`.

    """

    step_states: tuple[str, ...] = ()
    contact_frames: tuple[str, ...] = ()
    #: The contact frames that make up each support frame whose geoms are elsewhere (a flat
    #: foot's heel and toe); a support frame not listed is its own contact frame.
    foot_contacts: Mapping[str, tuple[str, ...]] = {}

    def __init__(self, robot: Robot) -> None:
        self.robot = robot
        self.controller = Controller(robot, clip=True, on_singular="skip")
        self.machine: StateMachine | None = None
        self.last: ControlOutput | None = None
        self._limp: dict[str, np.ndarray] = {}

    def _finish(self, machine: StateMachine) -> None:
        self.machine = machine
        self._limp = {s.name: self.controller.joint_indices(s.limp) for s in machine.states}

    def _front_is(self, side: str, event: Event) -> Event:
        """``event``, but only while ``side`` is the front foot (``self.front``)."""
        return lambda context: self.front == side and event(context)

    def initial_configuration(self) -> np.ndarray:
        """Where a simulation of this gait starts (default: the robot's standing pose)."""
        return self.robot.neutral()

    def nominal_height(self) -> float:
        """Nominal hip height above level ground [m] (the gait's ``height`` or ``hip_height``)."""
        parameters = getattr(self, "parameters", None)
        if hasattr(parameters, "hip_height"):
            return float(parameters.hip_height(0.0))
        return float(parameters.height)

    def support_contacts(self) -> list[tuple[str, ...]]:
        """Per foot in support in the current state, the contact frames that make it up."""
        contacts = self.foot_contacts
        return [contacts.get(foot, (foot,)) for foot in self.machine.current.support]

    @property
    def state(self) -> str:
        """Name of the current state."""
        return self.machine.current.name

    def compute(
        self,
        q: np.ndarray,
        v: np.ndarray,
        time: float,
        contacts: Mapping[str, bool] | None = None,
    ) -> ControlOutput:
        """One control tick: update the state machine, then evaluate the active attachments.

        Args:
            q: Configuration ``(nq,)`` (Pinocchio convention).
            v: Velocity ``(nv,)``.
            time: Controller time [s].
            contacts: Contact switches by frame name (only the gaits that use switches need them).

        Returns:
            The :class:`ControlOutput` (its ``tau`` goes to the motors).

        """
        snapshot = Snapshot(self.robot, q, v)  # the tick's one kinematics pass
        context = Context(self.robot, q, v, time, contacts, snapshot=snapshot)
        before = len(self.machine.history)
        state = self.machine.update(context)
        if len(self.machine.history) != before:
            self.controller.reset(state.active, snapshot, time)
        self.last = self.controller.compute(
            snapshot, None, time, state.active, self._limp[state.name]
        )
        return self.last

    def __repr__(self) -> str:
        return f"{type(self).__name__}(robot={self.robot.name!r}, state={self.state!r})"


#: The ways a gait's double support can share the body's wrench (``distribution=``).
DISTRIBUTIONS = ("partitioned", "qp")


def check_distribution(distribution: object) -> bool:
    """Whether ``distribution`` asks for the QP (checked: one of :data:`DISTRIBUTIONS`).

    Raises:
        InvalidInputError: Any other value.

    """
    if distribution not in DISTRIBUTIONS:
        raise InvalidInputError(
            f"distribution must be one of {DISTRIBUTIONS}, got {distribution!r}."
        )
    return distribution == "qp"


def planar_leg_ik(dx: float, dz: float, thigh: float, shin: float) -> tuple[float, float]:
    """Hip and knee angles that put a planar two-link leg's end at ``(dx, dz)`` from the hip.

    Joints turn about +y (a positive angle swings the distal link backward), the knee bends
    positively (it points forward), the body is upright.

    Args:
        dx: Foot x minus hip x [m].
        dz: Foot z minus hip z [m] (negative below the hip).
        thigh: Hip-to-knee length [m].
        shin: Knee-to-foot length [m].

    Returns:
        ``(hip, knee)`` [rad].

    Raises:
        InvalidInputError: The point is out of reach.

    """
    u, w = -dx, -dz
    cos_knee = (u * u + w * w - thigh**2 - shin**2) / (2.0 * thigh * shin)
    if not -1.0 - 1e-12 <= cos_knee <= 1.0 + 1e-12:
        raise InvalidInputError(
            f"Foot offset ({dx:.3f}, {dz:.3f}) m is out of reach of a {thigh:.3f} + {shin:.3f} m "
            "leg."
        )
    knee = math.acos(min(1.0, max(-1.0, cos_knee)))  # rounding at full extension
    hip = math.atan2(u, w) - math.atan2(shin * math.sin(knee), thigh + shin * math.cos(knee))
    return hip, knee


def planar_standing_configuration(
    robot: Robot,
    height: float,
    feet: Mapping[str, float],
    foot_frame: str = "{side}_foot",
    ground: float = 0.0,
) -> np.ndarray:
    """A standing configuration of a planar biped on a boom at a given hip height.

    Args:
        robot: A planar biped with joints ``boom_x``, ``boom_z``, ``boom_pitch``,
            ``SIDE_hip``, ``SIDE_knee`` (and optionally ``SIDE_ankle``, set so the foot is flat).
        height: Hip height above the foot frames [m].
        feet: Foot frame x relative to the hip, per side, e.g. ``{"left": 0.1, "right": -0.1}``.
        foot_frame: Name pattern of the frame at the end of the shin (ankle or point foot).
        ground: Height of the foot frames [m].

    Returns:
        ``q`` of size ``nq`` (Pinocchio convention).

    Raises:
        JointNotFoundError: A joint above is missing.
        InvalidInputError: A foot is out of reach.

    """
    model = robot.model
    q = robot.neutral()
    data = pin.Data(model)
    pin.framesForwardKinematics(model, data, q)

    def index(joint: str) -> int:
        return model.joints[resolve_joint(model, joint)].idx_q

    q[index("boom_z")] = ground + height
    q[index("boom_pitch")] = 0.0
    for side, dx in feet.items():
        hip = data.oMi[resolve_joint(model, f"{side}_hip")].translation
        knee = data.oMi[resolve_joint(model, f"{side}_knee")].translation
        end = data.oMf[resolve_frame(model, foot_frame.format(side=side), "foot")].translation
        thigh, shin = np.linalg.norm(knee - hip), np.linalg.norm(end - knee)
        hip_angle, knee_angle = planar_leg_ik(dx, -height, thigh, shin)
        q[index(f"{side}_hip")], q[index(f"{side}_knee")] = hip_angle, knee_angle
        if f"{side}_ankle" in model.names:
            q[index(f"{side}_ankle")] = -(hip_angle + knee_angle)
    return q
