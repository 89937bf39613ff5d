"""What a walk log holds: the standard channels and their units, the states that are steps.

Standard channels
-----------------

The walking demos record these (`STANDARD_CHANNELS`); all SI, world frame, planar robots
moving along ``x`` with ``z`` up and pitch about ``y``:

====================  ======  ===========================================================
channel               unit    meaning
====================  ======  ===========================================================
``time``              s       simulation time of the control tick (required in every log)
``x``                 m       body (hip) x
``z``                 m       hip height above the terrain directly below the hip
``z_world``           m       hip height in the world frame
``pitch``             rad     body pitch (positive nose down, about +y)
``xdot``              m/s     body (hip) horizontal velocity
``x_setpoint``        m       set point of the x virtual spring (NaN when none)
``z_setpoint``        m       set point of the height spring, same reference as ``z``
``pitch_setpoint``    rad     set point of the pitch spring
``xdot_setpoint``     m/s     dogtrack bunny speed; NaN when the bunny is inactive
``fx``                N       virtual force along x applied to the body by the components
``fz``                N       virtual force along z applied to the body by the components
``m_pitch``           N m     virtual moment about y applied to the body by the components
``global_slope``      rad     global slope estimate (seed section 6); NaN for level walkers
``fallen``            0/1     1 from the tick the robot is judged fallen
====================  ======  ===========================================================

plus the discrete ``state`` (int index into ``state_names``, -1 when unknown), always recorded.
Extra channels (joint torques, saturation counts, ...) may be declared beside them.

Standard metadata keys
----------------------

``robot`` (str), ``terrain`` (str, a name), ``terrain_points`` (``(n, 2)`` array of terrain
``(x, z)`` vertices in the world frame), ``speed_setpoint_mps`` (float), ``nominal_height_m``
(float), ``step_states`` (names of the single-support states whose entries count as steps),
``double_support_states`` (names of the double-support states), ``control_dt_s`` (float),
``wall_time_s`` (float, wall-clock time of the run). Any other JSON-able values or NumPy arrays
may be added.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from virtual_actuators.exceptions import InvalidInputError, closest_names

__all__ = [
    "STANDARD_CHANNELS",
    "STATE_CHANNEL",
    "UNITS",
    "check_names",
    "default_step_states",
    "resolve_step_states",
    "unknown_name",
]

#: The float channels recorded by the walking demos (the discrete ``state`` is always recorded).
STANDARD_CHANNELS: tuple[str, ...] = (
    "time",
    "x",
    "z",
    "z_world",
    "pitch",
    "xdot",
    "x_setpoint",
    "z_setpoint",
    "pitch_setpoint",
    "xdot_setpoint",
    "fx",
    "fz",
    "m_pitch",
    "global_slope",
    "fallen",
)

#: Units of the standard channels, for labels.
UNITS: dict[str, str] = {
    "time": "s",
    "x": "m",
    "z": "m",
    "z_world": "m",
    "pitch": "rad",
    "xdot": "m/s",
    "x_setpoint": "m",
    "z_setpoint": "m",
    "pitch_setpoint": "rad",
    "xdot_setpoint": "m/s",
    "fx": "N",
    "fz": "N",
    "m_pitch": "N m",
    "global_slope": "rad",
    "fallen": "",
}

STATE_CHANNEL = "state"


def unknown_name(name: object, valid: Sequence[str], what: str) -> InvalidInputError:
    """Build the error for a name that is not one of ``valid`` (names it, lists the valid ones)."""
    listed = ", ".join(repr(v) for v in valid)
    hint = closest_names(str(name), valid, n=3)
    did_you_mean = f" Did you mean {', '.join(repr(h) for h in hint)}?" if hint else ""
    return InvalidInputError(f"Unknown {what} {name!r}; valid {what}s: {listed}.{did_you_mean}")


def check_names(names: Iterable[object], what: str) -> tuple[str, ...]:
    """Return ``names`` as a tuple of non-empty unique strings, or raise naming the bad one."""
    out: list[str] = []
    for name in names:
        if not isinstance(name, str) or not name:
            raise InvalidInputError(f"{what}: every name must be a non-empty str, got {name!r}.")
        if name in out:
            raise InvalidInputError(f"{what}: {name!r} is given twice.")
        out.append(name)
    return tuple(out)


def default_step_states(state_names: Iterable[str]) -> tuple[str, ...]:
    """Guess the single-support states from their names.

    A name counts when it contains ``single``, or contains ``support`` but neither ``double`` nor
    ends in ``2`` (the seed's buffer states "Left Support 2" and "Right Support 2" follow a step,
    they do not start one). Prefer giving ``metadata["step_states"]`` explicitly.

    Args:
        state_names: The log's state names.

    Returns:
        The names that look like single-support states.
    """
    out = []
    for name in state_names:
        low = name.lower()
        if "single" in low or (
            "support" in low and "double" not in low and not low.rstrip().endswith("2")
        ):
            out.append(name)
    return tuple(out)


def resolve_step_states(
    state_names: Sequence[str], metadata: dict, step_states: Iterable[str] | None = None
) -> tuple[str, ...]:
    """Return the step-state names: ``step_states``, else metadata, else the default guess.

    Args:
        state_names: The run's state names (``WalkLog.state_names``).
        metadata: Its metadata (``WalkLog.metadata``).
        step_states: Explicit names, or None.

    Returns:
        Names from ``step_states``, else ``metadata["step_states"]``, else
        `default_step_states` of the log's state names.

    Raises:
        InvalidInputError: If a given name is not a state of the log (the message names it and
            lists the valid ones).
    """
    source = "step_states"
    if step_states is None:
        step_states = metadata.get("step_states")
        source = "metadata['step_states']"
    if step_states is None:
        return default_step_states(state_names)
    if isinstance(step_states, str):
        step_states = (step_states,)
    names = tuple(str(s) for s in step_states)
    for name in names:
        if name not in state_names:
            listed = ", ".join(repr(s) for s in state_names) or "none"
            raise InvalidInputError(
                f"{source}: {name!r} is not a state of the log; valid states: {listed}."
            )
    return names
