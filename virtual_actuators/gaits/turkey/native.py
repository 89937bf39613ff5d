"""Turkey walking's whole tick in one compiled call: the compiled core's ``NativeTurkey``.

`TurkeyWalker.compute` is the reference: a kinematics pass, the
state machine (Table 1's events and the gait's callbacks), the components' resets, every active
attachment (its spring-dampers and distribution), the sums, the limp joints and the clipping,
about 150 Python calls per tick. `NativeTick` runs the same arithmetic in one call of the core
(``src/core/turkey.hpp`` and ``NativeTurkey`` in ``src/core/bind_native_turkey.hpp``), bit for
bit (``tests/test_native_turkey.py``): a walk's log is the same whichever runs.

The core holds a copy of the gait's memory (its state, the swing's start, the ground, the
components' set points); the Python objects are brought up to date when the machine changes state
(its ``current``, ``entered_at`` and ``history``) and by `sync`. A tick the core does not decide
(a non-finite state, a kernel that hands the tick on, a double support whose request must be
scaled on its yield axes) runs in Python, between two synchronisations: the Python gait then
carries on exactly as if it had computed every tick.

The runner (`drive`) uses it when nothing reads the
controller's per-tick [`ControlOutput`][] (no ``on_tick`` callback): the native tick answers a
`NativeOutput` (the efforts, the active attachments and their wrenches), not a full output;
the gait's ``last`` stays the last [`ControlOutput`][] its Python tick computed.
"""

from __future__ import annotations

import numpy as np

from ...components.walking import DogtrackBunny, GrannyWalker, SwingLegLinkage
from ...control.attachment_kernel import PARAMETERS
from ...kinematics.tree import tree_of
from ...native import CORE
from ..native_tick import CoreTick, NativeOutput, spring_parameters
from .walker import TurkeyWalker

__all__ = ["NativeOutput", "NativeTick"]

#: The gait's memory in the core, entry by entry (``NativeTurkey.memory()``).
MEMORY = (
    "state", "entered_at", "front", "swing_start_x", "swing_start_z", "progress_start",
    "ground", "granny_height", "bunny_start_position", "bunny_start_time", "left_swing_x",
    "left_swing_z", "right_swing_x", "right_swing_z", "bunny_setpoint",
)  # fmt: skip
#: ``TurkeyParameters`` fields the core reads, in its order.
GAIT_VARIABLES = (
    "over_distance", "away_distance", "buffer_delay", "height", "foot_radius", "swing_reach",
    "lift_peak", "lift", "touchdown_depth",
)  # fmt: skip
_SIDES = ("left", "right")
_GRANNY, _BUNNY, _LEFT_SWING, _RIGHT_SWING = range(1, 5)  # 0: a plain spring-damper
_VELOCITY_SETPOINT = PARAMETERS.index("velocity_setpoint")


def _role(gait: TurkeyWalker, component: object) -> int | None:
    """The component's slot role, None for one the core does not run."""
    kind = type(component)
    if kind is GrannyWalker and component is gait.granny:
        return _GRANNY
    if kind is DogtrackBunny and component is gait.bunny:
        return _BUNNY
    if kind is SwingLegLinkage:
        for side in _SIDES:
            if component is gait.swing[side]:
                return _LEFT_SWING if side == "left" else _RIGHT_SWING
    return None


class NativeTick(CoreTick):
    """A `TurkeyWalker`'s tick in the compiled core.

    Build one with `of` (None when the core cannot run this gait). It carries one walk's state:
    a call while another thread's is running raises
    [`ConcurrentUseError`][virtual_actuators.ConcurrentUseError].

    Attributes:
        gait: The walker (its Python objects follow the core's memory, see the module).
        deferred: Ticks the Python gait computed.

    """

    def __init__(self, gait: TurkeyWalker, core: object, names: tuple[str, ...], slots) -> None:
        # the readings' last row: the granny walker's height set point
        super().__init__(gait, core, names, extra_rows=1)
        self._slots = slots  # (component, slot index) of each component

    @classmethod
    def of(cls, gait: object) -> NativeTick | None:
        """The native tick of ``gait``, or None.

        None: no compiled core, not a `TurkeyWalker`, a machine not started yet (its first tick
        runs in Python), an effort rate limit, an attachment without the core's one-call tick
        (a QP distribution, another component), or frames outside the tick's frame table.
        """
        if CORE is None or not hasattr(CORE, "NativeTurkey") or type(gait) is not TurkeyWalker:
            return None
        controller = gait.controller
        if not gait.machine.started or not controller.clip or controller.postures:
            return None
        if controller.effort_rate_limit is not None:  # the Python tick limits the rate
            return None
        tree = tree_of(gait.robot)
        core_tree = tree.core_tree
        rows = [tree.name_rows.get(frame, -1) for frame in ("body", "left_foot", "right_foot")]
        if core_tree is None or min(rows) < 0:
            return None
        controller, p = gait.controller, gait.parameters
        core = CORE.NativeTurkey(
            core_tree,
            np.array(rows, dtype=np.int64),
            np.array([float(getattr(p, name)) for name in GAIT_VARIABLES]),
            -np.asarray(controller.effort_limits, dtype=float),
            np.asarray(controller.effort_limits, dtype=float),
        )
        slots: dict[int, tuple[object, int]] = {}
        names = tuple(controller.attachments)
        for name in names:
            if not _add_attachment(core, gait, controller.attachments[name], slots):
                return None
        for state in gait.machine.names:
            active = gait.machine.state(state).active
            core.add_state(
                np.array([names.index(name) for name in active], dtype=np.int64),
                np.asarray(controller.joint_indices(gait.machine.state(state).limp), np.int64),
            )
        native = cls(gait, core, names, tuple(slots.values()))
        native.load()
        return native

    def _compute(self, q: np.ndarray, v: np.ndarray, time: float, contacts) -> NativeOutput:
        status = self.core.tick(q, v, time, self.tau, self.readings)
        if status < 0:  # DEFER
            return self.python_tick(q, v, time, contacts)
        if status:  # ENTERED
            self.enter(self.core.state, time)
            self.sync()
        self.gait.granny.height = self.readings.item(-1, 0)  # what a walk's record reads
        return self.answer()

    def sync(self) -> None:
        """Bring the Python gait's objects up to the core's memory."""
        gait = self.gait
        gait.restore(dict(zip(MEMORY, self.core.memory().tolist(), strict=True)))
        for side in _SIDES:
            swing = gait.swing[side]
            values = self.core.slot(self._slot_of(swing))
            swing.velocity_setpoint = np.split(values, len(PARAMETERS))[_VELOCITY_SETPOINT]

    def load(self) -> None:
        """Copy the Python gait's memory and components' parameters into the core."""
        gait = self.gait
        machine = gait.machine
        memory = gait.memory()
        memory["state"] = self._state = machine.names.index(machine.current.name)
        memory["entered_at"] = machine.entered_at
        self.core.set_memory(np.array([float(memory[name]) for name in MEMORY]))
        for component, slot in self._slots:
            self.core.set_slot(slot, spring_parameters(component))

    def _slot_of(self, component: object) -> int:
        return next(slot for c, slot in self._slots if c is component)


def _add_attachment(core: object, gait: TurkeyWalker, attachment, slots: dict) -> bool:
    """Declare an attachment to the core (its components as slots); False if it cannot run."""
    tick = attachment.spring_tick
    if tick is None or tick.core is None:
        return False
    serial = tick.efforts
    if not serial and tick.fused is None:
        return False
    indices, resets = [], []
    for component, axes in zip(attachment.components, attachment.indices, strict=True):
        role = _role(gait, component)
        if role is None:
            return False
        if id(component) not in slots:
            slots[id(component)] = (component, core.add_slot(spring_parameters(component), role))
        indices.append(slots[id(component)][1])
        resets.append(int(np.asarray(axes).reshape(-1)[0]) if role == _BUNNY else -1)
    yields = attachment.yield_mask is not None
    if yields and attachment.margins is None:
        return False
    if yields:
        points, axis_rows, minima_axes, lows = attachment.margins
        orientation = attachment.actuator.kinematics.orientation_rows
    else:
        points, axis_rows, minima_axes, lows = np.zeros((0, 7)), _NONE, _NONE, np.zeros(0)
        orientation = _NONE
    core.add_attachment(
        tick.core,
        None if serial else tick.fused,
        np.array(indices, dtype=np.int64),
        np.array(resets, dtype=np.int64),
        yields,
        np.asarray(attachment.yield_mask if yields else _NONE, dtype=np.int64),
        np.asarray(orientation, dtype=np.int64),
        np.ascontiguousarray(points, dtype=float).reshape(-1, 7),
        np.asarray(axis_rows, dtype=np.int64),
        np.asarray(minima_axes, dtype=np.int64),
        np.asarray(lows, dtype=float),
    )
    return True


_NONE = np.zeros(0, dtype=np.int64)
