"""``flamingo-slopes``: Spring Flamingo walks blind over slopes (its registration in ``WALKS``)."""

from __future__ import annotations

from ..base import Walk
from ..planar_walk import draw_planar_walk, run_planar_walk
from .parameters import FlamingoParameters
from .walker import FlamingoWalker

WALK = Walk(
    name="flamingo-slopes",
    robot="spring_flamingo",
    run=run_planar_walk,
    parameters=FlamingoParameters,
    terrain="profile-one",
    duration=40.0,
    draw=draw_planar_walk,
    description="Spring Flamingo walks blind over unknown slopes (VMC section 6)",
    gait=FlamingoWalker,
    push=10.0,
    push_time=0.2,
    plot_window=True,
    nominal_speed=FlamingoParameters.speed,
    speeds=(0.3, 0.5),
)
