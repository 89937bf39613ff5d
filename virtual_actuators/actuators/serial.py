"""Serial virtual actuators (VAC 2.1-2.4): a wrench between two frames, ``tau = J^T F``."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..distribution.linalg import stable_norm
from ..distribution.tolerances import JACOBIAN_FLOOR, RCOND
from ..exceptions import ConstraintError, InvalidInputError
from ..kinematics.relative import RelativeKinematics
from ..kinematics.snapshot import Snapshot
from ..models.robot import Robot
from ..vocabulary.arguments import as_float_array, check_number, check_robot
from ..vocabulary.axes import parse_axes, resolve_frame


def wrench_array(wrench: np.ndarray, axes: Sequence[str]) -> np.ndarray:
    """``wrench`` as a finite float64 array of one entry per axis (a float64 array: as given).

    Raises:
        InvalidInputError: Not real numbers, the wrong shape, or a NaN or inf entry.
    """
    if not (isinstance(wrench, np.ndarray) and wrench.dtype == np.float64):
        wrench = as_float_array(
            wrench, "wrench", f"an array of {len(axes)} real numbers (axes {tuple(axes)})"
        )
    if wrench.shape != (len(axes),):
        raise InvalidInputError(
            f"The wrench has shape {wrench.shape}; this actuator's axes {tuple(axes)} need "
            f"({len(axes)},)."
        )
    if not np.isfinite(wrench).all():  # (no squares: no overflow at 1e200)
        raise InvalidInputError(f"The wrench has NaN or inf entries: {wrench}.")
    return wrench


def check_tolerance(tol: object) -> float:
    """``tol`` checked: a finite real number >= 0."""
    return check_number(tol, "tol (the admissibility tolerance)", minimum=0.0)


@dataclass(frozen=True, repr=False)
class ActuatorReading:
    """One reading of a serial actuator's virtual sensor.

    Attributes:
        position: Pose of {B} relative to {A} in {O} on the actuator's axes [m, rad]: the
            orientation as a rotation vector in {O}'s axes (norm at most pi).
        velocity: Its rate ``jacobian @ v`` [m/s, rad/s]: on rotational axes the angular
            velocity of {B} relative to {A} in {O}'s axes.
        jacobian: ``(len(axes), nv)`` Jacobian.
    """

    position: np.ndarray
    velocity: np.ndarray
    jacobian: np.ndarray

    def __repr__(self) -> str:
        return f"ActuatorReading(position={self.position}, velocity={self.velocity})"


class VirtualActuator:
    """A serial virtual actuator between an action frame {B} and a reaction frame {A}.

    Args:
        robot: The robot.
        action: Name of the action frame {B} (the wrench acts on it).
        reaction: Name of the reaction frame {A} (minus the wrench acts on it), or ``"world"``.
        reference: Name of the reference frame {O} whose axes the wrench is expressed along.
        axes: Ordered subset of ``("x", "y", "z", "rx", "ry", "rz")``, or one axis name.

    Raises:
        InvalidInputError: ``robot`` is not a robot (e.g. None or a robot's name).
        FrameNotFoundError: A frame name is not a str or not in the model.
        ConstraintError: The action and reaction frames are the same frame.
        InvalidAxisError: Bad axes.
    """

    def __init__(
        self,
        robot: Robot,
        action: str,
        reaction: str,
        reference: str = "world",
        axes: Sequence[str] = ("x", "y", "z", "rx", "ry", "rz"),
    ) -> None:
        check_robot(robot, "VirtualActuator")
        self.robot = robot
        self.action, self.reaction, self.reference = action, reaction, reference
        self.axes = parse_axes(axes)
        model = robot.model
        action_id = resolve_frame(model, action, "action")
        reaction_id = resolve_frame(model, reaction, "reaction")
        if action_id == reaction_id:
            same = repr(action) if action == reaction else f"{action!r} (= {reaction!r})"
            raise ConstraintError(
                f"The action frame {same} is also the reaction frame; a virtual actuator acts "
                "between two different frames."
            )
        self.kinematics = RelativeKinematics(
            robot, action_id, [reaction_id], resolve_frame(model, reference, "reference"), self.axes
        )

    def read(self, state: np.ndarray | Snapshot, v: np.ndarray | None = None) -> ActuatorReading:
        """Read the virtual sensor: position, velocity and Jacobian from one kinematics pass.

        Args:
            state: A [`Snapshot`][] built with a velocity, or a configuration ``(nq,)``.
            v: Velocity ``(nv,)`` when ``state`` is a configuration.

        Raises:
            InvalidInputError: Bad ``q`` or ``v``, no velocity given, or a snapshot of another
                robot.
        """
        if not isinstance(state, Snapshot):
            if v is None:
                raise InvalidInputError("read(q, v) needs a velocity v (or a Snapshot with v).")
            state = Snapshot(self.robot, state, v)
        jacobian, position, velocity = self.kinematics.sense(state, velocity=True)
        return ActuatorReading(position=position, velocity=velocity, jacobian=jacobian)

    def position(self, state: np.ndarray | Snapshot) -> np.ndarray:
        """Virtual sensor: pose of {B} relative to {A} in {O}, on the selected axes.

        Translations ``R_O^T (p_B - p_A)`` [m]; rotations ``log(R_A^T R_B)`` in {O} [rad].

        Raises:
            InvalidInputError: Bad ``q``, or a snapshot of another robot.
        """
        return self.kinematics.sense(state)[1]

    def jacobian(self, state: np.ndarray | Snapshot) -> np.ndarray:
        """``(len(axes), nv)``: twist of {B} relative to {A} at {B}'s origin, in {O}.

        Raises:
            InvalidInputError: Bad ``q``, or a snapshot of another robot.
        """
        return self.kinematics.sense(state)[0]

    def velocity(self, state: np.ndarray | Snapshot, v: np.ndarray | None = None) -> np.ndarray:
        """Virtual sensor: ``jacobian(q) @ v`` [m/s, rad/s] (angular velocity on rotations).

        Raises:
            InvalidInputError: Bad ``q`` or ``v``, or no velocity given.
        """
        if isinstance(state, Snapshot):
            snapshot = self.kinematics.snapshot(state, need_velocity=True)
            return self.jacobian(snapshot) @ snapshot.v
        if v is None:
            raise InvalidInputError("velocity(q, v) needs a velocity v.")
        v = self.kinematics.tree.check_velocity(v)
        return self.jacobian(state) @ v

    def torques(self, state: np.ndarray | Snapshot, wrench: np.ndarray) -> np.ndarray:
        """Joint torques ``J^T F`` that emulate ``wrench`` on {B} from {A} (VAC eq. 7).

        Raises:
            InvalidInputError: Bad ``q``, or a ``wrench`` that is not ``len(axes)`` finite real
                numbers (complex or bool entries included).
        """
        wrench = wrench_array(wrench, self.axes)
        return self.jacobian(state).T @ wrench

    def is_admissible(
        self, q: np.ndarray | Snapshot, wrench: np.ndarray, tol: float = 1e-9
    ) -> bool:
        """Whether ``wrench`` lies in the range of the Jacobian (it can be produced).

        Args:
            q: Configuration, or a [`Snapshot`][].
            wrench: Wrench over ``axes``.
            tol: Tolerance on the part outside the range, relative to ``|wrench|``.

        Raises:
            InvalidInputError: Bad ``q``, ``wrench`` or ``tol``.
        """
        tol = check_tolerance(tol)
        wrench = wrench_array(wrench, self.axes)
        jac = self.jacobian(q)
        u, s, _ = np.linalg.svd(jac, full_matrices=False)
        # relative rank, with an absolute floor: a direction produced by J < 1e-12 is not
        rank = int(np.sum(s > max(RCOND * s[0], JACOBIAN_FLOOR))) if s.size else 0
        inside = u[:, :rank] @ (u[:, :rank].T @ wrench)
        return stable_norm(wrench - inside) <= tol * stable_norm(wrench)

    def __repr__(self) -> str:
        return (
            f"VirtualActuator(action={self.action!r}, reaction={self.reaction!r}, "
            f"reference={self.reference!r}, axes={self.axes})"
        )
