"""Are the feet in support pushing and not sliding? Measured on MuJoCo's contact forces.

The figures are defined on the "Command line" page (a walk's stance figures).
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np

from ..simulation.simulator import Simulator

#: Friction ratios are taken where the normal force is at least this [N].
NORMAL_FLOOR = 1.0
#: A foot is read from this long after it enters support (the touchdown impact) [s].
SETTLE_TIME = 0.02


class StanceForces:
    """Least normal force and largest friction ratio of the supporting feet over a run.

    Args:
        simulator: The simulation (MuJoCo's contacts and their forces).

    Attributes:
        normal_min: Least normal force of a supporting foot so far [N] (inf before a sample).
        ratio_max: Largest tangential / normal force of the feet above `NORMAL_FLOOR`.
        samples: Foot readings taken.
    """

    def __init__(self, simulator: Simulator) -> None:
        self.simulator = simulator
        self.normal_min = math.inf
        self.ratio_max = 0.0
        self.samples = 0
        self._since: dict[tuple[str, ...], float] = {}  # foot -> time it entered support [s]
        self._feet: list[tuple[str, ...]] | None = None  # the support set of _since
        self._settled: tuple[tuple[str, ...], ...] = ()  # its feet settled so far
        self._owners: dict[tuple, np.ndarray] = {}  # settled feet -> each geom's foot (or -1)

    def sample(self, feet: Iterable[Iterable[str]]) -> None:
        """Read the supporting feet, each the contact frames that make it up.

        Raises:
            FrameNotFoundError: A foot names a frame the robot lacks.
        """
        simulator = self.simulator
        now = simulator.time
        settled = self._settle(feet, now)
        if not settled:
            return
        owner = self._owners.get(settled)
        if owner is None:  # robot geom -> index of the settled foot owning it, once per set
            owner = self._owners[settled] = _owners(simulator, settled)
        normal = [0.0] * len(settled)  # [N]
        tangential = [0.0] * len(settled)  # sum of the contacts' |f_t| [N]
        for index, f_normal, f_t1, f_t2 in simulator.grouped_contact_forces(owner):
            index = int(index)
            normal[index] += f_normal
            tangential[index] += math.hypot(f_t1, f_t2)
        for foot_normal, foot_tangential in zip(normal, tangential, strict=True):
            self.normal_min = min(self.normal_min, foot_normal)
            if foot_normal >= NORMAL_FLOOR:
                self.ratio_max = max(self.ratio_max, foot_tangential / foot_normal)
            self.samples += 1

    def _settle(self, feet: Iterable[Iterable[str]], now: float) -> tuple[tuple[str, ...], ...]:
        """The feet in support since `SETTLE_TIME` at least (their entry times kept)."""
        feet = feet if feet.__class__ is list else list(feet)
        if feet != self._feet:  # a new support set: entry times of the feet that stay
            since = self._since
            self._since = {foot: since.get(foot, now) for foot in map(tuple, feet)}
            self._feet = [tuple(foot) for foot in feet]
            self._settled = ()
        if len(self._settled) < len(self._since):  # feet still settling
            self._settled = tuple(
                foot for foot, entered in self._since.items() if now - entered >= SETTLE_TIME - 1e-9
            )
        return self._settled

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


def _owners(simulator: Simulator, settled: tuple[tuple[str, ...], ...]) -> np.ndarray:
    """Per geom, the index of the settled foot that owns it (-1: none; the first foot wins)."""
    mm = simulator.mujoco_model
    for frame in {frame for foot in settled for frame in foot}:
        mm.check_frame(frame)
    owner = np.full(simulator.model.ngeom, -1, dtype=np.int64)
    for index, foot in reversed(list(enumerate(settled))):  # the first foot's claim stands
        for frame in foot:
            for geom in mm.frame_geoms.get(frame, ()):
                owner[geom] = index
    return owner
