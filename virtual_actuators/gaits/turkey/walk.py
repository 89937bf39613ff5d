"""``turkey-walk``: Spring Turkey walks on level ground (its registration in ``WALKS``)."""

from __future__ import annotations

from ..base import Walk
from ..planar_walk import draw_planar_walk, run_planar_walk
from .parameters import TurkeyParameters
from .walker import TurkeyWalker

WALK = Walk(
    name="turkey-walk",
    robot="spring_turkey",
    run=run_planar_walk,
    parameters=TurkeyParameters,
    terrain="flat",
    duration=20.0,
    draw=draw_planar_walk,
    description="Spring Turkey walks on level ground (VMC section 5, Table 1)",
    gait=TurkeyWalker,
    push=15.0,
    push_time=0.2,
    plot_window=True,
    nominal_speed=TurkeyParameters.speed,
    speeds=(0.3, 0.6),
)
