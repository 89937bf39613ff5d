"""Joint efforts to MuJoCo actuator controls, and back.

Every actuated joint has one ``motor`` actuator of gear 1 named after it, so a control is the
joint's effort. A free-flyer and passive joints have no actuator.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from virtual_actuators.core import CORE, has
from virtual_actuators.exceptions import InvalidInputError
from virtual_actuators.simulation.conversions import finite_vector, gathers
from virtual_actuators.simulation.model import MujocoModel

__all__ = ["UNACTUATED_TOLERANCE", "ctrl_to_torques", "ctrl_writer", "torques_to_ctrl"]

#: Largest effort [N m or N] tolerated on an unactuated degree of freedom.
UNACTUATED_TOLERANCE = 1e-9


def ctrl_writer(mm: MujocoModel, ctrl: np.ndarray) -> Callable[[np.ndarray, bool], bool] | None:
    """A per-tick writer of efforts into ``ctrl`` (MuJoCo's ``data.ctrl``): one compiled call.

    ``write(tau, ignore_unactuated)`` writes what `torques_to_ctrl` returns and returns True, or
    writes nothing and returns False (`torques_to_ctrl` then says why).

    Returns:
        The writer; None without the compiled core or when a motor drives no single joint.
    """
    maps = gathers(mm)
    if not has("efforts_to_ctrl") or maps.direct_ctrl is None:
        return None
    kernel, direct, unactuated = CORE.efforts_to_ctrl, maps.direct_ctrl, maps.unactuated_v
    none = unactuated[:0]
    shape = (mm.robot.model.nv,)

    def write(tau: np.ndarray, ignore_unactuated: bool) -> bool:
        if tau.__class__ is not np.ndarray or tau.shape != shape:
            return False
        checked = none if ignore_unactuated else unactuated
        return kernel(tau, direct, checked, UNACTUATED_TOLERANCE, ctrl) == 0

    return write


def torques_to_ctrl(
    mm: MujocoModel, tau: np.ndarray, *, ignore_unactuated: bool = False
) -> np.ndarray:
    """The actuators' controls ``(mj_model.nu,)`` for joint efforts ``tau`` (not clipped).

    Args:
        mm: The MuJoCo model and its maps.
        tau: Joint efforts [N m or N], shape ``(model.nv,)``, Pinocchio velocity order.
        ignore_unactuated: Drop efforts on unactuated degrees of freedom instead of raising.

    Raises:
        InvalidInputError: If ``tau`` has the wrong size or non-finite entries, or (unless
            ``ignore_unactuated``) asks for more than 1e-9 on a degree of freedom that no
            actuator drives (the message names the joint).
    """
    tau = finite_vector(tau, mm.robot.model.nv, "tau")
    maps = gathers(mm)
    if maps.direct_ctrl is not None:  # every motor drives one joint: one gather
        ctrl = tau[maps.direct_ctrl]
    else:
        ctrl = np.zeros(mm.model.nu)
        ctrl[maps.actuator] = tau[maps.actuated_v]
    if ignore_unactuated or not maps.unactuated:
        return ctrl
    if len(maps.unactuated) <= 8:  # a few entries: plain floats (tau is finite)
        efforts = tau[maps.unactuated_v].tolist()
        if max(efforts) <= UNACTUATED_TOLERANCE and min(efforts) >= -UNACTUATED_TOLERANCE:
            return ctrl
    elif np.abs(tau[maps.unactuated_v]).max() <= UNACTUATED_TOLERANCE:
        return ctrl
    for joint in mm.joints:
        effort = tau[joint.idx_v : joint.idx_v + joint.nv]
        if joint.actuator is None and np.any(np.abs(effort) > UNACTUATED_TOLERANCE):
            raise InvalidInputError(
                f"tau asks for {effort.tolist()} on joint {joint.name!r}, which no actuator "
                f"drives (actuated joints: {', '.join(mm.actuated) or 'none'}); pass "
                "ignore_unactuated=True to drop it."
            )
    return ctrl


def ctrl_to_torques(mm: MujocoModel, ctrl: np.ndarray) -> np.ndarray:
    """Joint efforts ``(model.nv,)`` of actuator controls ``ctrl``, 0 where unactuated.

    Raises:
        InvalidInputError: If ``ctrl`` has the wrong size or non-finite entries.
    """
    ctrl = finite_vector(ctrl, mm.model.nu, "ctrl")
    maps = gathers(mm)
    tau = np.zeros(mm.robot.model.nv)
    tau[maps.actuated_v] = ctrl[maps.actuator]
    return tau
