"""A controller's effort limits: the URDF's, checked when assigned, and the clip to them."""

from __future__ import annotations

import numpy as np

from ..exceptions import InvalidInputError
from ..models.robot import Robot
from ..vocabulary.arguments import as_float_array


def urdf_effort_limits(robot: Robot) -> np.ndarray:
    """``(nv,)`` effort limits of the URDF [N m or N], ``inf`` where unlimited.

    A 1-dof joint's positive finite ``effortLimit``; ``inf`` elsewhere.
    """
    model = robot.model
    effort = np.asarray(model.effortLimit, dtype=float)
    one_dof = [model.joints[j].idx_v for j in range(1, model.njoints) if model.joints[j].nv == 1]
    usable = [i for i in one_dof if np.isfinite(effort[i]) and effort[i] > 0.0]
    limits = np.full(model.nv, np.inf)
    limits[usable] = effort[usable]
    return limits


def check_effort_limits(limits: object, nv: int) -> tuple[np.ndarray, np.ndarray]:
    """``(lower, upper)`` read-only copies of ``limits`` (``upper``; ``lower = -upper``).

    Raises:
        InvalidInputError: Not ``nv`` numbers, or a NaN or negative entry.
    """
    expected = f"{nv} numbers >= 0 (inf where unlimited)"
    upper = as_float_array(limits, "effort_limits", expected, copy=True)
    if upper.shape != (nv,) or np.isnan(upper).any() or (upper < 0.0).any():
        raise InvalidInputError(f"effort_limits must be {expected}, got {upper}.")
    lower = -upper
    upper.setflags(write=False)
    lower.setflags(write=False)
    return lower, upper


def clip_efforts(
    requested: np.ndarray, lower: np.ndarray, upper: np.ndarray, clip: bool
) -> tuple[np.ndarray, np.ndarray]:
    """``(efforts, saturated)``: ``requested`` clipped to the limits (a copy when not ``clip``).

    ``saturated`` is True where the request exceeds a limit (clipped there when ``clip``).
    """
    if clip:
        tau = np.minimum(np.maximum(requested, lower), upper)
        return tau, tau != requested  # clipped exactly where the request exceeds a limit
    return requested.copy(), np.abs(requested) > upper
