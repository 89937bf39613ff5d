"""A joint-space spring-damper holding named joints (arms, head, a redundant arm's null space).

``tau_j = k_j (setpoint_j - q_j) - b_j v_j`` [N m or N], projected by ``I - J^T (J^T)^+``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ..exceptions import InvalidInputError, JointNotFoundError, suggestion
from ..kinematics.snapshot import Snapshot
from ..models.robot import Robot
from ..vocabulary.arguments import as_float_array, check_names, check_robot, describe
from .gains import Gains, joint_rows


class Posture:
    """Joint-space spring-damper on named one-degree-of-freedom joints.

    Args:
        joints: Joint names (revolute or prismatic joints).
        stiffness: [N m/rad or N/m], a number or one per joint (>= 0).
        damping: [N m s/rad or N s/m], a number or one per joint (>= 0).
        setpoint: Target positions [rad or m]: one number per joint, a dict ``{joint: value}``
            (joints not named hold their reset pose), or None to hold the reset pose.
        robot: Bind now (else ``Controller.add`` binds it to the controller's robot).
        null_space: A serial [`VirtualActuator`][] whose wrench the efforts must not disturb.
        name: Label used in reports.

    Raises:
        InvalidInputError: Empty or repeated joints, negative or non-finite gains, a setpoint
            of the wrong size or naming a joint not in ``joints``.
        JointNotFoundError: (when bound) A name that is not a joint of the robot (with the
            closest names), or a joint with more than one degree of freedom.

    Example:
        >>> arms = va.Posture(["arm_left_1_joint", "arm_left_2_joint"], 200.0, 10.0)
        >>> controller.add("arms", arms)
    """

    def __init__(
        self,
        joints: Sequence[str],
        stiffness: float | Sequence[float],
        damping: float | Sequence[float],
        setpoint: float | Sequence[float] | Mapping[str, float] | None = None,
        *,
        robot: Robot | None = None,
        null_space: object | None = None,
        name: str | None = None,
    ) -> None:
        names = check_names(joints, "Posture: joints", JointNotFoundError)
        if not names:
            raise InvalidInputError("Posture: joints must name at least one joint.")
        if len(set(names)) != len(names):
            raise InvalidInputError(f"Posture: joints names a joint twice: {list(names)}.")
        self.joints: tuple[str, ...] = tuple(names)
        self.name = name or "Posture"
        self.stiffness = self._per_joint(stiffness, "stiffness", non_negative=True)
        self.damping = self._per_joint(damping, "damping", non_negative=True)
        self._targets = self._setpoint(setpoint)
        self.setpoint: np.ndarray | None = None  # [rad or m], once bound and reset
        self.null_space = null_space
        self.robot: Robot | None = None
        self._plan = False  # the gains and set point are a compiled plan's registers
        #: the joints' configuration and velocity indices, once bound
        self.q_rows = self.v_rows = np.zeros(0, dtype=np.intp)
        if robot is not None:
            self.bind(robot)

    def _per_joint(self, value: object, what: str, non_negative: bool = False) -> np.ndarray:
        """``value``: a finite number (>= 0 if ``non_negative``) or one per joint, as an array."""
        bound = " >= 0" if non_negative else ""
        rule = f"a finite number{bound} or one per joint {list(self.joints)}"
        array = as_float_array(value, f"Posture: {what}", rule, copy=True)
        if array.ndim == 0:
            array = np.full(len(self.joints), float(array))
        bad = array.shape != (len(self.joints),) or not np.isfinite(array).all()
        if bad or (non_negative and (array < 0).any()):
            raise InvalidInputError(f"Posture: {what} must be {rule}, got {describe(value)}.")
        return array

    def _setpoint(self, setpoint: object) -> dict[str, float] | np.ndarray | None:
        if setpoint is None:
            return None
        if isinstance(setpoint, Mapping):
            unknown = [key for key in setpoint if key not in self.joints]
            if unknown:
                raise InvalidInputError(
                    f"Posture: setpoint names {unknown[0]!r}, not one of its joints. "
                    f"{suggestion(str(unknown[0]), self.joints, 'joints')}"
                )
            values = {
                key: float(as_float_array(value, f"Posture: setpoint[{key!r}]", "a number"))
                for key, value in setpoint.items()
            }
            if not all(np.isfinite(list(values.values()))):
                raise InvalidInputError(f"Posture: setpoint must be finite, got {setpoint}.")
            return values
        return self._per_joint(setpoint, "setpoint")

    def plan_slots(self) -> dict[str, np.ndarray]:
        """The arrays a compiled plan keeps: stiffness, damping and set point per joint."""
        if self.setpoint is None:
            self.setpoint = np.zeros(len(self.joints))  # the first reset sets it
        return {"stiffness": self.stiffness, "damping": self.damping, "setpoint": self.setpoint}

    def bind_slots(self, views: dict[str, np.ndarray]) -> None:
        """Keep the gains and the set point in a compiled plan's registers (``views``)."""
        self.stiffness = views["stiffness"]
        self.damping = views["damping"]
        self.setpoint = views["setpoint"]
        self._plan = True

    def traced_torques(self, slots: object, position: tuple, velocity: tuple) -> list:
        """`torques` on a plan's traced joint positions and velocities (its joints only)."""
        k, b, x0 = slots["stiffness"], slots["damping"], slots["setpoint"]
        return [k[i] * (x0[i] - position[i]) - b[i] * velocity[i] for i in range(len(k))]

    def traced_reset(self, slots: object, position: tuple) -> None:
        """`reset` on a plan's traced joint positions."""
        slots.store("setpoint", tuple(self._targets_at(position)))

    def _targets_at(self, position: Sequence) -> list:
        """The set point per joint: the targets given, ``position`` for the others."""
        targets = self._targets
        if isinstance(targets, np.ndarray):
            return targets.tolist()
        if isinstance(targets, dict):
            return [targets.get(j, p) for j, p in zip(self.joints, position, strict=True)]
        return list(position)

    def linear_gains(self) -> Gains:
        """The stiffness and damping per joint (see `Component.linear_gains`)."""
        return Gains(self.stiffness.copy(), self.damping.copy())

    def scale_gains(self, factor: np.ndarray) -> None:
        """Multiply the stiffness and damping of each joint by ``factor``.

        Raises:
            InvalidInputError: ``factor`` is not one number >= 0 per joint.
        """
        factor = self._per_joint(factor, "gain factor", non_negative=True)
        self.stiffness = self.stiffness * factor
        self.damping = self.damping * factor

    def bind(self, robot: Robot) -> Posture:
        """Resolve the joint names on ``robot`` (once); returns ``self``.

        Raises:
            InvalidInputError: Bound to another robot already, or ``robot`` is not a robot.
            JointNotFoundError: An unknown joint (with the closest names), or one with more
                than one degree of freedom.
        """
        check_robot(robot, "Posture")
        if self.robot is not None:
            if self.robot.model is robot.model:
                return self
            raise InvalidInputError(
                f"{self.name}: already bound to robot {self.robot.name!r}; make one per robot."
            )
        model = robot.model
        why = "; a posture holds revolute and prismatic joints"
        q_rows, v_rows = joint_rows(robot, self.joints, self.name, why, strict=True)
        self.q_rows = np.array(q_rows, dtype=np.intp)
        self.v_rows = np.array(v_rows, dtype=np.intp)
        if self.null_space is not None and (
            getattr(self.null_space, "robot", None) is None
            or self.null_space.robot.model is not model
            or not hasattr(self.null_space, "jacobian")
        ):
            raise InvalidInputError(
                f"{self.name}: null_space must be a serial va.VirtualActuator of robot "
                f"{robot.name!r}, got {describe(self.null_space)}."
            )
        self.robot = robot
        if isinstance(self._targets, np.ndarray):
            self.setpoint = self._targets.copy()
        return self

    def reset(self, q: np.ndarray | Snapshot) -> None:
        """Take the current pose as the setpoint of the joints not given one.

        Raises:
            InvalidInputError: Not bound to a robot yet.
        """
        self._check_bound()
        configuration = q.q if isinstance(q, Snapshot) else np.asarray(q, dtype=float)
        current = configuration[self.q_rows].tolist()
        setpoint = np.array(self._targets_at(current))
        if self._plan:  # a compiled plan keeps it: written in place
            self.setpoint[:] = setpoint
        else:
            self.setpoint = setpoint

    def torques(self, q: np.ndarray | Snapshot, v: np.ndarray | None = None) -> np.ndarray:
        """The efforts ``(nv,)`` [N m or N]: the spring-damper on its joints, zero elsewhere.

        Args:
            q: Configuration ``(nq,)``, or a snapshot built with a velocity.
            v: Velocity ``(nv,)`` (omit it with a snapshot).

        Raises:
            InvalidInputError: Not bound, or no velocity.
        """
        self._check_bound()
        if isinstance(q, Snapshot):
            snapshot, configuration, velocity = q, q.q, q.v
        else:
            snapshot, configuration, velocity = None, np.asarray(q, dtype=float), v
        if velocity is None:
            raise InvalidInputError(f"{self.name}: torques() needs a velocity v.")
        if self.setpoint is None:
            self.reset(configuration)
        tau = np.zeros(self.robot.model.nv)
        tau[self.v_rows] = (
            self.stiffness * (self.setpoint - configuration[self.q_rows])
            - self.damping * np.asarray(velocity, dtype=float)[self.v_rows]
        )
        if self.null_space is not None:
            if snapshot is None:
                snapshot = Snapshot(self.robot, configuration)
            jacobian = self.null_space.jacobian(snapshot)  # (axes, nv)
            tau = tau - jacobian.T @ (np.linalg.pinv(jacobian.T, rcond=1e-8) @ tau)
        return tau

    def _check_bound(self) -> None:
        if self.robot is None:
            raise InvalidInputError(
                f"{self.name}: not bound to a robot: give robot= or add it to a va.Controller."
            )

    def __repr__(self) -> str:
        bound = f", robot={self.robot.name!r}" if self.robot is not None else ""
        return f"Posture(joints={list(self.joints)}{bound})"
