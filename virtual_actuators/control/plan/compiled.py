"""The compiled machine: a lowered MachineController run by the core, one call a tick.

The Python pieces run from inside the core's tick, on its snapshot and context (built on use);
a tick's [`PlanOutput`][] is read from the plan's registers on demand.
"""

from __future__ import annotations

import threading
from collections.abc import Mapping
from types import MappingProxyType

import numpy as np

from ...core import CORE, has
from ...exceptions import ConcurrentUseError, InvalidInputError
from ...kinematics.snapshot import Snapshot
from ...vocabulary.arguments import check_number
from ..context import Context
from ..tick import ControlOutput
from .builder import MACHINE
from .entries import Attached, Entry, Term
from .lower import Lowering

_FLOAT64, _ARRAY = np.dtype(np.float64), np.ndarray
_TICKED, _ENTERED, _FAILED, _INVALID = (
    (CORE.PLAN_TICKED, CORE.PLAN_ENTERED, CORE.PLAN_FAILED, CORE.PLAN_INVALID)
    if has("PLAN_INVALID") else (0, 1, 2, 3)
)  # fmt: skip


class CompiledMachine:
    """A MachineController lowered into the core (see the module docstring).

    Args:
        machine: The machine controller (its controller's components and the gait's memory
            are bound to the plan's registers: they read and write them from now on).

    Attributes:
        pieces: ``(what, why)`` of each piece that runs in Python.
        registers: The plan's registers (a view of the core's).

    Raises:
        TraceError: The compiled core is not built, or the robot's joints are not the core's.
    """

    def __init__(self, machine: object) -> None:
        self.machine = machine
        controller = machine.controller
        self.robot = controller.robot
        self.joint_names = controller.joint_names
        lowering = self.lowering = Lowering(machine)
        lowering.runtime = self
        # the machine's state (index, entered at, started) in registers MACHINE.. MACHINE+2
        lowering.owners.append((machine.machine, {"position": (MACHINE, 3)}))
        used = {name for state in machine.machine.states for name in state.active}
        names = [n for n in (*controller.attachments, *controller.postures) if n in used]
        self._index = {name: i for i, name in enumerate(names)}
        postures, attachments = controller.postures, controller.attachments
        self._entries = [
            Term(self, n, postures[n], lowering)
            if n in postures
            else Attached(self, n, attachments[n], lowering)
            for n in self._index
        ]
        states = [self._lower_state(state) for state in machine.machine.states]
        tree = lowering.tree
        self._rows = dict(tree.frame_tables[0])  # the plan's frame table, final now
        registers, ops, bounds = lowering.builder.assemble()
        _, parents, floats = tree.frame_tables
        limits = controller.effort_limits if controller.clip else np.full(tree.nv, np.inf)
        limits = np.asarray(limits, dtype=float)
        self.core = CORE.PlanMachine(
            *tree.joint_tables, parents, np.ascontiguousarray(floats).reshape(-1, 12), tree.nq,
            registers, ops, bounds, -limits, limits, tree.unit_bounds,
        )  # fmt: skip
        self.core.set_masses(tree.masses, np.ascontiguousarray(tree.levers))
        for entry in self._entries:
            entry.declare(self.core)
        for attachments, limp, enter, update, _ in states:
            self.core.add_state(attachments, limp, enter, update)
        for index, (_, _, _, _, exits) in enumerate(states):
            for program, result, target in exits:
                self.core.add_exit(index, program, result, target)
        self.core.set_initial(machine.machine.index[machine.machine.initial])
        self.core.set_callbacks(list(lowering.callbacks))
        self.registers = self.core.registers()
        self.requested = self.core.requested()  # the last tick's unclipped sum (a view)
        for owner, layout in lowering.owners:
            views = {name: self.registers[b : b + s] for name, (b, s) in layout.items()}
            if owner is machine.machine:
                owner.bind_position(views["position"])
            else:
                owner.bind_slots(views)
        for entry in self._entries:
            entry.bind(self.core)
        self.pieces = lowering.pieces
        self._contacts = [(f, r, required) for f, (r, required) in lowering.contacts.items()]
        self._tau = np.zeros(tree.nv)
        self._free = np.zeros(tree.nv, dtype=bool)  # no entry held by the rate limit
        self._free.flags.writeable = False
        self._limit_rate = controller.limit_rate
        self.layouts: dict[tuple, list] = {}  # PlanOutput's readings per (active, what)
        self._tick: tuple | None = None  # (q, v, time, contacts) of the tick running
        self._snapshot: Snapshot | None = None
        self._context: Context | None = None
        self._lock = threading.Lock()  # one tick at a time: the registers are one run's state

    def _lower_state(self, state: object) -> tuple:
        lowering, machine = self.lowering, self.machine.machine
        attachments = np.array([self._index[name] for name in state.active], dtype=np.int64)
        limp = np.asarray(self.machine.limp[state.name], dtype=np.int64)
        enter = lowering.hook(state.name, "on_enter", state.on_enter)
        update = lowering.hook(state.name, "on_update", state.on_update)
        exits = []
        for event, target in machine.exits(state.name):
            program, result = lowering.exit(state.name, event)
            exits.append((program, result, machine.index[target.name]))
        return attachments, limp, enter, update, exits

    def snapshot(self) -> Snapshot:
        """The snapshot of the tick running (for the Python pieces), built on first use."""
        if self._snapshot is None:
            q, v, _, _ = self._tick
            self._snapshot = Snapshot.of_pass(self.robot, q, v, self.core.pass_buffer(), self._rows)
        return self._snapshot

    def context(self) -> Context:
        """The context of the tick running (for the Python pieces), built on first use."""
        context = self._context
        if context is None:
            _, _, time, contacts = self._tick
            context = self._context = Context.of_tick(self.robot, self.snapshot(), time, contacts)
        context.state = self.machine.machine.current.name  # the state now (a piece may follow
        context.time_in_state = self.registers.item(1)  # a transition in the same tick)
        return context

    def compute(
        self,
        q: np.ndarray | Snapshot,
        v: np.ndarray | None,
        time: float,
        contacts: Mapping[str, bool] | None = None,
    ) -> ControlOutput:
        """One tick: [`MachineController.compute`][virtual_actuators.MachineController.compute].

        Raises:
            InvalidInputError: Bad ``q``, ``v``, ``time`` or ``contacts``, or a contact switch
                an event reads that ``contacts`` lacks.
            ConcurrentUseError: Another thread is in a tick of this machine.
        """
        if not self._lock.acquire(blocking=False):
            raise ConcurrentUseError(
                f"{self!r} is computing a tick in another thread: one run's state, one thread at "
                "a time (build one gait or machine per thread)."
            )
        try:
            if q.__class__ is Snapshot:
                q, v = q.q, q.v
            if not (
                q.__class__ is _ARRAY and v.__class__ is _ARRAY and q.dtype is _FLOAT64
                and v.dtype is _FLOAT64 and time.__class__ is float
            ):  # fmt: skip
                q, v, time = self._checked(q, v, time)  # the typed errors, or q normalised
            switches, registers = contacts or {}, self.registers
            for frame, register, required in self._contacts:  # the switches into the registers
                closed = switches.get(frame)
                if closed is None and required:
                    raise InvalidInputError(
                        f"No contact switch for {frame!r}: the machine's events read it."
                    )
                registers[register] = 1.0 if closed else 0.0
            self._tick, self._snapshot, self._context = (q, v, time, switches), None, None
            core, tau = self.core, self._tau
            try:  # the core checks the sizes (and copies a strided array)
                outcome = core.tick(q, v, time, tau)
            except (TypeError, ValueError):
                outcome = _INVALID
            if outcome == _INVALID:  # what the core does not accept as it is: the Python checks
                q, v, time = self._checked(q, v, time)
                self._tick = (q, v, time, switches)
                outcome = core.tick(q, v, time, tau)
            machine = self.machine
            if outcome == _FAILED:  # the Python tick decides (the failure policy), same state
                return machine.compute_in_python(self.snapshot(), None, time, contacts)
            state = machine.machine.current
            if outcome == _ENTERED:
                machine.machine.history.append((time, state.name))
            tau, held = self._limit_rate(tau.copy(), time)
            output = PlanOutput(self, state.active, tau, self._free if held is None else held)
            machine.last = output
            return output
        finally:
            self._lock.release()

    def _checked(self, q: object, v: object, time: object) -> tuple:
        """``(q, v, time)`` as the Python checks take them (raising their typed errors)."""
        tree = self.lowering.tree
        time = check_number(time, "time [s]")
        return tree.check_configuration(q), tree.check_velocity(v), time

    @property
    def time(self) -> float:
        """The time of the tick running [s]."""
        return self._tick[2]

    def entry(self, name: str) -> Entry:
        """The lowered attachment or term ``name``."""
        return self._entries[self._index[name]]

    def __repr__(self) -> str:
        return (
            f"CompiledMachine(state={self.machine.machine.current.name!r}, "
            f"{len(self.pieces)} Python pieces)"
        )


class PlanOutput:
    """One compiled tick's output (see the module docstring).

    Args:
        active: The names evaluated this tick.
        tau: The tick's efforts after the limp joints and the clip [N m or N].
        held: ``(nv,)`` bool, True where the effort rate limit held the effort back.
    """

    __slots__ = ("_cache", "_compiled", "active", "rate_limited", "tau", "tau_requested")

    #: A compiled tick has no failures (a failing tick is the Python machine's).
    failed: Mapping[str, str] = MappingProxyType({})
    failures: Mapping[str, object] = MappingProxyType({})

    def __init__(
        self, compiled: object, active: tuple[str, ...], tau: np.ndarray, held: np.ndarray
    ) -> None:
        self._compiled = compiled
        self.active = active
        self.tau = tau
        self.tau_requested = compiled.requested.copy()
        self.rate_limited = held
        self._cache: dict[str, dict] = {}

    @property
    def joint_names(self) -> tuple[str, ...]:
        """Names of the velocity entries."""
        return self._compiled.joint_names

    @property
    def saturated(self) -> np.ndarray:
        """``(nv,)`` True where the request exceeds the effort limit."""
        limits = self._compiled.machine.controller.effort_limits
        return np.abs(self.tau_requested) > limits

    def _readings(self, what: str) -> dict[str, np.ndarray]:
        cached = self._cache.get(what)
        if cached is None:
            compiled, key = self._compiled, (self.active, what)
            layout = compiled.layouts.get(key)
            if layout is None:  # each reading's span in one gather, once per active set
                entries = [(name, compiled.entry(name)) for name in self.active]
                entries = [(n, e) for n, e in entries if e.reports]  # a term has no wrench
                index = [getattr(e, what) + i for _, e in entries for i in range(e.n)]
                bounds = np.cumsum([0] + [e.n for _, e in entries]).tolist()
                spans = [(n, bounds[k], bounds[k + 1]) for k, (n, _) in enumerate(entries)]
                layout = compiled.layouts[key] = (np.array(index, dtype=np.intp), spans)
            index, spans = layout
            values = compiled.registers.take(index)  # a copy: the next tick leaves it alone
            cached = self._cache[what] = {name: values[a:b] for name, a, b in spans}
        return cached

    def wrench_of(self, name: str) -> np.ndarray | None:
        """The requested wrench of attachment ``name`` (a copy), None when it is not active."""
        cached = self._cache.get("wrench")
        if cached is not None:
            return cached.get(name)
        if name not in self.active:
            return None
        entry = self._compiled.entry(name)
        if not entry.reports:
            return None
        return self._compiled.registers[entry.wrench : entry.wrench + entry.n].copy()

    @property
    def wrenches(self) -> dict[str, np.ndarray]:
        """Requested wrench per active attachment, on its actuator's axes."""
        return self._readings("wrench")

    @property
    def produced(self) -> dict[str, np.ndarray]:
        """Wrench produced per active attachment."""
        return self._readings("produced")

    @property
    def positions(self) -> dict[str, np.ndarray]:
        """Sensor position per active attachment [m, rad]."""
        return self._readings("position")

    @property
    def velocities(self) -> dict[str, np.ndarray]:
        """Sensor velocity per active attachment [m/s, rad/s]."""
        return self._readings("velocity")

    @property
    def solutions(self) -> dict:
        """The distribution's solution per active parallel attachment."""
        cached = self._cache.get("solutions")
        if cached is None:
            solved = ((name, self._compiled.entry(name).solved_solution()) for name in self.active)
            cached = self._cache["solutions"] = {n: s for n, s in solved if s is not None}
        return cached

    saturated_joints = ControlOutput.saturated_joints  # read the same fields by name
    rate_limited_joints = ControlOutput.rate_limited_joints

    def __repr__(self) -> str:
        return (
            f"PlanOutput(active={self.active}, |tau|={np.linalg.norm(self.tau):.3g}, "
            f"saturated={self.saturated_joints})"
        )
