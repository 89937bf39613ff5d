"""Relative kinematics of an action frame {B} with respect to reaction frames {A_i}, in {O}.

One :class:`RelativeKinematics` serves a serial actuator (one reaction frame) or a parallel one
(several). Everything that depends only on the kinematic tree (which joints lie between {A_i}
and {B}, with which sign) is computed once in the constructor; :meth:`RelativeKinematics.compute`
does one Pinocchio pass per configuration and returns every chain's Jacobian at once.

Conventions (VAC eq. 1-7): the twist of {B} relative to {A_i} is taken at {B}'s origin, with
{A_i}'s velocity taken at the point of {A_i}'s body that coincides with {B}'s origin, and both
linear and angular parts are expressed in {O}'s orientation. Its transpose maps a wrench on {B}
(force, and moment about {B}'s origin, in {O}) to joint torques exactly like the pair of
external wrenches "+wrench on {B}, -wrench on {A_i}" does.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from ..declaration.frames import AXES, axis_rows
from ..exceptions import InvalidInputError


@dataclass(frozen=True)
class KinematicState:
    """What :meth:`RelativeKinematics.compute` returns for one configuration.

    Attributes:
        jacobian_o: ``(n, nv)`` rows ``axes`` of the world-frame joint Jacobians shifted to
            {B}'s origin and rotated into {O}; chain ``i``'s Jacobian is
            ``jacobian_o * signs[i]``.
        rotation_o: ``(3, 3)`` orientation of {O} in the world.
        position_b: ``(3,)`` position of {B}'s origin in the world [m].
        rotation_b: ``(3, 3)`` orientation of {B} in the world.
        position_a: ``(p, 3)`` positions of the reaction frames' origins in the world [m].
        rotation_a: ``(p, 3, 3)`` orientations of the reaction frames in the world.

    """

    jacobian_o: np.ndarray
    rotation_o: np.ndarray
    position_b: np.ndarray
    rotation_b: np.ndarray
    position_a: np.ndarray
    rotation_a: np.ndarray

    def offsets_o(self) -> np.ndarray:
        """Return ``(p, 3)`` vectors from each {A_i}'s origin to {B}'s origin, in {O} [m]."""
        return (self.position_b[None, :] - self.position_a) @ self.rotation_o


class RelativeKinematics:
    """Jacobians and virtual sensors of {B} relative to each {A_i}, expressed in {O}.

    Args:
        model: Pinocchio model.
        action_id: Frame id of {B}.
        reaction_ids: Frame ids of the {A_i}.
        reference_id: Frame id of {O}.
        axes: Selected axes (an ordered subset of :data:`~virtual_actuators.AXES`).

    """

    def __init__(
        self,
        model: pin.Model,
        action_id: int,
        reaction_ids: Sequence[int],
        reference_id: int,
        axes: Sequence[str],
    ) -> None:
        self.model = model
        self.data = pin.Data(model)
        self.action_id = int(action_id)
        self.reaction_ids = np.array(reaction_ids, dtype=int)
        self._reaction_list = [int(r) for r in reaction_ids]
        self.reference_id = int(reference_id)
        self.axes = tuple(axes)
        self.rows = axis_rows(self.axes)
        self.nq, self.nv = model.nq, model.nv
        self._quaternion_slices = _quaternion_slices(model)
        action_joint = model.frames[self.action_id].parentJoint
        #: ``(p, nv)`` entries +1 for velocity indices between {A_i} and {B} on {B}'s side,
        #: -1 on {A_i}'s side, 0 elsewhere (shared ancestors and other branches cancel).
        self.signs = np.stack(
            [
                self._path_signs(model, action_joint, model.frames[int(r)].parentJoint)
                for r in self.reaction_ids
            ]
        )

    @staticmethod
    def _path_signs(model: pin.Model, joint_b: int, joint_a: int) -> np.ndarray:
        support_b = set(model.supports[joint_b])
        support_a = set(model.supports[joint_a])
        signs = np.zeros(model.nv)
        for joint_id, sign in [(j, 1.0) for j in support_b - support_a] + [
            (j, -1.0) for j in support_a - support_b
        ]:
            joint = model.joints[joint_id]
            signs[joint.idx_v : joint.idx_v + joint.nv] = sign
        return signs

    def check_configuration(self, q: np.ndarray) -> np.ndarray:
        """Return ``q`` as a float array after checking its shape, values and quaternions.

        Args:
            q: Configuration, shape ``(model.nq,)``.

        Returns:
            ``q`` as a float64 array; quaternions and (cos, sin) pairs within 1e-3 of unit
            norm are normalised (a copy is made then).

        Raises:
            InvalidInputError: Wrong shape, NaN or inf, or a quaternion far from unit norm.

        """
        q = np.asarray(q, dtype=float)
        if q.shape != (self.nq,):
            raise InvalidInputError(
                f"Configuration q has shape {q.shape}; model {self.model.name!r} needs "
                f"({self.nq},) (model.nq)."
            )
        if not np.all(np.isfinite(q)):
            bad = np.flatnonzero(~np.isfinite(q)).tolist()
            raise InvalidInputError(f"Configuration q has NaN or inf at indices {bad}.")
        normalized = False
        for s in self._quaternion_slices:
            norm = float(np.linalg.norm(q[s]))
            if abs(norm - 1.0) > 1e-3:
                kind = "(cos, sin) pair" if s.stop - s.start == 2 else "quaternion"
                raise InvalidInputError(
                    f"Configuration q[{s.start}:{s.stop}] is a {kind} of norm {norm:.6g}; "
                    f"it must have unit norm (see pinocchio.normalize)."
                )
            if abs(norm - 1.0) > 1e-12:
                if not normalized:
                    q, normalized = q.copy(), True
                q[s] /= norm  # integration drift: use the exact unit quaternion
        return q

    def check_velocity(self, v: np.ndarray) -> np.ndarray:
        """Return ``v`` as a float array after checking its shape and values.

        Raises:
            InvalidInputError: Wrong shape, NaN or inf.

        """
        v = np.asarray(v, dtype=float)
        if v.shape != (self.nv,):
            raise InvalidInputError(
                f"Velocity v has shape {v.shape}; model {self.model.name!r} needs ({self.nv},) "
                "(model.nv)."
            )
        if not np.all(np.isfinite(v)):
            raise InvalidInputError("Velocity v has NaN or inf entries.")
        return v

    def compute(self, q: np.ndarray) -> KinematicState:
        """Run the kinematics at ``q`` (already checked) and return the Jacobian rows in {O}.

        Args:
            q: Configuration, shape ``(model.nq,)``.

        Returns:
            The :class:`KinematicState`.

        """
        model, data = self.model, self.data
        pin.computeJointJacobians(model, data, q)
        pin.updateFramePlacements(model, data)
        oMf = data.oMf
        placement_b = oMf[self.action_id]
        # data.J and the placements are views into Pinocchio's memory: copy what is kept
        position_b = placement_b.translation.copy()
        rotation_o = oMf[self.reference_id].rotation.copy()
        jacobian_world = data.J.reshape(2, 3, -1)
        x, y, z = position_b
        # velocity of the point at {B}'s origin: v + w x p_B = v - skew(p_B) w
        shift = np.array(((0.0, z, -y), (-z, 0.0, x), (y, -x, 0.0)))
        shifted = np.stack((jacobian_world[0] + shift @ jacobian_world[1], jacobian_world[1]))
        jacobian_o = (rotation_o.T @ shifted).reshape(6, -1)[self.rows]
        placements_a = [oMf[r] for r in self._reaction_list]
        return KinematicState(
            jacobian_o=jacobian_o,
            rotation_o=rotation_o,
            position_b=position_b,
            rotation_b=placement_b.rotation.copy(),
            position_a=np.array([m.translation for m in placements_a]),
            rotation_a=np.array([m.rotation for m in placements_a]),
        )

    def positions(self, state: KinematicState) -> np.ndarray:
        """Virtual sensors: pose of {B} relative to each {A_i}, in {O}, on the selected axes.

        Translations are ``R_O^T (p_B - p_A)`` [m]; rotations are the rotation vector
        ``log(R_A^T R_B)`` of {B} relative to {A}, expressed in {O} [rad].

        Returns:
            ``(p, n)`` array.

        """
        out = np.empty((len(self.reaction_ids), 6))
        out[:, :3] = state.offsets_o()
        for i, rotation_a in enumerate(state.rotation_a):
            relative = pin.log3(rotation_a.T @ state.rotation_b)
            out[i, 3:] = state.rotation_o.T @ (rotation_a @ relative)
        return out[:, self.rows]

    def __repr__(self) -> str:
        names = [self.model.frames[int(r)].name for r in self.reaction_ids]
        return (
            f"RelativeKinematics(action={self.model.frames[self.action_id].name!r}, "
            f"reactions={names}, reference={self.model.frames[self.reference_id].name!r}, "
            f"axes={self.axes})"
        )


def skew(vector: np.ndarray) -> np.ndarray:
    """Return the ``(..., 3, 3)`` cross-product matrices of ``(..., 3)`` vectors."""
    vector = np.asarray(vector)
    out = np.zeros(vector.shape[:-1] + (3, 3))
    x, y, z = vector[..., 0], vector[..., 1], vector[..., 2]
    out[..., 0, 1], out[..., 0, 2] = -z, y
    out[..., 1, 0], out[..., 1, 2] = z, -x
    out[..., 2, 0], out[..., 2, 1] = -y, x
    return out


def _quaternion_slices(model: pin.Model) -> list[slice]:
    """Slices of ``q`` that must have unit norm.

    Free-flyer and spherical joints hold quaternions; continuous (unbounded revolute) joints hold
    a ``(cos, sin)`` pair.
    """
    slices = []
    for joint in list(model.joints)[1:]:
        if joint.shortname() == "JointModelFreeFlyer":
            slices.append(slice(joint.idx_q + 3, joint.idx_q + 7))
        elif joint.shortname() == "JointModelSpherical":
            slices.append(slice(joint.idx_q, joint.idx_q + 4))
        elif joint.nq == 2 and joint.nv == 1:
            slices.append(slice(joint.idx_q, joint.idx_q + 2))
    return slices


__all__ = ["AXES", "KinematicState", "RelativeKinematics", "skew"]
