"""The balancer's body spring-damper, its request kept within what the support can produce."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ...components.springs import SpringDamper
from ...vocabulary.scalar import clip, maximum, select, sqrt
from ..base import SizedSlots, sized_slot

__all__ = ["SupportedSpring", "support_limited"]


def support_limited(
    wrench: Sequence, lever: Sequence, reach: Sequence, friction: object, moment_weight: object
) -> list:
    """``wrench`` moved to the nearest one the support holds; floats or traced.

    Its centre of pressure is kept within ``reach`` of the support's centre and its horizontal
    force within ``friction`` times the vertical one; force and moment share each change (least
    squares, weighted 1 : ``moment_weight``).

    Args:
        wrench: ``(6,)`` force and moment on the body, world axes, about its origin [N, N m].
        lever: The body's origin minus the support's centre, world axes [m].
        reach: The support's half extents along world x, y, margins taken [m].
        friction: Largest horizontal over vertical force [-].
        moment_weight: The moments' weight against the forces' in the shared change [-].

    Returns:
        The limited wrench ``(6,)``.
    """
    fx, fy, fz, mx, my, mz = wrench
    lx, ly, lz = lever
    normal = maximum(fz, 0.0)
    horizontal = sqrt(fx * fx + fy * fy)
    over = horizontal > friction * normal
    scale = select(over, friction * normal / maximum(horizontal, 1e-300), 1.0)
    fx, fy = select(over, fx * scale, fx), select(over, fy * scale, fy)
    about_x = mx + (ly * fz - lz * fy)  # the moment about the support's centre
    about_y = my + (lz * fx - lx * fz)
    bound_x, bound_y = reach[1] * normal, reach[0] * normal  # |M_x| by y, |M_y| by x
    miss_x = about_x - clip(about_x, -bound_x, bound_x)
    miss_y = about_y - clip(about_y, -bound_y, bound_y)
    # M_x moves with -height F_y, M_y with +height F_x: each miss shared, weighted
    spread = lz * lz + 1.0 / moment_weight
    share_x, share_y = miss_x / spread, miss_y / spread
    fy = select(miss_x != 0.0, fy - share_x * -1.0 * lz, fy)
    mx = select(miss_x != 0.0, mx - share_x / moment_weight, mx)
    fx = select(miss_y != 0.0, fx - share_y * 1.0 * lz, fx)
    my = select(miss_y != 0.0, my - share_y / moment_weight, my)
    return [fx, fy, fz, mx, my, mz]


class SupportedSpring(SizedSlots, SpringDamper):
    """The body's spring-damper, its request kept within what the support can produce.

    Args:
        axes: The body's six axes.
        stiffness: Per axis [N/m, N m/rad].
        damping: Per axis [N s/m, N m s/rad].
        name: Label used in reports.
    """

    SIZES = {"lever": 3, "reach": 2, "friction": 1, "moment_weight": 1}
    SLOTS = (*SpringDamper.SLOTS, *SIZES)
    FINITE = False  # the reach and the friction are unbounded until the first tick

    def __init__(
        self, axes: Sequence[str], stiffness: object, damping: object, name: str | None = None
    ) -> None:
        super().__init__(axes, stiffness, damping, name=name)
        self.lever = np.zeros(3)
        self.reach = np.full(2, np.inf)
        self.friction = np.inf
        self.moment_weight = 1.0

    lever = sized_slot("lever", "The body's origin minus the support's centre, world axes [m].")
    reach = sized_slot("reach", "The support's half extents along world x, y, margins taken [m].")
    friction = sized_slot("friction", "Largest horizontal over vertical force [-].", scalar=True)
    moment_weight = sized_slot(
        "moment_weight", "The moments' weight against the forces' [-].", scalar=True
    )

    def compute_wrench(self, position: np.ndarray, velocity: np.ndarray, time: float) -> np.ndarray:
        """The spring-damper's wrench, then limited (`support_limited`)."""
        wrench = np.asarray(super().compute_wrench(position, velocity, time), dtype=float)
        limited = support_limited(
            wrench.tolist(), self._lever.tolist(), self._reach.tolist(),
            float(self._friction[0]), float(self._moment_weight[0]),
        )  # fmt: skip
        return np.array(limited)

    def traced_wrench(self, slots, position: tuple, velocity: tuple, time: object) -> list:
        """The spring-damper's traced wrench, then limited (a plan's ops)."""
        wrench = super().traced_wrench(slots, position, velocity, time)
        return support_limited(
            wrench, slots["lever"], slots["reach"], slots["friction"][0],
            slots["moment_weight"][0],
        )  # fmt: skip
