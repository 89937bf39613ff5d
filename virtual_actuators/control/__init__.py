"""Control: the controller that turns components into efforts, and gait state machines."""

from . import events
from .controller import Attachment, Controller, ControlOutput, velocity_names
from .effort_limits import LimitFraction
from .failures import FAILURE_POLICIES
from .machine_controller import MachineController
from .run_loop import RunStats, run
from .safe_action import SAFE_ACTIONS
from .state_machine import Context, State, StateMachine, Transition
from .tick import AttachmentFailure
from .tick_rate import RATE_LIMIT, TickRate, bound_tick_rate, tick_rate

__all__ = [
    "FAILURE_POLICIES",
    "RATE_LIMIT",
    "SAFE_ACTIONS",
    "Attachment",
    "AttachmentFailure",
    "Context",
    "ControlOutput",
    "Controller",
    "LimitFraction",
    "MachineController",
    "RunStats",
    "State",
    "StateMachine",
    "TickRate",
    "Transition",
    "bound_tick_rate",
    "events",
    "run",
    "tick_rate",
    "velocity_names",
]
