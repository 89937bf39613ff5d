"""Control: the controller that turns components into efforts, and gait state machines."""

from . import events
from .controller import Attachment, Controller, ControlOutput, velocity_names
from .run_loop import RunStats, run
from .state_machine import Context, State, StateMachine, Transition

__all__ = [
    "Attachment",
    "Context",
    "ControlOutput",
    "Controller",
    "RunStats",
    "State",
    "StateMachine",
    "Transition",
    "events",
    "run",
    "velocity_names",
]
