"""The walk registry: the `Walk` of every gait (the bipeds' in ``planar_walk.py``)."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from ..exceptions import InvalidInputError, suggestion
from ..simulation.simulator import Simulator
from ..simulation.terrain import Terrain
from .balance.walk import WALK as BALANCE
from .base import Gait, Walk, WalkRequest
from .hexapod.walk import WALK as HEXAPOD
from .legged.walk import WALK as LEGGED
from .planar_walk import FLAMINGO, TURKEY

#: The walks by name, in the command line's order.
WALKS: dict[str, Walk] = {walk.name: walk for walk in (TURKEY, FLAMINGO, HEXAPOD, LEGGED, BALANCE)}


def run_walk(
    name: str,
    duration: float | None = None,
    speed: float | None = None,
    terrain: str | Terrain | None = None,
    progress: bool = True,
    on_tick: Callable[[Simulator, Gait], None] | None = None,
    stop_on_fall: bool = True,
    seed: int | None = None,
    parameters: object | None = None,
    distribution: str | None = None,
    force_speed: bool = False,
    **options: Any,
) -> Any:
    """Simulate one of the walks and measure it.

    Args:
        name: A key of `WALKS`.
        duration: Simulated time [s] (default: the walk's).
        speed: Desired speed [m/s] (default: `Walk.default_speed`).
        terrain: A [`Terrain`][] or a spec for [`Terrain.parse`][] (default: the walk's).
        progress: Show a tqdm progress bar.
        on_tick: Called after every physics step (e.g. a viewer's update).
        stop_on_fall: End the run at the first fallen tick (plus 0.5 s to see the fall).
        seed: None for the walk's nominal start; an int varies the start.
        parameters: The gait's parameters (a ``WALKS[name].parameters``); ``speed`` overrides.
        distribution: ``"partitioned"`` or ``"qp"`` (overrides ``parameters.distribution``).
        force_speed: Run a ``speed`` outside the walk's supported range instead of refusing it.
        **options: The walk's own options (``WALKS[name].options``).

    Returns:
        The walk's `WalkResult` (or its subclass).

    Raises:
        InvalidInputError: Unknown walk or option, bad duration, speed, terrain, seed,
            parameters (not a ``WALKS[name].parameters``) or distribution; a speed outside the
            walk's supported range (naming it) without ``force_speed``.
    """
    if name not in WALKS:
        raise InvalidInputError(f"Unknown walk {name!r}. {suggestion(name, WALKS, 'walks')}")
    walk = WALKS[name]
    duration = walk.duration if duration is None else float(duration)
    if not (math.isfinite(duration) and duration > 0.0):
        raise InvalidInputError(f"duration must be a positive number of seconds, got {duration}.")
    unknown = sorted(set(options) - set(walk.options))
    if unknown:
        known = ", ".join(walk.options) or "none"
        raise InvalidInputError(f"{name} takes no option {unknown[0]!r} (its options: {known}).")
    if not force_speed:
        walk.check_speed(speed, **options)
    if parameters is not None and not isinstance(parameters, walk.parameters):
        raise InvalidInputError(
            f"{walk.name}: parameters must be a {walk.parameters.__name__}, got "
            f"{type(parameters).__name__}."
        )
    return walk.run(WalkRequest(
        walk, duration, speed, walk.terrain if terrain is None else terrain, progress, on_tick,
        stop_on_fall, seed, parameters, distribution, options,
    ))  # fmt: skip
