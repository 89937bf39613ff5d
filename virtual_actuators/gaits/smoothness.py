"""The smoothness of a walk's closed loop: every tick's efforts on its motors' limits."""

from __future__ import annotations

import numpy as np

from ..control.effort_limits import urdf_effort_limits
from ..experiments.smoothness import EffortSmoothness, effort_smoothness
from ..simulation.simulator import Simulator
from .runner import LoopEnd

__all__ = ["loop_smoothness", "motor_limits"]


def motor_limits(simulator: Simulator) -> tuple[np.ndarray, list[str]]:
    """The effort limits of the motors the simulation drives, and every degree of freedom's joint.

    Returns:
        ``(limits, names)``: ``(nv,)`` the URDF's effort limits of the actuated joints [N m or
        N] (``inf`` elsewhere), and ``nv`` joint names.
    """
    model, actuated = simulator.robot.model, set(simulator.mujoco_model.actuated)
    limits, names = urdf_effort_limits(simulator.robot), [""] * model.nv
    for j in range(1, model.njoints):
        joint = model.joints[j]
        dofs = slice(joint.idx_v, joint.idx_v + joint.nv)
        names[dofs] = [model.names[j]] * joint.nv
        if model.names[j] not in actuated:
            limits[dofs] = np.inf
    return limits, names


def loop_smoothness(simulator: Simulator, end: LoopEnd) -> EffortSmoothness:
    """`effort_smoothness` of a loop's ticks before its fall, on the motors `motor_limits` gives.

    Raises:
        InvalidInputError: Non-finite efforts or base rates in the record.
    """
    limits, names = motor_limits(simulator)
    until = end.ticks if end.fall_tick is None else end.fall_tick
    rates = None if end.base_rates is None else end.base_rates[:until]
    efforts = end.efforts[:until]
    return effort_smoothness(efforts, limits, rates, time_step=end.time_step, names=names)
