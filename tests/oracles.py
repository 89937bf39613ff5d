"""Oracles shared by the correctness tests: everything here uses Pinocchio and numpy only.

Nothing in this file imports the library's internals: the oracles rebuild every quantity (frame
placements, relative Jacobians, external forces, the force distribution) from Pinocchio so that
a bug in the library cannot hide in the reference.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pinocchio as pin
import pytest

import virtual_actuators as va
from virtual_actuators.core import CORE

#: Skips a test of the compiled core's own paths when it is not built (or VA_CORE=0): the numpy
#: paths then answer, and the tests of behaviour run on them.
requires_core = pytest.mark.skipif(
    CORE is None, reason="the compiled core is not built (or VA_CORE=0)"
)

AXES = ("x", "y", "z", "rx", "ry", "rz")


# -- robots and configurations ---------------------------------------------------------------
@functools.cache
def robot(name: str) -> va.Robot:
    """A robot loaded once per test session (treat it as read-only)."""
    return va.load_robot(name)


@functools.cache
def millipede(legs: int) -> va.Robot:
    return va.millipede(legs=legs)


@functools.cache
def zero_gravity_model(name: str) -> pin.Model:
    """A copy of the robot's model with gravity set to zero (for the RNEA oracle)."""
    model = pin.Model(robot(name).model)
    model.gravity.setZero()
    return model


def random_configuration(rob: va.Robot, rng: np.random.Generator, scale: float = 0.5):
    """``robot.neutral()`` moved by a random tangent vector (works with infinite base limits)."""
    model = rob.model
    q = pin.integrate(model, rob.neutral(), rng.uniform(-scale, scale, model.nv))
    return pin.normalize(model, q)


def frame_id(model: pin.Model, name: str) -> int:
    return 0 if name == "world" else int(model.getFrameId(name))


def placements(model: pin.Model, q: np.ndarray) -> pin.Data:
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    return data


def full_wrench(axes, wrench) -> np.ndarray:
    """The 6-vector (f, m) with the entries of unselected axes set to zero."""
    out = np.zeros(6)
    for axis, value in zip(axes, wrench, strict=True):
        out[AXES.index(axis)] = value
    return out


def yaw_pitch_roll(rotation: np.ndarray) -> tuple[float, float, float]:
    """Z-Y-X angles of a rotation matrix ``R = Rz(yaw) Ry(pitch) Rx(roll)`` [rad]."""
    (r00, _, _), (r10, _, _), (r20, r21, r22) = np.asarray(rotation, dtype=float).tolist()
    return math.atan2(r10, r00), math.asin(max(-1.0, min(1.0, -r20))), math.atan2(r21, r22)


def axis_rows(axes) -> list[int]:
    return [AXES.index(a) for a in axes]


# -- RNEA oracle ------------------------------------------------------------------------------
def external_forces(model: pin.Model, q: np.ndarray, pairs) -> list:
    """Per-joint external forces (local joint frames) for a list of action/reaction pairs.

    Each pair is ``(action, reaction, reference, axes, wrench)``: ``+wrench`` (forces along and
    moments about {O}'s axes, moments about {B}'s origin) on {B}'s parent joint and ``-wrench``
    at the same point on {A}'s parent joint (nothing when {A} is the world).
    """
    data = placements(model, q)
    fext = [pin.Force.Zero() for _ in range(model.njoints)]
    for action, reaction, reference, axes, wrench in pairs:
        fid_b, fid_a = frame_id(model, action), frame_id(model, reaction)
        rot_o = data.oMf[frame_id(model, reference)].rotation
        w6 = full_wrench(axes, wrench)
        force_w, moment_w = rot_o @ w6[:3], rot_o @ w6[3:]
        p_b = data.oMf[fid_b].translation
        # about the world origin: same force, moment m + p x f
        spatial = pin.Force(force_w, moment_w + np.cross(p_b, force_w))
        for fid, sign in ((fid_b, 1.0), (fid_a, -1.0)):
            joint = model.frames[fid].parentJoint
            if joint == 0:
                continue
            fext[joint] = fext[joint] + data.oMi[joint].actInv(spatial * sign)
    return fext


def chain_forces_world(body, q: np.ndarray, forces: np.ndarray) -> np.ndarray:
    """``(p, 3)`` each chain's force on {B} in world axes (``R_O f``), from Pinocchio's {O}."""
    model = body.robot.model
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    rotation_o = (
        np.eye(3)
        if body.reference == "world"
        else data.oMf[model.getFrameId(body.reference)].rotation
    )
    full = np.zeros((body.p, 6))
    full[:, [AXES.index(a) for a in body.axes]] = forces
    return full[:, :3] @ rotation_o.T


def rnea_torques(name_or_model, q: np.ndarray, fext) -> np.ndarray:
    """``-rnea(q, 0, 0, fext)`` without gravity: joint torques that balance ``fext``."""
    model = zero_gravity_model(name_or_model) if isinstance(name_or_model, str) else name_or_model
    assert not np.any(model.gravity.linear)
    data = model.createData()
    zero = np.zeros(model.nv)
    return -pin.rnea(model, data, q, zero, zero, fext)


# -- relative Jacobian (independent construction) ---------------------------------------------
def relative_jacobian(model: pin.Model, q: np.ndarray, action: str, reaction: str, reference: str):
    """6 x nv twist of {B} relative to {A} at {B}'s origin in {O}'s axes, from frame Jacobians."""
    data = model.createData()
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    lwa = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    fid_b, fid_a = frame_id(model, action), frame_id(model, reaction)
    jac_b = pin.getFrameJacobian(model, data, fid_b, lwa)
    if fid_a == 0:
        jac_a = np.zeros_like(jac_b)
    else:
        jac_a = pin.getFrameJacobian(model, data, fid_a, lwa).copy()
        offset = data.oMf[fid_b].translation - data.oMf[fid_a].translation
        # velocity of A's body point at B's origin: v_A + w_A x (p_B - p_A)
        jac_a[:3] += np.cross(jac_a[3:].T, offset).T
    rot_o = data.oMf[frame_id(model, reference)].rotation
    rel = jac_b - jac_a
    return np.vstack((rot_o.T @ rel[:3], rot_o.T @ rel[3:]))


def path_columns(model: pin.Model, action: str, reaction: str) -> np.ndarray:
    """Velocity indices of the joints between the two frames (symmetric difference of supports)."""
    ja = model.frames[frame_id(model, reaction)].parentJoint
    jb = model.frames[frame_id(model, action)].parentJoint
    joints = set(model.supports[ja]) ^ set(model.supports[jb])
    cols = []
    for j in sorted(joints):
        if j == 0:
            continue
        joint = model.joints[j]
        cols += list(range(joint.idx_v, joint.idx_v + joint.nv))
    return np.array(sorted(cols), dtype=int)


def joint_v(model: pin.Model, name: str) -> int:
    joint = model.joints[model.getJointId(name)]
    assert joint.nv == 1
    return joint.idx_v


def joint_angle(model: pin.Model, q: np.ndarray, name: str) -> float:
    joint = model.joints[model.getJointId(name)]
    if joint.nq == 2:
        return float(np.arctan2(q[joint.idx_q + 1], q[joint.idx_q]))
    return float(q[joint.idx_q])


# -- independent force-distribution oracle ------------------------------------------------------
class ReferenceDistribution:
    """Rebuild the distribution problem from Pinocchio and solve it with ``pinv``.

    Unknowns: all chains' wrenches stacked ``(p * n,)``. Exact rows: for each chain, zero
    component on the directions its joints and point contact cannot produce (left null space of
    ``[J_i, ball_i]``), prescribed torque at its own limp / passive joints, zero moment about the
    reaction origin at a point contact; shared limp / passive joints: summed torque; design rows.
    Wrench rows: ``sum_i F_i = w`` on the prescribed axes.
    """

    def __init__(
        self,
        rob,
        action,
        reactions,
        reference,
        axes,
        contact,
        unactuated=(),
        passive=None,
        design=(),
    ):
        self.rob, self.model = rob, rob.model
        self.action, self.reactions, self.reference = action, list(reactions), reference
        self.axes, self.rows = tuple(axes), axis_rows(axes)
        self.n, self.p = len(axes), len(reactions)
        if isinstance(contact, str):
            contact = {r: contact for r in reactions}
        self.contact = {r: contact.get(r, "point") for r in reactions}
        self.limp = list(unactuated)
        self.passive = dict(passive or {})
        self.design = list(design)

    def chain_jacobians(self, q):
        out = []
        for r in self.reactions:
            jac = relative_jacobian(self.model, q, self.action, r, self.reference)[self.rows]
            mask = np.zeros(self.model.nv, dtype=bool)
            mask[path_columns(self.model, self.action, r)] = True
            out.append(np.where(mask[None, :], jac, 0.0))
        return out

    def ball_columns(self, q, reaction):
        data = placements(self.model, q)
        rot_o = data.oMf[frame_id(self.model, self.reference)].rotation
        d = rot_o.T @ (
            data.oMf[frame_id(self.model, self.action)].translation
            - data.oMf[frame_id(self.model, reaction)].translation
        )
        cols = []
        for k in range(3):
            if AXES[3 + k] not in self.axes:
                continue
            e = np.eye(3)[k]
            cols.append(np.concatenate((np.cross(e, d), e))[self.rows])
        return np.array(cols).reshape(-1, self.n).T

    def system(self, q, wrench, free=(), rank_tol=1e-7):
        """Return ``(hard, hard_rhs, soft, soft_rhs)`` over the stacked wrenches."""
        model, n, p = self.model, self.n, self.p
        jacs = self.chain_jacobians(q)
        hard, rhs = [], []

        def row_for(chain, vec):
            row = np.zeros(p * n)
            row[chain * n : (chain + 1) * n] = vec
            return row

        constrained = {joint_v(model, j): 0.0 for j in self.limp}
        for name, (k, rest) in self.passive.items():
            constrained[joint_v(model, name)] = -k * (joint_angle(model, q, name) - rest)
        for i, r in enumerate(self.reactions):
            cols = path_columns(model, self.action, r)
            full = jacs[i][:, cols]
            if self.contact[r] == "point":
                ball = self.ball_columns(q, r)
                full = np.hstack((full, ball))
                for c in range(ball.shape[1]):
                    hard.append(row_for(i, ball[:, c]))
                    rhs.append(0.0)
            u, s, _ = np.linalg.svd(full)
            rank = int(np.sum(s > rank_tol * s[0]))
            for c in range(rank, n):
                hard.append(row_for(i, u[:, c]))
                rhs.append(0.0)
        for v, torque in constrained.items():
            row = np.concatenate([jacs[i][:, v] for i in range(p)])
            hard.append(row)
            rhs.append(torque)
        for constraint in self.design:
            row = np.zeros(p * n)
            if isinstance(constraint, va.Equal):
                row[self.index(constraint.a)] += 1.0
                row[self.index(constraint.b)] -= 1.0
                rhs.append(0.0)
            elif isinstance(constraint, va.Linear):
                for label, coeff in constraint.coefficients.items():
                    row[self.index(label)] += coeff
                rhs.append(constraint.rhs)
            else:
                va_, vb = joint_v(model, constraint.joint_a), joint_v(model, constraint.joint_b)
                row = np.concatenate([jacs[i][:, va_] - jacs[i][:, vb] for i in range(p)])
                rhs.append(0.0)
            hard.append(row)
        keep = [k for k, a in enumerate(self.axes) if a not in free]
        soft = np.tile(np.eye(n), (1, p))[keep]
        return (
            np.array(hard).reshape(-1, p * n),
            np.array(rhs),
            soft,
            np.asarray(wrench, dtype=float)[keep],
        )

    def index(self, label):
        reaction, axis = label
        return self.reactions.index(reaction) * self.n + self.axes.index(axis)

    def solve(self, q, wrench, free=()):
        """Minimum-norm distribution meeting every row (the request must be admissible)."""
        hard, hard_rhs, soft, soft_rhs = self.system(q, wrench, free)
        k = np.vstack((hard, soft))
        x = np.linalg.pinv(k, rcond=1e-10) @ np.concatenate((hard_rhs, soft_rhs))
        assert np.allclose(k @ x, np.concatenate((hard_rhs, soft_rhs)), atol=1e-8), "inadmissible"
        return x.reshape(self.p, self.n)

    def least_squares(self, q, wrench, free=()):
        """Exact rows hold; the wrench rows in the least-squares sense; then minimum norm."""
        hard, hard_rhs, soft, soft_rhs = self.system(q, wrench, free)
        x_hard = np.linalg.lstsq(hard, hard_rhs, rcond=None)[0]
        assert np.allclose(hard @ x_hard, hard_rhs, atol=1e-9)
        _, s, vt = np.linalg.svd(hard)
        rank = int(np.sum(s > 1e-10 * s[0]))
        null = vt[rank:].T  # feasible directions; x_hard (minimum norm) is orthogonal to them
        z = np.linalg.pinv(soft @ null, rcond=1e-10) @ (soft_rhs - soft @ x_hard)
        return (x_hard + null @ z).reshape(self.p, self.n)

    def feasible_directions(self, q, wrench, free=()):
        """Orthonormal basis of the distributions changes that keep every row satisfied."""
        hard, _, soft, _ = self.system(q, wrench, free)
        k = np.vstack((hard, soft))
        _, s, vt = np.linalg.svd(k)
        rank = int(np.sum(s > 1e-10 * s[0]))
        return vt[rank:].T


def relative_error(a, b) -> float:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return float(np.max(np.abs(a - b)) / max(1.0, np.max(np.abs(b))))


# -- walks -----------------------------------------------------------------------------------
def assert_same_walk(one: object, other: object) -> None:
    """Two walks' results (``run_walk``'s) agree bit for bit: every log channel, the states,
    the machine's history and every tick's efforts and velocities (a compiled machine against
    the Python machine, its oracle)."""
    assert one.log.data.keys() == other.log.data.keys()
    for name, values in one.log.data.items():
        np.testing.assert_array_equal(values, other.log.data[name], err_msg=name)
    np.testing.assert_array_equal(one.log.state, other.log.state)
    assert one.gait.machine.history == other.gait.machine.history
    np.testing.assert_array_equal(one.loop.efforts, other.loop.efforts)
    np.testing.assert_array_equal(one.loop.velocities, other.loop.velocities)
    assert one.smoothness == other.smoothness
