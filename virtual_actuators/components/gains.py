"""Gains in physical units: ``k = m omega^2``, ``d = 2 zeta m omega`` from an inertia ``m``."""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np
import pinocchio as pin

from ..exceptions import InvalidInputError, JointNotFoundError, suggestion
from ..models.robot import Robot
from ..vocabulary.arguments import as_float_array, check_number
from ..vocabulary.axes import parse_axes


class Gains(NamedTuple):
    """Stiffness and damping, one entry per axis or joint.

    Attributes:
        stiffness: [N/m, N m/rad].
        damping: [N s/m, N m s/rad].
    """

    stiffness: np.ndarray
    damping: np.ndarray


def gains(inertia: float | Sequence[float], frequency: float, damping_ratio: float = 1.0) -> Gains:
    """Stiffness ``m omega^2`` and damping ``2 zeta m omega`` of inertias ``m``.

    Args:
        inertia: Mass [kg] or moment of inertia [kg m^2], one or several (>= 0).
        frequency: Natural frequency ``omega`` [rad/s] (> 0).
        damping_ratio: ``zeta`` (>= 0; 1 is critical damping).

    Returns:
        The [`Gains`][] (arrays shaped like ``inertia``).

    Raises:
        InvalidInputError: A negative or non-finite inertia, ``frequency`` not > 0,
            ``damping_ratio`` < 0.
    """
    frequency = check_number(frequency, "frequency [rad/s]", positive=True)
    damping_ratio = check_number(damping_ratio, "damping_ratio", minimum=0.0)
    m = as_float_array(inertia, "inertia", "masses [kg] or inertias [kg m^2]", copy=True)
    if not np.isfinite(m).all() or (m < 0).any():
        raise InvalidInputError(f"inertia must be finite and >= 0, got {inertia!r}.")
    return Gains(m * frequency**2, 2.0 * damping_ratio * m * frequency)


def joint_gains(
    robot: Robot,
    joints: Sequence[str],
    frequency: float,
    damping_ratio: float = 1.0,
    q: np.ndarray | None = None,
) -> Gains:
    """Gains of joints from their inertia at ``q`` (the joint-space mass matrix's diagonal).

    Args:
        robot: The robot.
        joints: Names of one-degree-of-freedom joints.
        frequency: Natural frequency [rad/s].
        damping_ratio: Damping ratio.
        q: Configuration (default: [`Robot.neutral`][]).

    Returns:
        The [`Gains`][], one entry per joint.

    Raises:
        JointNotFoundError: An unknown joint (with close matches) or one with several degrees
            of freedom.
        InvalidInputError: A bad ``frequency``, ``damping_ratio`` or ``q``.
    """
    model = robot.model
    q = _configuration(robot, q, "joint_gains")
    _, columns = joint_rows(robot, joints, "joint_gains")
    mass_matrix = pin.crba(model, model.createData(), q)
    return gains(np.diag(mass_matrix)[columns], frequency, damping_ratio)


def body_gains(
    robot: Robot,
    frequency: float,
    damping_ratio: float = 1.0,
    axes: Sequence[str] = ("x", "y", "z", "rx", "ry", "rz"),
    q: np.ndarray | None = None,
) -> Gains:
    """Gains of a body actuator carrying the whole robot: its mass, its centroidal inertia.

    Moments use the diagonal of the centroidal inertia at ``q`` (world axes).

    Args:
        robot: The robot.
        frequency: Natural frequency [rad/s].
        damping_ratio: Damping ratio.
        axes: The actuator's axes.
        q: Configuration (default: [`Robot.neutral`][]).

    Returns:
        The [`Gains`][], one entry per axis.

    Raises:
        InvalidAxisError: Bad axes.
        InvalidInputError: A bad ``frequency``, ``damping_ratio`` or ``q``, or a massless robot.
    """
    axes = parse_axes(axes, "body_gains: axes")
    model = robot.model
    q = _configuration(robot, q, "body_gains")
    if not robot.mass > 0.0:
        raise InvalidInputError(f"body_gains: robot {robot.name!r} has no mass.")
    data = model.createData()
    pin.ccrba(model, data, q, np.zeros(model.nv))
    rotational = np.diag(np.array(data.Ig.inertia))
    inertias = [
        robot.mass if axis in ("x", "y", "z") else float(rotational["xyz".index(axis[1])])
        for axis in axes
    ]
    return gains(inertias, frequency, damping_ratio)


def _configuration(robot: Robot, q: np.ndarray | None, who: str) -> np.ndarray:
    """``q`` checked (``robot.neutral()`` for None)."""
    model = robot.model
    q = robot.neutral() if q is None else as_float_array(q, "q", f"{model.nq} numbers")
    if q.shape != (model.nq,) or not np.isfinite(q).all():
        raise InvalidInputError(f"{who}: q must be {model.nq} finite numbers.")
    return q


def joint_rows(
    robot: Robot, joints: Sequence[str], who: str, why: str = "", strict: bool = False
) -> tuple[list[int], list[int]]:
    """The configuration and velocity rows of one-degree-of-freedom joints (``who``: caller).

    Raises:
        JointNotFoundError: An unknown joint (with close matches) or one with several degrees
            of freedom.
    """
    model = robot.model
    known = list(model.names)[1:]
    q_rows, v_rows = [], []
    for joint in joints:
        if joint not in known:
            raise JointNotFoundError(
                f"{who}: robot {robot.name!r} has no joint {joint!r}. "
                f"{suggestion(str(joint), known, 'joints')}"
            )
        data = model.joints[model.getJointId(joint)]
        if data.nv != 1 or (strict and data.nq != 1):
            raise JointNotFoundError(
                f"{who}: joint {joint!r} has {data.nv} degrees of freedom{why}."
            )
        q_rows.append(data.idx_q)
        v_rows.append(data.idx_v)
    return q_rows, v_rows
