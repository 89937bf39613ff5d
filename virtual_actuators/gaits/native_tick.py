"""What a gait's whole tick in the compiled core shares, whatever the gait.

A native tick (`gaits.turkey.native`, `gaits.hexapod.native`) runs `Gait.compute`'s arithmetic in
one call of the core, bit for bit, and answers a `NativeOutput`. `CoreTick` holds what every one
of them does around that call: the active attachments' wrenches read from the core's readings,
the Python machine's entry into the state the core entered, and a tick the core hands on,
computed by the Python gait between two synchronisations (`sync`, then `load`), so that the
Python gait carries on exactly as if it had computed every tick.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass

import numpy as np

from ..control.attachment_kernel import PARAMETERS
from ..exceptions import ConcurrentUseError
from .base import Gait

__all__ = ["CoreTick", "NativeOutput", "spring_parameters"]


def spring_parameters(component: object) -> np.ndarray:
    """A spring-damper's six parameter arrays end to end (`PARAMETERS` order): a core's table."""
    return np.concatenate([getattr(component, name) for name in PARAMETERS]).astype(float)


@dataclass(slots=True)
class NativeOutput:
    """What a native tick answers (a [`ControlOutput`][]'s fields the walks read).

    Attributes:
        tau: ``(nv,)`` the efforts for the motors, clipped [N m or N].
        active: The state's attachments.
        wrenches: Each active attachment's requested wrench, on its axes.

    """

    tau: np.ndarray
    active: tuple[str, ...]
    wrenches: dict[str, np.ndarray]


class CoreTick:
    """A gait's tick in the compiled core: what the gaits' native ticks share.

    Subclasses build the core's object and define ``_compute`` (one tick), ``sync`` (the
    Python gait's objects brought up to the core's memory) and ``load`` (the Python gait's
    memory copied into the core, the machine's state in ``_state``). One object carries one
    walk's state: a call while another thread's is running raises
    [`ConcurrentUseError`][virtual_actuators.ConcurrentUseError].

    Args:
        gait: The gait, its machine started.
        core: The core's native gait (its ``nv``; a readings row of 18 floats per attachment:
            position, velocity, wrench on up to six axes).
        names: The controller's attachments, in the core's order.
        extra_rows: Readings rows after the attachments' (what else the core reports).

    Attributes:
        gait: As given.
        core: As given.
        deferred: Ticks the Python gait computed.
        tau: The last native tick's efforts (written by the core).
        readings: The last native tick's readings (written by the core).

    """

    def __init__(
        self, gait: Gait, core: object, names: tuple[str, ...], extra_rows: int = 0
    ) -> None:
        self.gait = gait
        self.core = core
        self.deferred = 0
        self._names = names
        machine = gait.machine
        index = {name: k for k, name in enumerate(names)}
        self._active = [machine.state(name).active for name in machine.names]
        self._rows = [[(name, index[name]) for name in active] for active in self._active]
        self._n = [len(gait.controller.attachments[name].actuator.axes) for name in names]
        self.tau = np.zeros(core.nv)
        self.readings = np.zeros((len(names) + extra_rows, 18))
        self._state = 0  # the machine's state, as an index of its names
        self._lock = threading.Lock()  # one tick at a time

    def compute(self, q: np.ndarray, v: np.ndarray, time: float, contacts=None) -> NativeOutput:
        """One tick: the efforts, the active attachments and their wrenches.

        Args:
            q: Configuration ``(nq,)`` (Pinocchio convention).
            v: Velocity ``(nv,)``.
            time: Controller time [s].
            contacts: Contact switches by frame (the gait's, when it reads them).

        Raises:
            ConcurrentUseError: Another thread is in a tick of this object.
            VirtualActuatorError: What the Python tick raises, when it runs.

        """
        if not self._lock.acquire(blocking=False):
            raise ConcurrentUseError(
                f"{self!r} is computing a tick in another thread: one walk's state, one thread "
                "at a time (build one native tick per walk)."
            )
        try:
            return self._compute(q, v, time, contacts)
        finally:
            self._lock.release()

    def _compute(self, q, v, time, contacts) -> NativeOutput:  # pragma: no cover - subclasses
        raise NotImplementedError

    def sync(self) -> None:  # pragma: no cover - every subclass defines it
        """Bring the Python gait's objects up to the core's memory."""
        raise NotImplementedError

    def load(self) -> None:  # pragma: no cover - every subclass defines it
        """Copy the Python gait's memory into the core."""
        raise NotImplementedError

    def answer(self) -> NativeOutput:
        """The native tick's output in the current state (the wrenches from `readings`)."""
        state, readings, wrenches = self._state, self.readings, {}
        for name, k in self._rows[state]:
            wrenches[name] = readings[k, 12 : 12 + self._n[k]].copy()
        return NativeOutput(self.tau.copy(), self._active[state], wrenches)

    def enter(self, state: int, time: float) -> None:
        """The Python machine enters ``state`` at ``time`` (as the core's did)."""
        machine = self.gait.machine
        self._state = state
        current = machine.state(machine.names[state])
        machine.current = current
        machine.entered_at = time
        machine.history.append((time, current.name))

    def python_tick(self, q, v, time, contacts) -> NativeOutput:
        """The tick the core handed on: the Python gait's, between two synchronisations.

        Raises:
            VirtualActuatorError: What the Python tick raises.

        """
        self.deferred += 1
        self.sync()
        try:  # the Python machine's tick: a compiled machine's registers do not follow this core's
            output = self.gait.last = self.gait.wiring.compute_in_python(q, v, time, contacts)
        finally:  # the core follows the Python gait, even past an error
            self.load()
        return NativeOutput(output.tau, output.active, output.wrenches)

    def __repr__(self) -> str:
        return (
            f"{type(self).__name__}({self.gait!r}, attachments={list(self._names)}, "
            f"deferred={self.deferred})"
        )
