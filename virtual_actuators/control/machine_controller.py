"""A controller driven by a state machine: the tick every gait runs, written once.

One tick of a gait, in this order:

1. one [`Snapshot`][] of ``(q, v)``: the tick's only kinematics pass;
2. a [`Context`][] on it, with the time and the contact switches;
3. [`StateMachine.update`][]: at most one transition,
   then the current state's ``on_update`` hook (a gait moves its set points there);
4. when the state changed, [`Controller.reset`][] of the
   attachments the new state activates (their components' ``reset`` hooks);
5. [`Controller.compute`][] of the state's active
   attachments, with its limp joints at zero effort.

[`MachineController`][] does exactly that; it has the ``compute(q, v, time)`` of a
controller, so [`va.run`][virtual_actuators.run] drives it like one::

    machine = va.MachineController(controller, va.StateMachine(states, transitions, "stand"))
    output = machine.compute(q, v, time, contacts={"FL_FOOT": True, ...})
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..exceptions import InvalidInputError
from ..kinematics.snapshot import Snapshot
from ..vocabulary.arguments import describe
from .controller import Controller, ControlOutput
from .state_machine import Context, State, StateMachine
from .tick import active_names


class MachineController:
    """A [`Controller`][] whose active attachments a state machine picks.

    Args:
        controller: The attachments (every name a state lists must be one of them).
        machine: The states and transitions.

    Attributes:
        controller: As given.
        machine: As given.
        last: The last [`ControlOutput`][] (None before the first tick).

    Raises:
        InvalidInputError: ``controller`` or ``machine`` of the wrong kind, or a state naming
            an attachment the controller lacks.
        JointNotFoundError: A state's limp joint is not a joint of the robot.

    """

    def __init__(self, controller: Controller, machine: StateMachine) -> None:
        if not isinstance(controller, Controller):
            raise InvalidInputError(
                f"MachineController: controller must be a va.Controller, got "
                f"{describe(controller)}."
            )
        if not isinstance(machine, StateMachine):
            raise InvalidInputError(
                f"MachineController: machine must be a va.StateMachine, got {describe(machine)}."
            )
        for state in machine.states:
            active_names(state.active)  # checked once: compute passes them on unchecked
            known = (*controller.attachments, *controller.postures)
            unknown = [name for name in state.active if name not in known]
            if unknown:
                raise InvalidInputError(
                    f"MachineController: state {state.name!r} activates {unknown[0]!r}, which is "
                    f"not an attachment of the controller ({list(known)})."
                )
        self.controller = controller
        self.machine = machine
        self.last: ControlOutput | None = None
        self._limp = {s.name: controller.joint_indices(s.limp) for s in machine.states}

    @property
    def state(self) -> State:
        """The current state."""
        return self.machine.current

    def limp_indices(self, state: str) -> np.ndarray:
        """The velocity indices a state leaves limp (its ``limp`` joints)."""
        return self._limp[state]

    def compute(
        self,
        q: np.ndarray | Snapshot,
        v: np.ndarray | None,
        time: float,
        contacts: Mapping[str, bool] | None = None,
    ) -> ControlOutput:
        """One tick: snapshot, context, machine update, resets on a change, the controller.

        Args:
            q: Configuration ``(nq,)`` (Pinocchio convention), or the tick's
                [`Snapshot`][] (with a velocity) to share its pass.
            v: Velocity ``(nv,)`` (ignored with a snapshot).
            time: Controller time [s].
            contacts: Contact switches by frame name (for events that read them).

        Returns:
            The [`ControlOutput`][] (its ``tau`` goes to the motors).

        Raises:
            InvalidInputError: Bad ``q``, ``v``, ``time`` or ``contacts``.
            VirtualActuatorError: What the controller raises under its failure policy.

        """
        controller = self.controller
        if isinstance(q, Snapshot):  # the caller's pass of this tick, shared
            snapshot, q, v = q, q.q, q.v
        else:
            snapshot = Snapshot(controller.robot, q, v)  # the tick's one kinematics pass
        context = Context.of_tick(controller.robot, snapshot, time, contacts)
        machine = self.machine
        before = len(machine.history)
        state = machine.update(context)
        if len(machine.history) != before:
            controller.reset(state.active, snapshot, time)
        self.last = controller.compute_checked(
            snapshot, context.time, state.active, self._limp[state.name]
        )
        return self.last

    def __repr__(self) -> str:
        return f"MachineController(state={self.machine.current.name!r}, {self.controller!r})"


__all__ = ["MachineController"]
