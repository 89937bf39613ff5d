"""A serial spring-damper attachment's whole tick in one compiled call.

An attachment of a serial [`VirtualActuator`][] that is its own sensor,
with one [`SpringDamper`][] on all its axes (a swing leg's spring-damper),
needs per tick: the sensor's reading (`sense`), the spring-damper's wrench (its float path,
[`compute_wrench_floats`][virtual_actuators.SpringDamper.compute_wrench_floats]) and the efforts
``J^T w``.
`spring_damper_tick` does the three in one call, the same operations in the same order
as those (``J^T w`` as a sum over the axes in order, where the controller's general path lets
numpy's ``J.T @ w`` round its own way). It is the reference of the compiled core's C++ port
(``src/core/attachment.hpp``), which `SerialSpringTick` calls when the core is built:
both agree bit for bit (``tests/test_attachment_kernel.py``), and an edit here goes with the
same edit there.

The tick hands the general path back (flag 0 in its buffer) when the spring's one rotational
axis has a difference outside ``[-pi, pi]`` (the float path wraps it) or the wrench is not
finite (the general path names the component).
"""

from __future__ import annotations

import numpy as np

from ..actuators import VirtualActuator
from ..components.orientation import rotation_axes
from ..components.springs import Spring, SpringDamper
from ..kinematics.kernels import HAVE_NUMBA, njit
from ..kinematics.sensor_kernels import relative_sensor
from ..kinematics.snapshot import Snapshot
from ..native import CORE

__all__ = ["SerialSpringTick", "spring_damper_tick"]

#: The classes whose wrench is the spring-damper formula itself (a Spring: without a law).
_FORMULA = (SpringDamper.compute_wrench, Spring.compute_wrench)


@njit(cache=True)
def spring_damper_tick(
    jacobian_world: np.ndarray,
    frames: np.ndarray,
    v: np.ndarray,
    axis_rows: np.ndarray,
    rows: np.ndarray,
    columns: np.ndarray,
    signs: np.ndarray,
    rotation: int,
    stiffness: np.ndarray,
    damping: np.ndarray,
    setpoint: np.ndarray,
    velocity_setpoint: np.ndarray,
    force: np.ndarray,
    limit: np.ndarray,
) -> np.ndarray:
    """Sense {B} relative to {A}, the spring-damper's wrench on it, and its efforts.

    Args:
        jacobian_world: ``(6, nv)`` world joint Jacobian (the snapshot's).
        frames: ``(nf, 12)`` frame placements (the snapshot's).
        v: ``(nv,)`` velocity.
        axis_rows: ``(n,)`` rows of the actuator's axes among ``x y z rx ry rz``.
        rows: ``(3,)`` rows of {B}, {O} and {A} in ``frames``.
        columns: velocity indices of the chain between {A} and {B}.
        signs: their +1 / -1.
        rotation: Index among the axes of the spring's one rotational axis (-1: none).
        stiffness: ``(n,)`` the spring-damper's parameters, per axis.
        damping: ``(n,)``.
        setpoint: ``(n,)``.
        velocity_setpoint: ``(n,)``.
        force: ``(n,)``.
        limit: ``(n,)`` (``inf``: no saturation; ``min(max(w, -inf), inf)`` is ``w``).

    Returns:
        One buffer: ``effort (nv)`` (``J^T w``), ``position (n)``, ``velocity (n)``,
        ``wrench (n)``, then 1.0, or 0.0 when the general path must run instead (and
        ``effort`` is left zero).

    """
    n = axis_rows.shape[0]
    nv = jacobian_world.shape[1]
    sensed = relative_sensor(jacobian_world, frames, v, axis_rows, rows, columns, signs)
    out = np.zeros(nv + 3 * n + 1)
    ok = True
    total = 0.0
    for i in range(n):
        x = sensed[n * nv + i]
        rate = sensed[n * nv + n + i]
        bent = setpoint[i] - x
        if i == rotation and not -np.pi <= bent <= np.pi:
            ok = False  # the float path wraps the angle
        wrench = stiffness[i] * bent + damping[i] * (velocity_setpoint[i] - rate)
        wrench = min(max(wrench, -limit[i]), limit[i]) + force[i]
        out[nv + i] = x
        out[nv + n + i] = rate
        out[nv + 2 * n + i] = wrench
        total += wrench
    if not np.isfinite(total):
        ok = False  # the general path names the component
    if ok:
        for j in range(columns.shape[0]):
            col = columns[j]
            acc = 0.0
            for i in range(n):
                acc += sensed[i * nv + col] * out[nv + 2 * n + i]
            out[col] = acc
        out[nv + 3 * n] = 1.0
    return out


def _core_tick(arguments: tuple) -> object | None:
    """The compiled core's object for these tables, or None (no core)."""
    if CORE is None or not hasattr(CORE, "SerialSpring"):
        return None
    return CORE.SerialSpring(*arguments)


class SerialSpringTick:
    """The one-call tick of a serial actuator with one spring-damper on all its axes.

    Built by `of` at declaration for the attachments it serves; `run` returns the
    tick's buffer (`spring_damper_tick`'s layout) or None (the general path runs).

    Args:
        actuator: The serial actuator (its own sensor).
        component: The spring-damper on all of its axes.

    """

    __slots__ = ("component", "core", "nv", "n", "rows_end", "tables")

    def __init__(self, actuator: VirtualActuator, component: SpringDamper) -> None:
        kinematics = actuator.kinematics
        rotations = rotation_axes(component.axes)
        rotation = -1 if rotations is None else rotations.start
        self.component = component
        self.nv, self.n = kinematics.nv, len(actuator.axes)
        rows = kinematics.frame_rows[:3].copy()  # {B}, {O}, {A}
        self.rows_end = int(rows.max()) + 1
        self.tables = (
            np.asarray(kinematics.rows, dtype=np.int64),
            rows,
            np.ascontiguousarray(kinematics.chain_columns[0], dtype=np.int64),
            np.ascontiguousarray(kinematics.chain_signs[0], dtype=float),
            rotation,
        )
        self.core = _core_tick((*self.tables, self.nv))

    @classmethod
    def of(cls, actuator: object, sensor: object, components: list) -> SerialSpringTick | None:
        """The tick for an attachment it serves, else None.

        It serves a serial actuator that is its own sensor, one reaction frame, with one
        spring-damper (the formula, not a subclass's own wrench) on all its axes, at most one of
        them rotational, when a compiled kernel exists (the core, or numba).
        """
        if CORE is None and not HAVE_NUMBA:
            return None
        if type(actuator) is not VirtualActuator or actuator is not sensor or len(components) != 1:
            return None
        component = components[0]
        klass = type(component)
        if not isinstance(component, SpringDamper) or klass.compute_wrench not in _FORMULA:
            return None
        if klass.compute_wrench_floats not in (
            SpringDamper.compute_wrench_floats, Spring.compute_wrench_floats
        ):
            return None
        rotations = rotation_axes(component.axes)
        if component.axes != actuator.axes or (rotations and len(rotations.which) != 1):
            return None
        if len(actuator.kinematics.reaction_ids) != 1:
            return None
        return cls(actuator, component)

    def run(self, components: list, snapshot: Snapshot) -> np.ndarray | None:
        """The tick's buffer, or None when the general path must run.

        Args:
            components: The attachment's components now (the same spring-damper, or None).
            snapshot: The tick's snapshot (with ``v``).

        Returns:
            ``effort (nv)``, ``position (n)``, ``velocity (n)``, ``wrench (n)``, flag (1.0), or
            None: other components, a Spring with a law, no velocity, a frame table without
            the sensor's rows, or the kernel's flag 0.

        """
        component = self.component
        if len(components) != 1 or components[0] is not component:
            return None
        v = snapshot.v
        if v is None or getattr(component, "law", None) is not None:
            return None
        jacobian_world, frames = snapshot.jacobian_world, snapshot.frame_table
        if frames.shape[0] < self.rows_end:
            return None
        parameters = (
            component.stiffness, component.damping, component.setpoint,
            component.velocity_setpoint, component.force, component.limit,
        )  # fmt: skip
        if self.core is not None:
            buffer = self.core.tick(jacobian_world, frames, v, *parameters)
        else:
            buffer = spring_damper_tick(jacobian_world, frames, v, *self.tables, *parameters)
        return buffer if buffer[-1] == 1.0 else None
