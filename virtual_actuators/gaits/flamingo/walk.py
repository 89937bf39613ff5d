"""``flamingo-slopes``: Spring Flamingo walks blind over slopes (its registration in ``WALKS``)."""

from __future__ import annotations

from ...models.robot import Robot
from ..base import Gait, Walk
from ..planar_walk import draw_planar_walk, run_planar_walk, with_speed
from .parameters import FlamingoParameters
from .walker import FlamingoWalker


def make_gait(
    robot: Robot, speed: float | None, parameters: FlamingoParameters | None = None
) -> Gait:
    """The walker at ``speed`` (None: the parameters')."""
    return FlamingoWalker(robot, with_speed(parameters or FlamingoParameters(), speed))


WALK = Walk(
    name="flamingo-slopes",
    robot="spring_flamingo",
    run=run_planar_walk,
    parameters=FlamingoParameters,
    terrain="profile-one",
    duration=40.0,
    draw=draw_planar_walk,
    description="Spring Flamingo walks blind over unknown slopes (VMC section 6)",
    make_gait=make_gait,
    push=10.0,
    push_time=0.2,
    plot_window=True,
    nominal_speed=FlamingoParameters.speed,
    speeds=(0.3, 0.5),
)
