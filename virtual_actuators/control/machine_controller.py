"""A controller driven by a state machine: the tick every gait runs, written once.

The tick's order and its lowering into the compiled core: docs/reference/control.md.
"""

from __future__ import annotations

import os
from collections.abc import Mapping

import numpy as np

from ..core import has
from ..exceptions import InvalidInputError, TraceError
from ..kinematics.snapshot import Snapshot
from ..models.robot import Robot
from ..vocabulary.arguments import describe
from .controller import Controller, ControlOutput
from .plan.compiled import CompiledMachine
from .state_machine import Context, State, StateMachine
from .tick import active_names


class MachineController:
    """A [`Controller`][] whose active attachments a state machine picks.

    Args:
        controller: The attachments (every name a state lists must be one of them).
        machine: The states and transitions.
        compiled: Lower the machine into the compiled core on its first tick (False: every
            tick in Python, `compute_in_python`).

    Attributes:
        controller: As given.
        machine: As given.
        last: The last [`ControlOutput`][] (None before the first tick).
        limp: The velocity indices each state leaves limp (its ``limp`` joints), by name.

    Raises:
        InvalidInputError: ``controller`` or ``machine`` of the wrong kind, or a state naming
            an attachment the controller lacks.
        JointNotFoundError: A state's limp joint is not a joint of the robot.
    """

    def __init__(
        self, controller: Controller, machine: StateMachine, compiled: bool = True
    ) -> None:
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
        self.limp = {s.name: controller.joint_indices(s.limp) for s in machine.states}
        # the tick: the compiled machine, this object (Python), or None (not lowered yet)
        self._tick: CompiledMachine | MachineController | None = None if compiled else self

    @property
    def robot(self) -> Robot:
        """The controller's robot."""
        return self.controller.robot

    @property
    def compiled(self) -> CompiledMachine | None:
        """The compiled machine the ticks run on (None: Python, or not lowered yet)."""
        return self._tick if isinstance(self._tick, CompiledMachine) else None

    @property
    def state(self) -> State:
        """The current state."""
        return self.machine.current

    def compute(
        self,
        q: np.ndarray | Snapshot,
        v: np.ndarray | None,
        time: float,
        contacts: Mapping[str, bool] | None = None,
    ) -> ControlOutput:
        """One tick: snapshot, context, machine update, resets on a change, the controller.

        The compiled machine's tick once the machine is lowered (on the first tick, or in
        `warm_up`), else `compute_in_python`: the same efforts.

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
            ConcurrentUseError: Another thread is in a compiled tick of this machine.
            VirtualActuatorError: What the controller raises under its failure policy.
        """
        tick = self._tick
        if tick is None:
            tick = self._tick = self._lower()
        if tick is self:
            return self.compute_in_python(q, v, time, contacts)
        return tick.compute(q, v, time, contacts)

    def warm_up(self, q: np.ndarray) -> None:
        """Lower the machine (if it has not been) and warm its controller up.

        Before a timed loop: [`va.run`][virtual_actuators.run] calls it.

        Raises:
            InvalidInputError: A bad ``q``.
        """
        if self._tick is None:
            self._tick = self._lower()
        self.controller.warm_up(q)

    def _lower(self) -> CompiledMachine | MachineController:
        """The compiled machine, or this object (no core, ``VA_PLAN=0``, or refused)."""
        if not has("PlanMachine") or os.environ.get("VA_PLAN") == "0":
            return self
        try:
            return CompiledMachine(self)
        except TraceError:
            return self

    def compute_in_python(
        self,
        q: np.ndarray | Snapshot,
        v: np.ndarray | None,
        time: float,
        contacts: Mapping[str, bool] | None = None,
    ) -> ControlOutput:
        """`compute` in Python, whether or not the machine is lowered.

        The compiled tick's oracle, and the tick it hands on.

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
            snapshot, context.time, state.active, self.limp[state.name]
        )
        return self.last

    def __repr__(self) -> str:
        return f"MachineController(state={self.machine.current.name!r}, {self.controller!r})"
