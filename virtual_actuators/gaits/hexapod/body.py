"""The hexapod body's virtual components, in its heading frame, and the pendulum's LQR.

The seed treats the hexapod "as if it were a space ship with virtual thrusters and reaction
wheels" (VAC 1996, section 4): z, roll and pitch held by virtual spring-dampers, x, y and yaw
velocity-controlled by virtual dampers. A robot that turns needs roll and pitch measured about
its *heading* (the body's yaw alone), not about the world axes: the sensor's rotation vector
mixes roll and pitch once the yaw is large (by half the yaw angle), so both components here
read the body's orientation as yaw, pitch, roll (Z-Y-X) and return world-frame wrenches:

* `HeadingAttitude` (axes ``rx, ry, rz``): roll and pitch spring-dampers about the heading
  frame's x and y axes, a damper toward the commanded yaw rate about z;
* `HeadingDamper` (axes ``x, y``): dampers toward a velocity given in the heading frame
  (the seed's commanded magnitude and angle of the body velocity), plus an optional force in
  that frame (the pendulum's LQR thruster).

`lqr_gain` and `pendulum_model` design the pendulum balancer: the cart-pole
linearised about the upright pendulum, state (pendulum angle, its rate, body velocity along the
heading x), input the virtual x force.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ...components.base import Component
from ...exceptions import InvalidInputError
from ..attitude import rotation_vector_angles, yaw_pitch_roll

GRAVITY = 9.81  # [m/s^2]


class HeadingAttitude(Component):
    """Roll and pitch spring-dampers about the heading axes, and a yaw-rate damper.

    Reads the body's rotation vector in the world (the axes ``rx, ry, rz`` of a sensor from the
    world to the body, world reference) and its angular velocity in world axes; returns the
    moment on the body in world axes::

        m_heading = (k_roll (roll_d - roll) - b_roll w_x,
                     k_pitch (pitch_d - pitch) - b_pitch w_y,
                     b_yaw (yaw_rate_d - w_z))          (w in the heading frame)

    Args:
        stiffness: ``(roll, pitch)`` [N m/rad].
        damping: ``(roll, pitch, yaw)`` [N m s/rad].
        name: Label used in reports.

    Attributes:
        roll: Roll set point [rad].
        pitch: Pitch set point [rad].
        yaw_rate: Yaw rate set point [rad/s].
        yaw: The body's yaw at the last evaluation [rad] (read by the gait).

    Raises:
        InvalidInputError: A gain that is not a finite number >= 0, or not 2 (3) of them.

    """

    def __init__(
        self, stiffness: Sequence[float], damping: Sequence[float], name: str | None = None
    ) -> None:
        super().__init__(("rx", "ry", "rz"), name)
        self.stiffness = _gains(stiffness, 2, f"{self.name}: stiffness (roll, pitch)")
        self.damping = _gains(damping, 3, f"{self.name}: damping (roll, pitch, yaw)")
        self.roll = 0.0
        self.pitch = 0.0
        self.yaw_rate = 0.0
        self.yaw = 0.0

    def compute_wrench(self, position: np.ndarray, velocity: np.ndarray, time: float) -> np.ndarray:
        """Moment on the body in world axes from its rotation vector and angular velocity."""
        yaw, pitch, roll = yaw_pitch_roll(pin.exp3(position))
        self.yaw = yaw
        c, s = math.cos(yaw), math.sin(yaw)
        wx = c * velocity[0] + s * velocity[1]  # angular velocity in the heading frame
        wy = -s * velocity[0] + c * velocity[1]
        k, b = self.stiffness, self.damping
        mx = k[0] * (self.roll - roll) - b[0] * wx
        my = k[1] * (self.pitch - pitch) - b[1] * wy
        mz = b[2] * (self.yaw_rate - velocity[2])
        return np.array((c * mx - s * my, s * mx + c * my, mz))

    def compute_wrench_floats(
        self, position: list[float], velocity: list[float], time: float
    ) -> list[float]:
        """`compute_wrench` on plain floats: the same operations, the same bits.

        The angles without the rotation matrix (``gaits.attitude.rotation_vector_angles``:
        ``pin.exp3``'s operations on the entries they read).
        """
        yaw, pitch, roll = rotation_vector_angles(*position)
        self.yaw = yaw
        c, s = math.cos(yaw), math.sin(yaw)
        v0, v1, v2 = velocity
        wx = c * v0 + s * v1  # angular velocity in the heading frame
        wy = -s * v0 + c * v1
        k0, k1 = self.stiffness.tolist()
        b0, b1, b2 = self.damping.tolist()
        mx = k0 * (self.roll - roll) - b0 * wx
        my = k1 * (self.pitch - pitch) - b1 * wy
        mz = b2 * (self.yaw_rate - v2)
        return [c * mx - s * my, s * mx + c * my, mz]


class HeadingDamper(Component):
    """Dampers toward a velocity given in the heading frame, plus a force in that frame.

    Args:
        damping: ``(along, across)`` the heading [N s/m].
        name: Label used in reports.

    Attributes:
        yaw: Heading of the body [rad] (the gait sets it every tick).
        velocity: Commanded body velocity in the heading frame ``(vx, vy)`` [m/s].
        force: Extra force in the heading frame ``(fx, fy)`` [N] (e.g. an LQR's).
        damping: As above; set ``damping[0] = 0`` to leave x to another law.

    Raises:
        InvalidInputError: A damping that is not a finite number >= 0, or not two of them.

    """

    def __init__(self, damping: Sequence[float], name: str | None = None) -> None:
        super().__init__(("x", "y"), name)
        self.damping = _gains(damping, 2, f"{self.name}: damping (along, across)")
        self.yaw = 0.0
        self.velocity = np.zeros(2)
        self.force = np.zeros(2)

    def compute_wrench(self, position: np.ndarray, velocity: np.ndarray, time: float) -> np.ndarray:
        """Force on the body in world axes."""
        floats = np.asarray(velocity, dtype=float).tolist()
        return np.array(self.compute_wrench_floats([], floats, time))

    def compute_wrench_floats(
        self, position: list[float], velocity: list[float], time: float
    ) -> list[float]:
        """`compute_wrench` on plain floats (the position is not read)."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        v0, v1 = velocity
        vx = c * v0 + s * v1
        vy = -s * v0 + c * v1
        d0, d1 = self.damping.tolist()
        cx, cy = np.asarray(self.velocity, dtype=float).tolist()
        f0, f1 = np.asarray(self.force, dtype=float).tolist()
        fx = d0 * (cx - vx) + f0
        fy = d1 * (cy - vy) + f1
        return [c * fx - s * fy, s * fx + c * fy]


def _gains(values: Sequence[float], count: int, what: str) -> np.ndarray:
    try:
        array = np.array(values, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InvalidInputError(f"{what} must be {count} numbers >= 0, got {values!r}.") from None
    if array.shape != (count,) or not np.all(np.isfinite(array)) or np.any(array < 0.0):
        raise InvalidInputError(f"{what} must be {count} finite numbers >= 0, got {values!r}.")
    return array


@dataclass(frozen=True)
class PendulumModel:
    """The cart-pole linearised about the upright pendulum: ``xdot = A x + B u``.

    State ``(theta, theta_dot, body velocity)`` [rad, rad/s, m/s]; input the virtual force on
    the body along the pendulum's swing plane [N]. ``theta`` is positive when the pendulum leans
    forward (its top ahead of the pivot).

    Attributes:
        a: ``(3, 3)``.
        b: ``(3, 1)``.
        body_mass: Mass moved by the virtual force, the pendulum excluded [kg].
        mass: Pendulum mass [kg].
        com: Pivot to the pendulum's centre of mass [m].
        inertia: Pendulum inertia about the pivot [kg m^2].

    """

    a: np.ndarray
    b: np.ndarray
    body_mass: float
    mass: float
    com: float
    inertia: float


def pendulum_model(body_mass: float, mass: float, com: float, inertia: float) -> PendulumModel:
    """Linearise the cart-pole (Lagrange's equations about ``theta = 0``).

    ``(M + m) a + m l theta'' = F`` and ``m l a + I theta'' = m g l theta``, with ``a`` the
    body's acceleration, ``I`` the pendulum's inertia about the pivot.

    Args:
        body_mass: ``M`` [kg].
        mass: ``m`` [kg].
        com: ``l`` [m].
        inertia: ``I`` [kg m^2], at least ``m l^2``.

    Returns:
        The `PendulumModel`.

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
    return PendulumModel(a, b, float(body_mass), float(mass), float(com), float(inertia))


def lqr_gain(a: np.ndarray, b: np.ndarray, q: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Continuous-time LQR gain ``K`` (``u = -K x``) from the stable subspace of the Hamiltonian.

    Solves ``A^T P + P A - P B R^-1 B^T P + Q = 0`` with ``P = U21 U11^-1``, ``[U11; U21]`` the
    eigenvectors of ``[[A, -B R^-1 B^T], [-Q, -A^T]]`` of negative real part.

    Args:
        a: ``(n, n)``.
        b: ``(n, m)``.
        q: ``(n, n)`` state weight, symmetric positive semi-definite.
        r: ``(m, m)`` input weight, symmetric positive definite.

    Returns:
        ``K``, ``(m, n)``.

    Raises:
        InvalidInputError: Shapes that do not match, or no stabilising solution (an
            unstabilisable pair or eigenvalues on the imaginary axis).

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
