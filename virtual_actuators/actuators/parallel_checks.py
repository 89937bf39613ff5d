"""The argument checks of a parallel virtual actuator's declaration and of its requests."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..distribution.problem import DistributionProblem
from ..exceptions import ConstraintError, FrameNotFoundError, InvalidAxisError, InvalidInputError
from ..models.robot import Robot
from ..vocabulary.arguments import as_float_array, check_names, describe
from ..vocabulary.axes import check_axes_subset, resolve_frame
from ..vocabulary.constraints import DesignConstraint, Equal, Linear


def resolve_chains(
    robot: Robot, action: str, reactions: Sequence[str]
) -> tuple[tuple[str, ...], int, list[int]]:
    """The reaction frames' names, checked, and the frame ids of the action and reaction frames.

    Raises:
        FrameNotFoundError: A name is not a str or not in the model.
        ConstraintError: No reaction frame, a repeated one, or the action frame among them.
    """
    reactions = check_names(reactions, "reactions", FrameNotFoundError)
    if not reactions:
        raise ConstraintError("A parallel virtual actuator needs at least one reaction frame.")
    if len(set(reactions)) != len(reactions):
        raise ConstraintError(f"Reaction frames repeat: {reactions}.")
    model = robot.model
    action_id = resolve_frame(model, action, "action")
    reaction_ids = [resolve_frame(model, r, "reaction") for r in reactions]
    if action_id in reaction_ids:
        raise ConstraintError(
            f"The action frame {action!r} is also a reaction frame; they must differ."
        )
    return reactions, action_id, reaction_ids


def preferred_entries(
    reactions: tuple[str, ...], axes: tuple[str, ...], design: tuple[DesignConstraint, ...]
) -> np.ndarray:
    """``(p, n)`` preference of each force entry: 1e-3 at the entries the design couples, else 1."""
    preferred = np.ones((len(reactions), len(axes)))
    for constraint in design:
        if isinstance(constraint, (Equal, Linear)):
            for reaction, axis in constraint.labels():
                preferred[reactions.index(reaction), axes.index(axis)] = 1e-3
    return preferred


def check_forces(forces: object, p: int, n: int) -> np.ndarray:
    """``forces`` checked as a ``(p, n)`` float array (chains x axes).

    Raises:
        InvalidInputError: Not ``(p, n)`` finite real numbers.
    """
    expected = f"a ({p}, {n}) array of real numbers (chains x axes)"
    forces = as_float_array(forces, "forces", expected)
    if forces.shape != (p, n) or not np.all(np.isfinite(forces)):
        raise InvalidInputError(
            f"forces must be finite with shape ({p}, {n}), got shape {forces.shape}."
        )
    return forces


def check_free(
    free: Sequence[str], axes: tuple[str, ...], problem: DistributionProblem, checked: dict
) -> tuple[tuple[str, ...], np.ndarray]:
    """``(free axes, keep)`` of ``free``, ``keep`` True at the others; kept in ``checked``.

    Raises:
        InvalidAxisError: ``free`` is not a collection of the actuator's axes.
        ConstraintError: Too many constraints for those free axes.
    """
    try:
        key = (free,) if isinstance(free, str) else tuple(free)
        cached = checked.get(key)
    except TypeError:  # not iterable, or unhashable entries
        raise InvalidAxisError(
            f"free must be an axis name or a sequence of axis names among this actuator's "
            f"axes {axes}, got {describe(free)}."
        ) from None
    if cached is None:
        free_axes = check_axes_subset(key, axes, "free")
        keep = np.array([a not in free_axes for a in axes])
        problem.check_counts(keep)  # declaration-only: checked once per set of free axes
        cached = checked[key] = (free_axes, keep)
    return cached
