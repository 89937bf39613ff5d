"""The legged walker's per-tick half: its hooks, its touchdown events and its swing curve."""

from __future__ import annotations

import math
from collections.abc import Sequence

from ...control.state_machine import Context
from ...vocabulary.scalar import (
    atan2,
    cos,
    cross,
    dot,
    hypot,
    logical_and,
    logical_or,
    maximum,
    minimum,
    select,
    sin,
)
from ...vocabulary.traced import lowerable
from ..base import as_floats
from ..planar import lift_profile, smoothstep
from .body import missing_direction
from .parameters import GRAVITY


class WalkerHooks:
    """The hooks and events of [`LeggedWalker`][virtual_actuators.gaits.legged.LeggedWalker]."""

    def _landing(self, group: tuple[str, ...]) -> object:
        """The lowerable event ending ``group``'s swing: its feet down late enough, or too long."""

        @lowerable
        def landed(context: Context) -> object:
            elapsed, p = context.time_in_state, self.parameters
            too_long = elapsed >= p.max_swing * self.swing_time
            contacts = context.contacts
            if not contacts:  # no switches (a traced context always has them)
                return logical_or(too_long, elapsed >= self.swing_time)
            down = elapsed >= p.touchdown_phase * self.swing_time
            for foot in group:
                down = logical_and(down, contacts.get(foot, False))
            return logical_or(too_long, down)

        landed.__qualname__ = f"landed({'+'.join(group)})"
        return landed

    @lowerable
    def _enter_swing(self, context: Context) -> None:
        """The swing starts where each foot of the group is: its set point there, at rest."""
        for foot in self._swinging[context.state]:
            position = as_floats(context.frame_position(foot))
            setattr(self.memory, f"foot_{self.feet.index(foot)}", (*position, *position, 0.0,
                    0.0, 0.0))  # fmt: skip

    @lowerable
    def _update(self, context: Context) -> None:
        """Body set points, the direction the support cannot produce, and the swing feet."""
        state, memory, body = context.state, self.memory, self.body
        rotation, origin = context.placement(self.body_frame)
        rotation, origin = [as_floats(row) for row in rotation], as_floats(origin)
        linear = as_floats(context.frame_velocity(self.body_frame))
        spin = as_floats(context.v[3:6])
        if self._to_body is not None:
            spin = tuple(dot(row, spin) for row in self._to_body.tolist())
        angular = tuple(dot(row, spin) for row in rotation)  # world axes [rad/s]
        com = as_floats(context.center_of_mass())
        yaw = atan2(rotation[1][0], rotation[0][0])
        c, s = cos(yaw), sin(yaw)
        dt = self._ramp(context.time, state != "stand")
        setpoint, yaw_command = memory.setpoint, memory.yaw_command
        body.velocity, body.lever = setpoint, tuple(com[i] - origin[i] for i in range(3))
        body.yaw_rate = yaw_command + memory.yaw_integral
        support = self._support[state]
        ground = sum((context.frame_coordinate(foot, "z") for foot in support), 0.0) / len(support)
        body.height = ground + self.stand_height
        if self.parameters.give_way and len(support) == 2:
            first, second = (as_floats(context.frame_position(foot)) for foot in support)
            body.missing = missing_direction(origin, first, second)
        else:  # three feet or more produce every wrench (one: the distribution yields)
            body.missing = (0.0,) * 6
        vx, vy, _ = linear
        error = (c * vx + s * vy - setpoint[0], -s * vx + c * vy - setpoint[1])
        self._integrate(dt, error, yaw_command - angular[2])
        if not state.startswith("swing"):
            return
        (sx, sy), (bx, by) = setpoint, memory.error_integral
        motion = (sx, sy, error[0] + bx, error[1] + by, yaw_command, yaw,
                  context.time_in_state, ground)  # fmt: skip
        self._move_swing(context, (*com, *origin, *linear, *angular), motion)

    def _integrate(self, dt: object, error: tuple, yaw_error: object) -> None:
        """Integrate the velocity errors (heading frame [m/s]; yaw rate [rad/s]), bounded."""
        memory, scale = self.memory, self.gains.time_scale
        rate = dt / (self.parameters.integral_time * scale)
        limit = self.parameters.integral_limit * math.sqrt(GRAVITY * self.gains.height)
        (x, y), (ex, ey) = memory.error_integral, error
        memory.error_integral = (
            maximum(-limit, minimum(limit, x + rate * ex)),
            maximum(-limit, minimum(limit, y + rate * ey)),
        )
        turn = self.parameters.integral_limit / scale  # [rad/s]
        memory.yaw_integral = maximum(-turn, minimum(turn, memory.yaw_integral + rate * yaw_error))

    def _ramp(self, time: object, moving: bool) -> object:
        """Move the velocity set point toward the command at the bounded acceleration.

        Returns:
            The tick's step [s] (0 on the first tick and while standing).
        """
        memory = self.memory
        dt = 0.0
        if moving:
            dt = select(memory.started, maximum(0.0, time - memory.last_time), 0.0)
        memory.last_time, memory.started = time, 1.0
        limit = self.parameters.acceleration * GRAVITY * dt
        (sx, sy), (cx, cy) = memory.setpoint, memory.command
        dx, dy = cx - sx, cy - sy
        norm = maximum(hypot(dx, dy), 1e-12)
        scale = minimum(1.0, limit / norm)
        memory.setpoint = (sx + scale * dx, sy + scale * dy)
        rate = self.parameters.acceleration * GRAVITY * (scale < 1.0)
        self.body.acceleration = (rate * dx / norm, rate * dy / norm)
        return dt

    def _move_swing(self, context: Context, body: tuple, motion: tuple) -> None:
        """The swing feet's set points to the footholds; a foot down late in the swing is held."""
        memory, time = self.memory, context.time
        late = context.time_in_state / self.swing_time >= self.parameters.touchdown_phase
        dt = time - memory.swung_at
        origin, linear, angular = body[3:6], body[6:9], body[9:12]
        for foot in self._swinging[context.state]:
            k = self.feet.index(foot)
            field = f"foot_{k}"
            state = getattr(memory, field)
            moved, setpoints = swing_setpoint(state, self._nominal[k], body, motion, dt,
                                              self._shape)  # fmt: skip
            down = logical_and(late, context.contacts.get(foot, False))
            position = as_floats(context.frame_position(foot))
            offset = tuple(position[i] - origin[i] for i in range(3))
            turning = cross(angular, offset)
            held = (*offset, *(-linear[i] - turning[i] for i in range(3)))
            chosen = tuple(select(down, h, m) for h, m in zip(held, setpoints, strict=True))
            spring = self.swing[foot]
            spring.setpoint, spring.velocity_setpoint = chosen[:3], chosen[3:]
            setattr(memory, field, tuple(select(down, a, b) for a, b in zip(state, moved,
                    strict=True)))  # fmt: skip
        memory.swung_at = time


def swing_setpoint(
    state: Sequence,
    nominal: Sequence[float],
    body: Sequence,
    motion: Sequence,
    dt: object,
    shape: Sequence[float],
) -> tuple[tuple, tuple]:
    """One swinging foot's next state and its spring's set points, relative to the body.

    The foothold, about the centre of mass predicted for touchdown and in the heading then: the
    nominal place turned by half a stance's yaw, moved by half a stance's travel and the capture
    time's velocity error, within ``reach`` of the nominal place; ``depth`` below the ground. The
    set point goes there by a smooth step arriving at 80 % of the swing horizontally, a smooth
    step between the two heights plus ``lift`` times `lift_profile` vertically; its velocity is
    low-pass filtered. Floats or traced values.

    Args:
        state: ``(9,)`` lift-off point, last set point, its velocity [m, m/s], world.
        nominal: ``(2,)`` the foot's nominal place relative to the centre of mass, heading
            frame [m].
        body: ``(12,)`` centre of mass, body origin, velocity, angular velocity, world.
        motion: ``(8,)`` ``vx, vy, ex, ey`` (set velocity and its error, heading frame) [m/s],
            yaw rate set point [rad/s], yaw [rad], time in the swing [s], ground height [m].
        dt: Time since the last set points [s] (not positive: the velocity is kept).
        shape: ``(8,)`` swing time, stance time, capture time (``sqrt(h / g)``), reach, lift,
            lift peak (a phase), touchdown depth, rate filter [s, s, s, m, m, -, m, s].

    Returns:
        ``(state, setpoints)``: the new ``(9,)`` state, and ``(6,)`` the set point and its
        velocity relative to the body, world axes.
    """
    vx, vy, ex, ey, yaw_rate, yaw, elapsed, ground = motion
    swing_time, stance_time, capture, reach, lift, peak, depth, rate_filter = shape
    phase = elapsed / swing_time
    remaining = maximum(0.0, swing_time - elapsed)
    heading = yaw + yaw_rate * remaining
    c, s = cos(heading), sin(heading)
    cy, sy = cos(yaw), sin(yaw)
    centre_x = body[0] + remaining * (cy * vx - sy * vy)  # the centre of mass at touchdown
    centre_y = body[1] + remaining * (sy * vx + cy * vy)
    depth = depth * (1.0 + 4.0 * maximum(0.0, phase - 1.0))
    moving = dt > 0.0
    blend = select(moving, minimum(1.0, dt / rate_filter), 0.0)
    step = select(moving, dt, 1.0)  # the divisor where it is used
    (x, y), half = nominal, 0.5 * stance_time
    angle = yaw_rate * half
    turn_c, turn_s = cos(angle), sin(angle)
    dx = turn_c * x - turn_s * y - x + vx * half + capture * ex
    dy = turn_s * x + turn_c * y - y + vy * half + capture * ey
    scale = minimum(1.0, reach / maximum(hypot(dx, dy), 1e-12))
    x, y = x + scale * dx, y + scale * dy  # the foothold
    goal = (centre_x + c * x - s * y, centre_y + s * x + c * y, ground - depth)
    along = smoothstep(minimum(1.0, 1.25 * phase))
    target = (
        state[0] + (goal[0] - state[0]) * along, state[1] + (goal[1] - state[1]) * along,
        state[2] + (goal[2] - state[2]) * smoothstep(phase) + lift * lift_profile(phase, peak),
    )  # fmt: skip
    rate = tuple(
        select(moving, state[6 + i] + blend * ((target[i] - state[3 + i]) / step - state[6 + i]),
               state[6 + i])
        for i in range(3)
    )  # fmt: skip
    offset = tuple(target[i] - body[3 + i] for i in range(3))
    spin = cross(body[9:12], offset)
    relative = tuple(rate[i] - body[6 + i] - spin[i] for i in range(3))
    return (*state[:3], *target, *rate), (*offset, *relative)
