"""What a walk log holds: the standard channels, the states that are steps.

The channels, their units and the metadata keys are described on the "Command line" page.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from virtual_actuators.exceptions import InvalidInputError, closest_names

#: The float channels recorded by the walking demos (the discrete ``state`` is always recorded).
STANDARD_CHANNELS: tuple[str, ...] = tuple(
    "time x z z_world pitch xdot x_setpoint z_setpoint pitch_setpoint xdot_setpoint fx fz m_pitch "
    "global_slope fallen".split()
)

STATE_CHANNEL = "state"


def unknown_name(name: object, valid: Sequence[str], what: str) -> InvalidInputError:
    """The error for a name that is not one of ``valid`` (naming it and the valid ones)."""
    listed = ", ".join(repr(v) for v in valid)
    hint = closest_names(str(name), valid, n=3)
    did_you_mean = f" Did you mean {', '.join(repr(h) for h in hint)}?" if hint else ""
    return InvalidInputError(f"Unknown {what} {name!r}; valid {what}s: {listed}.{did_you_mean}")


def check_names(names: Iterable[object], what: str) -> tuple[str, ...]:
    """``names`` as a tuple of non-empty unique strings.

    Raises:
        InvalidInputError: Naming the first bad name.
    """
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

    A name counts when it contains ``single``, or ``support`` but neither ``double`` nor a final
    ``2`` (the seed's buffer states "Left Support 2" follow a step, they do not start one).
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
    state_names: Sequence[str],
    metadata: dict,
    step_states: Iterable[str] | None = None,
    key: str = "step_states",
) -> tuple[str, ...]:
    """The step states: ``step_states``, else ``metadata[key]``, else the guess from the names.

    ``key`` is ``"step_states"`` (guessed by `default_step_states`) or
    ``"double_support_states"`` (guessed as the names that contain ``double``).

    Raises:
        InvalidInputError: If a given name is not a state of the log (the message names it and
            lists the valid ones).
    """
    source = key
    if step_states is None:
        step_states = metadata.get(key)
        source = f"metadata[{key!r}]"
    if step_states is None:
        if key == "step_states":
            return default_step_states(state_names)
        return tuple(s for s in state_names if "double" in s.lower())
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
