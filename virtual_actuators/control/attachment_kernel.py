"""A spring-damper attachment's sensing and wrench (and a serial one's efforts) in one call."""

from __future__ import annotations

from operator import attrgetter

import numpy as np

from ..actuators import VirtualActuator
from ..components.orientation import rotation_axes
from ..components.springs import Spring, SpringDamper
from ..components.walking import DogtrackBunny
from ..core import CORE, has
from ..distribution.partitioned.compiled import BufferSolve
from ..distribution.result import Solution
from ..kinematics.snapshot import Snapshot

#: The wrenches that are the spring-damper formula itself (the bunny moves its set point first)
_FORMULA = (
    SpringDamper.compute_wrench,
    Spring.compute_wrench,
    DogtrackBunny.compute_wrench,
)
#: A spring-damper's six parameter arrays (the core's rows, in its order) in one call
_read_parameters = attrgetter(*(f"_{name}" for name in SpringDamper.SLOTS))


def _served(component: object) -> bool:
    """Whether ``component`` is a spring-damper of the formula, with one rotational axis at most."""
    klass = type(component)
    if not isinstance(component, SpringDamper) or klass.compute_wrench not in _FORMULA:
        return False
    rotations = rotation_axes(component.axes)
    return not rotations or len(rotations.which) == 1


class SpringTick:
    """The one-call sensing and wrench of an attachment of spring-dampers (and serial efforts).

    ``starts``: each component's first axis (its axes a contiguous run); ``efforts``: the tick
    computes ``J^T w`` (the actuator is the sensor); ``solve``: a parallel actuator's one-call
    distribution, or None.
    """

    def __init__(
        self,
        sensor: VirtualActuator,
        components: list,
        starts: list[int],
        efforts: bool,
        solve: BufferSolve | None = None,
    ) -> None:
        kinematics = sensor.kinematics
        self.components = list(components)
        #: the bunnies, whose set point follows the time (their wrench moves it first)
        own = DogtrackBunny.compute_wrench
        self.bunnies = tuple(c for c in components if type(c).compute_wrench is own)
        #: the springs that may be given a law (then the general path runs)
        self.springs = tuple(c for c in components if isinstance(c, Spring))
        self.efforts = efforts
        self.nv, self.n = kinematics.nv, len(sensor.axes)
        nv, n = self.nv, self.n
        #: the buffer's position, velocity and wrench, and the efforts (None: not computed)
        self.slices = (
            slice(nv, nv + n),
            slice(nv + n, nv + 2 * n),
            slice(nv + 2 * n, nv + 3 * n),
            slice(0, nv) if efforts else None,
        )
        targets, rotations = [], []
        for component, start in zip(components, starts, strict=True):
            size = len(component.axes)
            turning = rotation_axes(component.axes)
            targets += range(start, start + size)
            rotations += [int(turning is not None and k == turning.start) for k in range(size)]
        summed = not (len(components) == 1 and starts[0] == 0 and len(targets) == self.n)
        self.rows_end = kinematics.sensor_rows_end
        self.tables = (
            *kinematics.sensor_tables,
            np.array(targets, dtype=np.int64),
            np.array(rotations, dtype=np.int64),
            int(summed),
            int(efforts),
        )
        self.core = CORE.SpringTick(*self.tables, self.nv)
        #: a parallel actuator's one-call distribution (None: serial, or none compiled)
        self.solve = solve if not efforts else None
        self.fused = None if self.solve is None else CORE.SpringSolve(self.core, *solve.packed)

    @classmethod
    def of(
        cls,
        actuator: object,
        sensor: object,
        components: list,
        slots: list,
        solve: BufferSolve | None = None,
    ) -> SpringTick | None:
        """The tick for an attachment of spring-dampers of the formula it serves, else None."""
        serial = isinstance(actuator, VirtualActuator)
        served = (
            has("SpringTick")
            and components
            and type(sensor) is VirtualActuator
            and not (serial and (type(actuator) is not VirtualActuator or actuator is not sensor))
            and all(isinstance(slot, slice) for slot in slots)
            and all(map(_served, components))
            and len(sensor.kinematics.reaction_ids) == 1
        )
        if not served:
            return None
        return cls(sensor, components, [slot.start for slot in slots], serial, solve)

    def warm_up(self, snapshot: Snapshot) -> None:
        """Call the kernel once on the components' parameters now (its result thrown away)."""
        if snapshot.v is None or snapshot.frame_table.shape[0] < self.rows_end:
            return
        parameters = [array for c in self.components for array in _read_parameters(c)]
        arguments = (snapshot.jacobian_world, snapshot.frame_table, snapshot.v)
        self.core.tick(*arguments, parameters)

    def run_solve(
        self, components: list, snapshot: Snapshot, time: float, solve: bool = True
    ) -> tuple[np.ndarray | None, Solution | None]:
        """The tick, and with a distribution (``solve``) its solution, in one compiled call.

        Returns:
            ``(buffer, solution)``: the buffer ``effort (nv), position (n), velocity (n), wrench
            (n), flag (1.0)``, or None (the general path runs); the distribution's
            [`Solution`][virtual_actuators.Solution], bit for bit the one of
            ``solve(snapshot, wrench)``, or None.
        """
        v = snapshot.v
        if (
            components != self.components
            or v is None
            or any(getattr(spring, "law", None) is not None for spring in self.springs)
            or snapshot.frame_table.shape[0] < self.rows_end
        ):
            return None, None
        jacobian_world, frames = snapshot.jacobian_world, snapshot.frame_table
        for bunny in self.bunnies:  # as its compute_wrench does before the formula
            bunny.setpoint = bunny.position_at(time)
        if len(components) == 1:
            parameters = _read_parameters(components[0])
        else:
            parameters = [array for c in components for array in _read_parameters(c)]
        fused = self.fused if solve else None
        if fused is not None:
            buffer, out, residual, scale, rounding, status = fused.tick(
                jacobian_world, frames, v, snapshot.q, parameters
            )
            if buffer[-1] != 1.0:
                return None, None
            if status:
                return buffer, None
            return buffer, self.solve.solution(out, residual, scale, rounding, 1e-6)
        buffer = self.core.tick(jacobian_world, frames, v, parameters)
        return (buffer if buffer[-1] == 1.0 else None), None
