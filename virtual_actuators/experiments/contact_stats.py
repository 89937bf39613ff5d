"""Are the feet in support pushing and not sliding? Measured on MuJoCo's contact forces.

At each sample (every few ticks: the walks read them at 250 Hz), for each foot the gait has in
support, the total terrain force on its geoms is split into its component along the terrain's normal
under the foot (the slope at the foot's x, in the x-z plane) and the rest. The run's figures are the
least normal force of a supporting foot (0: a foot that should carry load is off the ground or
unloaded; negative is impossible in MuJoCo) and the largest tangential / normal ratio among
supporting feet carrying at least :data:`NORMAL_FLOOR` newtons (a ratio at MuJoCo's friction
coefficient means the foot slides).

A foot is read from :data:`SETTLE_TIME` after it enters the support set: a touchdown is an
impact (the swing foot arrives with some velocity and its first millisecond slides whatever the
distribution asks); what is measured is the stance the controller is responsible for.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Iterable

from ..simulation.simulator import Simulator
from ..simulation.terrain import Terrain

#: Friction ratios are taken where the normal force is at least this [N].
NORMAL_FLOOR = 1.0
#: A foot is read from this long after it enters support (the touchdown impact) [s].
SETTLE_TIME = 0.02

__all__ = ["NORMAL_FLOOR", "SETTLE_TIME", "StanceForces"]


class StanceForces:
    """Least normal force and largest friction ratio of the supporting feet over a run.

    Args:
        simulator: The simulation (contact forces, frame sites).
        terrain: The terrain (its slope gives the normal under each foot).

    Attributes:
        normal_min: Least normal force of a supporting foot so far [N] (inf before a sample).
        ratio_max: Largest tangential / normal force so far (feet above the floor).
        samples: Foot readings taken.

    """

    def __init__(self, simulator: Simulator, terrain: Terrain) -> None:
        self.simulator, self.terrain = simulator, terrain
        self.flat = terrain.is_flat
        self.normal_min = math.inf
        self.ratio_max = 0.0
        self.samples = 0
        self._since: dict[tuple[str, ...], float] = {}  # foot -> time it entered support [s]
        self._xs = [float(x) for x in terrain.points[:, 0]]
        angles = [0.0, *terrain.slopes.tolist(), 0.0]  # before, per segment, after the points
        self._trig = [(math.sin(a), math.cos(a)) for a in angles]

    def sample(self, feet: Iterable[Iterable[str]]) -> None:
        """Read the supporting feet; each foot is the frames whose geoms touch for it.

        Args:
            feet: Per supporting foot, the contact frames that make it up (a point foot is one
                frame; a flat foot its heel and toe).

        """
        simulator = self.simulator
        now = simulator.time
        since = {foot: self._since.get(foot, now) for foot in map(tuple, feet)}
        self._since = since
        settled = [foot for foot, entered in since.items() if now - entered >= SETTLE_TIME - 1e-9]
        if not settled:
            return
        frames = [frame for foot in settled for frame in foot]
        forces = simulator.contact_forces(frames)
        sites = simulator.mujoco_model.frame_sites
        row = 0
        for foot in settled:
            fx, fy, fz = forces[row : row + len(foot)].sum(axis=0).tolist()
            x = float(simulator.data.site_xpos[sites[foot[0]], 0])
            row += len(foot)
            sine, cosine = (0.0, 1.0) if self.flat else self._slope_at(x)
            normal = -sine * fx + cosine * fz  # along (-sin, 0, cos) [N]
            tangential = math.sqrt((fx + sine * normal) ** 2 + fy**2 + (fz - cosine * normal) ** 2)
            self.normal_min = min(self.normal_min, normal)
            if normal >= NORMAL_FLOOR:
                self.ratio_max = max(self.ratio_max, tangential / normal)
            self.samples += 1

    def _slope_at(self, x: float) -> tuple[float, float]:
        """``(sin, cos)`` of the terrain's slope at ``x`` (as :meth:`Terrain.slope`)."""
        index = bisect.bisect_right(self._xs, x)
        return self._trig[index]

    def figures(self) -> tuple[float | None, float | None]:
        """``(least normal force [N], largest friction ratio)``, None before any sample."""
        if not self.samples:
            return None, None
        return float(self.normal_min), float(self.ratio_max)

    def __repr__(self) -> str:
        return (
            f"StanceForces(normal_min={self.normal_min:.3g} N, ratio_max={self.ratio_max:.3g}, "
            f"samples={self.samples})"
        )
