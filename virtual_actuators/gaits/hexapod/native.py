"""The hexapod's tripod gait's whole tick in one compiled call: the core's ``NativeHexapod``.

`HexapodWalker.compute` is the reference: a kinematics pass, the state machine (the tripods'
stance and the double supports' timer) and the gait's callbacks, every active attachment (the
body's three components and its QP distribution on the support feet, each swing leg's
spring-damper), the sums and the clipping. `NativeTick` runs the same arithmetic in one call of
the core (``src/core/hexapod_tick.hpp`` and ``NativeHexapod`` in
``src/core/bind_native_hexapod.hpp``), bit for bit (``tests/test_native_hexapod.py``): a walk's
log is the same whichever runs.

The core holds a copy of the gait's memory (`MEMORY`: its machine's state, the tripod kernel's
state, the filters and set points, the components' set points) and shares the QP's workspace
and warm start with the Python distribution (the same arrays). A tick the core does not decide
runs in Python between two synchronisations (`sync`, then `load`): a tripod's entry (its
lift-off points), a QP whose last certified active set does not hold (DAQP or ProxQP solve it),
a value that is not finite. Without a pendulum, with ``distribution="qp"``, on a free-flyer body
only (`NativeTick.of` answers None otherwise).
"""

from __future__ import annotations

import numpy as np

from ...components.springs import SpringDamper
from ...core import CORE
from ...distribution.tolerances import ACTIVE_TOL, EPS_ABS, EXACT_TOL
from ...kinematics.tree import tree_of
from ..native_tick import CoreTick, NativeOutput, spring_parameters
from .body import HeadingAttitude, HeadingDamper
from .walker import LEGS, HexapodWalker

__all__ = ["MEMORY", "NativeTick"]

#: The gait's memory in the core, entry by entry (``NativeHexapod.memory()``); the tripod
#: kernel's swing table (``_swing``) besides it.
MEMORY = (
    "state", "entered_at", "support", "phase", "ground", *(f"kernel_{i}" for i in range(5)),
    "target_time", "filter_time", "velocity_body_x", "velocity_body_y", "filtered_x",
    "filtered_y", "setpoint_x", "setpoint_y", "acceleration_x", "acceleration_y",
    "planar_velocity_x", "planar_velocity_y", "planar_yaw", "attitude_yaw", "attitude_yaw_rate",
    "height_setpoint", *(f"leg_{i}_setpoint_{a}" for i in LEGS for a in "xyz"),
    *(f"leg_{i}_velocity_{a}" for i in LEGS for a in "xyz"),
)  # fmt: skip
#: ``HexapodParameters`` fields the core reads, in its order.
GAIT_VARIABLES = ("velocity_filter", "acceleration", "height", "touchdown_phase",
                  "double_support_time")  # fmt: skip
_SUPPORT = ("a", "b")


def read_memory(gait: HexapodWalker) -> tuple[np.ndarray, np.ndarray]:
    """The gait's memory as `MEMORY` floats, and its swing table (27 floats)."""
    machine = gait.machine
    values = [
        float(machine.names.index(machine.current.name)), float(machine.entered_at),
        float(_SUPPORT.index(gait.support)), float(gait.phase), float(gait.ground),
        *gait._state.tolist(), float(gait._target_time), float(gait._filter_time),
        *gait._velocity_body, *gait._velocity_filtered, *gait._setpoint, *gait._acceleration,
        *np.asarray(gait.planar.velocity, dtype=float).tolist(), float(gait.planar.yaw),
        float(gait.attitude.yaw), float(gait.attitude.yaw_rate), gait.height.setpoint.item(0),
    ]  # fmt: skip
    for name in ("setpoint", "velocity_setpoint"):
        for i in LEGS:
            values += getattr(gait.swing[i], name).tolist()
    return np.array(values, dtype=float), gait._swing.ravel().copy()


def write_memory(gait: HexapodWalker, values: np.ndarray, swing: np.ndarray) -> None:
    """Take up a memory of `read_memory` (the machine's state excepted: see `NativeTick`)."""
    memory = dict(zip(MEMORY, values.tolist(), strict=True))
    gait.support = _SUPPORT[int(memory["support"])]
    gait.phase, gait.ground = memory["phase"], memory["ground"]
    gait._state[:] = values[5:10]
    gait._swing[:] = swing.reshape(3, 9)
    gait._target_time, gait._filter_time = memory["target_time"], memory["filter_time"]
    gait._velocity_body = (memory["velocity_body_x"], memory["velocity_body_y"])
    gait._velocity_filtered = (memory["filtered_x"], memory["filtered_y"])
    setpoint = (memory["setpoint_x"], memory["setpoint_y"])
    if setpoint != gait._setpoint:
        gait._setpoint = setpoint
        gait.velocity_setpoint = np.array(setpoint)
    gait._acceleration = (memory["acceleration_x"], memory["acceleration_y"])
    planar = (memory["planar_velocity_x"], memory["planar_velocity_y"])
    if list(planar) != np.asarray(gait.planar.velocity, dtype=float).tolist():
        gait.planar.velocity = gait.velocity_setpoint
    gait.planar.yaw = memory["planar_yaw"]
    gait.attitude.yaw, gait.attitude.yaw_rate = memory["attitude_yaw"], memory["attitude_yaw_rate"]
    gait.height.setpoint = memory["height_setpoint"]
    legs = values[len(MEMORY) - 36 :].reshape(2, 6, 3)
    for k, i in enumerate(LEGS):
        gait.swing[i].setpoint = legs[0, k]
        gait.swing[i].velocity_setpoint = legs[1, k]


class NativeTick(CoreTick):
    """A `HexapodWalker`'s tick in the compiled core.

    Build one with `of` (None when the core cannot run this gait). It carries one walk's state:
    a call while another thread's is running raises
    [`ConcurrentUseError`][virtual_actuators.ConcurrentUseError].

    Attributes:
        gait: The walker (its Python objects follow the core's memory, see the module).
        deferred: Ticks the Python gait computed.

    """

    def __init__(self, gait: HexapodWalker, core: object, names: tuple[str, ...],
                 bodies: dict[int, tuple], legs: dict[int, SpringDamper]) -> None:  # fmt: skip
        super().__init__(gait, core, names)
        self._bodies = bodies  # core index -> (QP distribution, keep, workspace)
        self._legs = legs  # core index -> the swing leg's spring-damper
        self._command = np.zeros(3)
        self._switches: object = None  # the last contacts dict (its array: _contacts)
        self._contacts = np.zeros(0, dtype=np.int64)
        self._guesses: list = []

    @classmethod
    def of(cls, gait: object) -> NativeTick | None:
        """The native tick of ``gait``, or None.

        None: no compiled core, not a `HexapodWalker`, a machine not started yet, an effort
        rate limit, a pendulum,
        a body that is not the free flyer's frame, ``distribution="partitioned"``, attachments
        other than the walker's own, or frames outside the tick's frame table.
        """
        if CORE is None or not hasattr(CORE, "NativeHexapod") or type(gait) is not HexapodWalker:
            return None
        controller, p = gait.controller, gait.parameters
        if not gait.machine.started or not controller.clip or controller.postures:
            return None
        if controller.effort_rate_limit is not None:  # the Python tick limits the rate
            return None
        if gait.pendulum is not None or not gait._body_is_root or p.distribution != "qp":
            return None
        tree = tree_of(gait.robot)
        frames = ("body", *(f"foot_{i}" for i in LEGS))
        rows = [tree.name_rows.get(frame, -1) for frame in frames]
        if tree.core_tree is None or min(rows) < 0 or not _plain_body(gait):
            return None
        core = CORE.NativeHexapod(
            tree.core_tree, np.array(rows, dtype=np.int64),
            np.array([float(getattr(p, name)) for name in GAIT_VARIABLES]),
            np.ascontiguousarray(gait._nominal_feet, dtype=float),
            np.ascontiguousarray(gait._shape, dtype=float), _body_constants(gait),
            np.array((ACTIVE_TOL, EXACT_TOL, EPS_ABS)),
            -np.asarray(controller.effort_limits, dtype=float),
            np.asarray(controller.effort_limits, dtype=float),
        )  # fmt: skip
        names = tuple(controller.attachments)
        bodies: dict[int, tuple] = {}
        legs: dict[int, SpringDamper] = {}
        q = gait.robot.neutral()
        for k, name in enumerate(names):
            added = _add_attachment(core, gait, name, q)
            if added is None:
                return None
            if isinstance(added, SpringDamper):
                legs[k] = added
            else:
                bodies[k] = added
        for state in gait.machine.names:
            declared = gait.machine.state(state)
            core.add_state(
                np.array([names.index(name) for name in declared.active], dtype=np.int64),
                np.asarray(controller.joint_indices(declared.limp), np.int64),
            )
        native = cls(gait, core, names, bodies, legs)
        native.load()
        return native

    def _compute(self, q: np.ndarray, v: np.ndarray, time: float, contacts) -> NativeOutput:
        gait, core = self.gait, self.core
        command = self._command
        command[:2] = gait.velocity
        command[2] = gait.yaw_rate
        if contacts is not self._switches:  # the episode's dict is the same while they hold
            self._switches = contacts
            self._contacts = (
                np.zeros(0, dtype=np.int64) if contacts is None else np.array(
                    [bool(contacts.get(f, False)) for f in gait.contact_frames], dtype=np.int64
                )
            )  # fmt: skip
        status = core.tick(q, v, time, command, self._contacts, self.tau, self.readings)
        if status < 0:  # DEFER
            return self.python_tick(q, v, time, contacts)
        if status:  # ENTERED
            self.enter(core.state, time)
        return self.answer()

    def sync(self) -> None:
        """Bring the Python gait's objects up to the core's memory.

        The QPs' warm starts are the Python distributions' own arrays; a native tick solves
        on the last certified active set, without ProxQP iterations.
        """
        write_memory(self.gait, self.core.memory(), self.core.swing())
        for qp, _, _ in self._bodies.values():
            qp._local.iterations = 0

    def load(self) -> None:
        """Copy the Python gait's memory, its components' constants and warm starts to the core."""
        values, swing = read_memory(self.gait)
        self._state = int(values[0])
        self.core.set_memory(values, swing)
        self.core.set_body(_body_constants(self.gait))
        for index, leg in self._legs.items():
            self.core.set_swing(index, spring_parameters(leg))
        guesses = []  # the arrays the core writes in place, kept alive until the next load
        for index, (qp, keep, work) in self._bodies.items():
            hot, slot = qp._hot(keep)
            guess = slot.active if hot is work else None  # another thread's: Python decides
            self.core.set_guess(index, guess)
            guesses.append(guess)
        self._guesses = guesses


def _plain_body(gait: HexapodWalker) -> bool:
    """The body's components as the walker made them (the core's formulas)."""
    height = gait.height
    return (
        type(height) is SpringDamper and not height._limited and type(gait.planar) is HeadingDamper
        and type(gait.attitude) is HeadingAttitude and all(
            type(gait.swing[i]) is SpringDamper and not gait.swing[i]._limited for i in LEGS
        )
    )  # fmt: skip


def _body_constants(gait: HexapodWalker) -> np.ndarray:
    """The body's components' constants in the core's order (``Body`` in hexapod_tick.hpp)."""
    height, planar, attitude = gait.height, gait.planar, gait.attitude
    return np.array([
        height.stiffness.item(0), height.damping.item(0), height.velocity_setpoint.item(0),
        height.force.item(0), *np.asarray(planar.damping, dtype=float).tolist(),
        *np.asarray(planar.force, dtype=float).tolist(), *attitude.stiffness.tolist(),
        *attitude.damping.tolist(), float(attitude.roll), float(attitude.pitch),
    ])  # fmt: skip


def _add_attachment(core: object, gait: HexapodWalker, name: str, q: np.ndarray):
    """Declare an attachment to the core.

    Returns:
        None: the core cannot run it; a swing leg's spring-damper; a support attachment's
        ``(QP distribution, keep, workspace)``.

    """
    attachment = gait.controller.attachments[name]
    if name.startswith("swing_"):
        leg = int(name.split("_")[1])
        tick = attachment.spring_tick
        if (tick is None or tick.core is None or not tick.efforts
                or attachment.components != [gait.swing[leg]]):  # fmt: skip
            return None
        core.add_swing(tick.core, leg - 1, spring_parameters(gait.swing[leg]))
        return gait.swing[leg]
    body = [gait.height, gait.planar, gait.attitude]
    if attachment.components != body or attachment.yield_mask is not None:
        return None
    actuator, request = attachment.actuator, attachment.plan
    qp = actuator.backends.get("qp")
    if request is None or request.method != "qp" or not request.compiled or qp is None:
        return None
    if actuator.axes != ("x", "y", "z", "rx", "ry", "rz") or qp.matrices.core is None:
        return None
    if not qp.matrices.applicable or attachment.sensor.axes != actuator.axes:
        return None
    kinematics, nf = attachment.sensor.kinematics, tree_of(gait.robot).core_tree.nf
    if max(int(kinematics.frame_rows[:3].max()), qp.matrices._max_row) >= nf:
        return None  # frames outside the tick's table: the Python tick places them
    work, _ = qp._hot(request.keep)
    core.add_body(
        np.asarray(kinematics.rows, dtype=np.int64),
        np.ascontiguousarray(kinematics.frame_rows[:3], dtype=np.int64),
        np.ascontiguousarray(kinematics.chain_columns[0], dtype=np.int64),
        np.ascontiguousarray(kinematics.chain_signs[0], dtype=float),
        qp.matrices.core, q, work.buffer, work.layout, work.kept,
        np.asarray(request.keep, dtype=np.int64), qp._weights(request),
    )  # fmt: skip
    return qp, request.keep, work
