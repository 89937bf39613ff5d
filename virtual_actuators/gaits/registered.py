"""The one entry of every registered walk: `run_registered`, then the walk's own ``run``."""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass, replace
from typing import Any

from ..exceptions import InvalidInputError
from ..simulation.simulator import Simulator
from ..simulation.terrain import Terrain
from .base import Gait, Walk
from .runner import WalkFigures, WalkResult, number

__all__ = ["ConfiguredResult", "WalkRequest", "run_registered"]


@dataclass(frozen=True, slots=True)
class WalkRequest:
    """One walk's run as `run_registered` resolved it (what `Walk.run` receives).

    Attributes:
        walk: The walk.
        duration: Simulated time [s].
        speed: Desired speed [m/s], as given (None: the walk's default).
        terrain: A [`Terrain`][] or its spec (the walk's when none was given).
        progress: Show a tqdm progress bar.
        on_tick: Called after every physics step, or None.
        stop_on_fall: End the run 0.5 s after the first fallen tick.
        seed: None for the walk's nominal start; an int varies it.
        parameters: The gait's parameters (a ``walk.parameters``), or None for the gait's.
        distribution: ``"partitioned"`` or ``"qp"`` as given, or None.
        options: The walk's own options (``walk.options``).
    """

    walk: Walk
    duration: float
    speed: float | None
    terrain: str | Terrain
    progress: bool
    on_tick: Callable[[Simulator, Gait], None] | None
    stop_on_fall: bool
    seed: int | None
    parameters: object | None
    distribution: str | None
    options: Mapping[str, Any]

    def distribution_and_parameters(self, default: str = "qp") -> tuple[str, object | None]:
        """The given distribution (else the parameters', else ``default``) and its parameters."""
        parameters, distribution = self.parameters, self.distribution
        if distribution is None:
            return (default if parameters is None else parameters.distribution), parameters
        if parameters is not None:
            parameters = replace(parameters, distribution=distribution)
        return distribution, parameters

    @property
    def loop(self) -> tuple[bool, Callable[[Simulator, Gait], None] | None, bool]:
        """``(progress, on_tick, stop_on_fall)``: the loop's arguments, in a walk's order."""
        return self.progress, self.on_tick, self.stop_on_fall

    def configured(self, config: type, speed: float | None = None) -> tuple[Any, object | None]:
        """A walk's configuration dataclass built from the request, and the parameters.

        ``speed`` replaces the request's (None: the request's).

        Raises:
            InvalidInputError: What ``config`` raises (a bad option, speed or distribution).
        """
        distribution, parameters = self.distribution_and_parameters()
        built = config(
            speed=self.speed if speed is None else speed, terrain=self.terrain,
            duration=self.duration, seed=self.seed, distribution=distribution, **self.options,
        )  # fmt: skip
        return built, parameters


@dataclass
class ConfiguredResult(WalkResult):
    """A walk's result with its configuration and tick count (its ``trace()`` the walk's own).

    Attributes:
        config: What was walked.
        ticks: Control ticks run.
    """

    config: Any = None
    ticks: int = 0

    def trace(self) -> dict[str, list]:
        """Equal-length lists of the walk's trace."""
        raise NotImplementedError

    def figures(self) -> WalkFigures:
        """What a sweep tabulates (the distance is the straight line from start to end)."""
        m, x, y = self.metrics, self.log["x"], self.log["y"]
        distance = math.hypot(x[-1] - x[0], y[-1] - y[0]) if len(x) else math.nan
        return WalkFigures(
            bool(m.fell), number(m.fall_time_s), distance, number(m.speed_mps), int(m.steps)
        )

    def to_json(self) -> dict[str, Any]:
        """``fell``, ``realtime_factor``, the summary figures, ``ticks``, ``config``, ``trace``."""
        figures, config = asdict(self.metrics), asdict(self.config)
        return {**figures, "ticks": self.ticks, "config": config, "trace": self.trace()}

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.metrics.summary()})"


def run_registered(request: WalkRequest) -> Any:
    """Run a registered walk: the parameters' type checked, then ``request.walk.run(request)``.

    Returns:
        The walk's result (a `WalkResult` or its subclass).

    Raises:
        InvalidInputError: Parameters that are not a ``walk.parameters``; what the walk's
            ``run`` raises (a bad configuration, speed, terrain, seed or distribution).
    """
    walk, parameters = request.walk, request.parameters
    expected = walk.parameters
    if parameters is not None and not isinstance(parameters, expected):
        raise InvalidInputError(
            f"{walk.name}: parameters must be a {expected.__name__}, got "
            f"{type(parameters).__name__}."
        )
    return walk.run(request)
