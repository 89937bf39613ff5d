"""Control: the controller that turns components into efforts, and gait state machines."""

from . import events
from .controller import Attachment, Controller, ControlOutput, velocity_names
from .failures import FAILURE_POLICIES, AttachmentFailure
from .machine_controller import MachineController
from .run_loop import RunStats, run
from .safe_action import SAFE_ACTIONS
from .state_machine import Context, State, StateMachine, Transition

__all__ = [
    "FAILURE_POLICIES",
    "SAFE_ACTIONS",
    "Attachment",
    "AttachmentFailure",
    "Context",
    "ControlOutput",
    "Controller",
    "MachineController",
    "RunStats",
    "State",
    "StateMachine",
    "Transition",
    "events",
    "run",
    "velocity_names",
]
