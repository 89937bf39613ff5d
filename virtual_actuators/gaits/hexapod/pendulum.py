"""The pendulum on the hexapod's back: its linear model and LQR (VAC 1996, section 4)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ...exceptions import InvalidInputError

GRAVITY = 9.81  # [m/s^2]


@dataclass(frozen=True)
class PendulumModel:
    """The cart-pole linearised about the upright pendulum: ``xdot = A x + B u``.

    State ``(theta, theta_dot, body velocity)`` [rad, rad/s, m/s] (``theta`` > 0 leaning
    forward); input the virtual force on the body in the pendulum's swing plane [N].

    Attributes:
        a: ``(3, 3)``.
        b: ``(3, 1)``.
    """

    a: np.ndarray
    b: np.ndarray


def pendulum_model(body_mass: float, mass: float, com: float, inertia: float) -> PendulumModel:
    """Linearise the cart-pole about ``theta = 0``.

    ``(M + m) a + m l theta'' = F`` and ``m l a + I theta'' = m g l theta``.

    Args:
        body_mass: ``M`` [kg].
        mass: ``m`` [kg].
        com: ``l`` [m].
        inertia: ``I`` [kg m^2], at least ``m l^2``.

    Raises:
        InvalidInputError: A value that is not a positive finite number, or ``I < m l^2``.
    """
    values = (body_mass, mass, com, inertia)
    if not all(isinstance(v, (int, float)) and math.isfinite(v) and v > 0 for v in values):
        raise InvalidInputError(
            f"pendulum_model: masses, com and inertia must be positive numbers, got {values}."
        )
    if inertia < mass * com**2 * (1.0 - 1e-12):
        raise InvalidInputError(
            f"pendulum_model: inertia about the pivot {inertia} is below m l^2 = {mass * com**2}."
        )
    mass_matrix = np.array(((body_mass + mass, mass * com), (mass * com, inertia)))
    inverse = np.linalg.inv(mass_matrix)
    # accelerations (a, theta'') = inverse @ (F, m g l theta)
    a = np.zeros((3, 3))
    a[0, 1] = 1.0
    a[1, 0] = inverse[1, 1] * mass * GRAVITY * com
    a[2, 0] = inverse[0, 1] * mass * GRAVITY * com
    b = np.array([[0.0], [inverse[1, 0]], [inverse[0, 0]]])
    return PendulumModel(a, b)


def lqr_gain(a: np.ndarray, b: np.ndarray, q: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Continuous-time LQR gain ``K`` (``u = -K x``) from the stable subspace of the Hamiltonian.

    Args:
        a: ``(n, n)``.
        b: ``(n, m)``.
        q: ``(n, n)`` state weight, symmetric positive semi-definite.
        r: ``(m, m)`` input weight, symmetric positive definite.

    Returns:
        ``K``, ``(m, n)``.

    Raises:
        InvalidInputError: Shapes that do not match, or no stabilising solution.
    """
    a, b, q, r = (np.atleast_2d(np.asarray(x, dtype=float)) for x in (a, b, q, r))
    n, m = a.shape[0], b.shape[1]
    if a.shape != (n, n) or b.shape != (n, m) or q.shape != (n, n) or r.shape != (m, m):
        raise InvalidInputError(
            f"lqr_gain: shapes A {a.shape}, B {b.shape}, Q {q.shape}, R {r.shape} do not match."
        )
    r_inv = np.linalg.inv(r)
    hamiltonian = np.block([[a, -b @ r_inv @ b.T], [-q, -a.T]])
    values, vectors = np.linalg.eig(hamiltonian)
    stable = vectors[:, values.real < 0.0]
    if stable.shape[1] != n or np.any(np.abs(values.real) < 1e-9):
        raise InvalidInputError(
            "lqr_gain: no stabilising solution (check that (A, B) is stabilisable)."
        )
    p = np.real(stable[n:] @ np.linalg.inv(stable[:n]))
    return r_inv @ b.T @ (0.5 * (p + p.T))


def pendulum_lqr(
    model: pin.Model, joint_name: str, weights: Sequence[float], effort: float
) -> tuple[PendulumModel, np.ndarray, tuple[int, int]]:
    """The pendulum's linear model and LQR from the robot's own inertias (the controller's model).

    Args:
        model: The robot's Pinocchio model (with the pendulum's joint).
        joint_name: The pendulum's joint, about the body's y axis.
        weights: The LQR's state weights (angle, rate, velocity error).
        effort: The LQR's effort weight.

    Returns:
        The `PendulumModel`, the gain ``(1, 3)`` and the joint's ``(q index, v index)``.
    """
    joint = model.getJointId(joint_name)
    inertia = model.inertias[joint]
    com = float(np.linalg.norm(inertia.lever))
    about_pivot = float(inertia.inertia[1, 1]) + inertia.mass * com**2  # about y [kg m^2]
    total = float(sum(i.mass for i in model.inertias))
    pendulum = pendulum_model(total - inertia.mass, inertia.mass, com, about_pivot)
    gain = lqr_gain(pendulum.a, pendulum.b, np.diag(weights), np.array([[effort]]))
    return pendulum, gain, (model.joints[joint].idx_q, model.joints[joint].idx_v)
