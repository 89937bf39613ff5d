"""Serial virtual actuators against Pinocchio oracles (RNEA, finite differences, frame poses).

Properties checked on arms, quadrupeds and humanoids, on frame pairs whose path goes up and down
the kinematic tree, for random configurations, random wrenches, several axis subsets and
references ("world", the action frame, the reaction frame, a third frame):

- ``torques(q, w)`` equals the joint torques that balance ``+w`` on {B} and ``-w`` on {A}
  (Pinocchio's RNEA with external forces, no gravity, no motion);
- ``jacobian(q)`` equals finite differences of the pose of {B} seen from {A}, rotated into {O};
- ``velocity(q, v) == jacobian(q) @ v``; columns off the path between the frames are zero;
- ``is_admissible`` accepts exactly the wrenches in the column space of the Jacobian.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from oracles import (
    AXES,
    axis_rows,
    external_forces,
    frame_id,
    path_columns,
    placements,
    random_configuration,
    relative_error,
    rnea_torques,
    robot,
)

import virtual_actuators as va

# (robot, action {B}, reaction {A}, a third frame on another branch)
CASES = [
    ("ur5_robot", "tool0", "world", "forearm_link"),
    ("ur5_robot", "wrist_2_link", "upper_arm_link", "tool0"),
    ("panda", "panda_hand_tcp", "world", "panda_link3"),
    ("panda", "panda_link7", "panda_link2", "panda_leftfinger"),
    ("solo12", "base_link", "FL_FOOT", "HR_FOOT"),
    ("solo12", "FL_FOOT", "HR_FOOT", "FR_FOOT"),
    ("solo12", "HL_FOOT", "world", "base_link"),
    ("anymal", "base", "LF_FOOT", "RH_FOOT"),
    ("anymal", "RH_FOOT", "LF_FOOT", "LH_FOOT"),
    ("hyq_no_sensors", "base_link", "rf_foot", "lh_foot"),
    ("hyq_no_sensors", "lh_foot", "rf_foot", "base_link"),
    ("talos_reduced", "left_sole_link", "gripper_right_base_link", "head_2_link"),
    ("talos_reduced", "torso_2_link", "right_sole_link", "left_sole_link"),
    ("talos_reduced", "gripper_left_base_link", "world", "torso_1_link"),
    ("go2", "base", "FL_foot", "RR_foot"),
    ("go2", "FR_foot", "RL_foot", "base"),
    ("g1_29dof_rev_1_0", "left_rubber_hand", "right_ankle_roll_link", "torso_link"),
    ("g1_29dof_rev_1_0", "torso_link", "left_ankle_roll_link", "right_rubber_hand"),
]
CASE_IDS = [f"{r}:{b}<-{a}" for r, b, a, _ in CASES]
REFERENCES = ("world", "action", "reaction", "third")

axes_subsets = st.one_of(
    st.sampled_from([AXES, ("x", "z", "ry"), ("rz",), ("x", "y", "z"), ("rx", "ry", "rz")]),
    st.lists(st.sampled_from(AXES), min_size=1, max_size=6, unique=True).map(
        lambda a: tuple(sorted(a, key=AXES.index))
    ),
)


def reference_name(case, kind: str) -> str:
    _, action, reaction, third = case
    return {"world": "world", "action": action, "reaction": reaction, "third": third}[kind]


def finite_difference_jacobian(model, q, action, reaction, reference, eps=1e-6):
    """Central differences of the pose of {B} in {A}, as a twist at {B}'s origin in {O}.

    Translational rows: ``R_O^T R_A d/dq[R_A^T (p_B - p_A)]``; rotational rows: the
    left-trivialised derivative of ``R_A^T R_B`` (an angular velocity in {A}), rotated into {O}.
    """
    fid_b, fid_a, fid_o = (frame_id(model, f) for f in (action, reaction, reference))

    def pose(qq):
        data = placements(model, qq)
        a, b = data.oMf[fid_a], data.oMf[fid_b]
        return a.rotation.T @ (b.translation - a.translation), a.rotation.T @ b.rotation

    data0 = placements(model, q)
    to_o = data0.oMf[fid_o].rotation.T @ data0.oMf[fid_a].rotation
    out = np.zeros((6, model.nv))
    for k in range(model.nv):
        dv = np.zeros(model.nv)
        dv[k] = eps
        p_plus, r_plus = pose(pin.integrate(model, q, dv))
        p_minus, r_minus = pose(pin.integrate(model, q, -dv))
        out[:3, k] = to_o @ (p_plus - p_minus) / (2 * eps)
        out[3:, k] = to_o @ pin.log3(r_plus @ r_minus.T) / (2 * eps)
    return out


@pytest.mark.parametrize("case", CASES, ids=CASE_IDS)
@pytest.mark.parametrize("ref_kind", REFERENCES)
@given(seed=st.integers(0, 2**32 - 1), axes=axes_subsets)
@settings(max_examples=6)
def test_torques_equal_rnea_of_plus_wrench_on_action_minus_on_reaction(case, ref_kind, seed, axes):
    """tau = J^T w balances +w on {B} and -w (same point) on {A}: -RNEA(q, 0, 0, fext), g = 0."""
    name, action, reaction, _ = case
    reference = reference_name(case, ref_kind)
    rob = robot(name)
    rng = np.random.default_rng(seed)
    q = random_configuration(rob, rng)
    wrench = rng.normal(scale=10.0, size=len(axes))
    leg = va.VirtualActuator(rob, action, reaction, reference, axes)
    tau = leg.torques(q, wrench)
    expected = rnea_torques(
        name, q, external_forces(rob.model, q, [(action, reaction, reference, axes, wrench)])
    )
    assert tau.shape == (rob.model.nv,)
    assert np.max(np.abs(expected)) > 1e-3  # the oracle is not trivially zero
    assert relative_error(tau, expected) < 1e-9


@pytest.mark.parametrize("case", CASES, ids=CASE_IDS)
@pytest.mark.parametrize("ref_kind", REFERENCES)
@given(seed=st.integers(0, 2**32 - 1), axes=axes_subsets)
@settings(max_examples=3)
def test_jacobian_equals_finite_differences_of_relative_pose(case, ref_kind, seed, axes):
    """Rows of J: twist of {B} relative to {A}'s body at {B}'s origin, in {O}'s axes (FD)."""
    name, action, reaction, _ = case
    reference = reference_name(case, ref_kind)
    rob = robot(name)
    q = random_configuration(rob, np.random.default_rng(seed))
    leg = va.VirtualActuator(rob, action, reaction, reference, axes)
    jac = leg.jacobian(q)
    fd = finite_difference_jacobian(rob.model, q, action, reaction, reference)[axis_rows(axes)]
    assert jac.shape == (len(axes), rob.model.nv)
    np.testing.assert_allclose(jac, fd, atol=1e-6, rtol=0)


@pytest.mark.parametrize("case", CASES, ids=CASE_IDS)
def test_jacobian_all_axes_at_standing_pose_matches_finite_differences(case):
    """Same FD oracle at the robot's own neutral pose (SRDF standing pose), 6 axes, {O} = third."""
    name, action, reaction, third = case
    rob = robot(name)
    q = rob.neutral()
    leg = va.VirtualActuator(rob, action, reaction, third)
    fd = finite_difference_jacobian(rob.model, q, action, reaction, third)
    np.testing.assert_allclose(leg.jacobian(q), fd, atol=1e-6, rtol=0)


@pytest.mark.parametrize("case", CASES, ids=CASE_IDS)
@given(seed=st.integers(0, 2**32 - 1))
@settings(max_examples=4)
def test_position_is_pose_of_action_relative_to_reaction_in_reference(case, seed):
    """position(q): R_O^T (p_B - p_A) and the rotation vector of R_A^T R_B expressed in {O}."""
    name, action, reaction, third = case
    rob = robot(name)
    model = rob.model
    q = random_configuration(rob, np.random.default_rng(seed))
    data = placements(model, q)
    a, b = data.oMf[frame_id(model, reaction)], data.oMf[frame_id(model, action)]
    rot_o = data.oMf[frame_id(model, third)].rotation
    expected = np.concatenate(
        (
            rot_o.T @ (b.translation - a.translation),
            rot_o.T @ a.rotation @ pin.log3(a.rotation.T @ b.rotation),
        )
    )
    for axes in (AXES, ("y", "rx"), ("z",)):
        leg = va.VirtualActuator(rob, action, reaction, third, axes)
        np.testing.assert_allclose(leg.position(q), expected[axis_rows(axes)], atol=1e-12)


@pytest.mark.parametrize("case", CASES, ids=CASE_IDS)
def test_translation_rows_are_derivative_of_position_when_reference_is_reaction(case):
    """With {O} = {A}, d/dq of position()'s translation equals J's translational rows."""
    name, action, reaction, _ = case
    rob = robot(name)
    model = rob.model
    q = random_configuration(rob, np.random.default_rng(11))
    leg = va.VirtualActuator(rob, action, reaction, reaction, ("x", "y", "z"))
    eps = 1e-6
    fd = np.zeros((3, model.nv))
    for k in range(model.nv):
        dv = np.zeros(model.nv)
        dv[k] = eps
        fd[:, k] = (
            leg.position(pin.integrate(model, q, dv)) - leg.position(pin.integrate(model, q, -dv))
        ) / (2 * eps)
    np.testing.assert_allclose(leg.jacobian(q), fd, atol=1e-6, rtol=0)


@pytest.mark.parametrize("case", CASES, ids=CASE_IDS)
@given(seed=st.integers(0, 2**32 - 1), axes=axes_subsets)
@settings(max_examples=4)
def test_velocity_is_jacobian_times_v(case, seed, axes):
    """velocity(q, v) == jacobian(q) @ v, and equals the Pinocchio-built relative twist."""
    name, action, reaction, third = case
    rob = robot(name)
    rng = np.random.default_rng(seed)
    q = random_configuration(rob, rng)
    v = rng.normal(size=rob.model.nv)
    leg = va.VirtualActuator(rob, action, reaction, third, axes)
    fd = finite_difference_jacobian(rob.model, q, action, reaction, third)[axis_rows(axes)]
    vel = leg.velocity(q, v)
    np.testing.assert_allclose(vel, leg.jacobian(q) @ v, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(vel, fd @ v, atol=1e-5)


@pytest.mark.parametrize("case", CASES, ids=CASE_IDS)
def test_columns_off_the_path_between_frames_are_zero(case):
    """Columns of joints outside the path (incl. the floating base unless one side is world)."""
    name, action, reaction, third = case
    rob = robot(name)
    model = rob.model
    q = random_configuration(rob, np.random.default_rng(5))
    jac = va.VirtualActuator(rob, action, reaction, third).jacobian(q)
    on_path = np.zeros(model.nv, dtype=bool)
    on_path[path_columns(model, action, reaction)] = True
    assert np.all(jac[:, ~on_path] == 0.0) or np.max(np.abs(jac[:, ~on_path])) < 1e-12
    # every joint on the path moves {B} relative to {A} (6 axes: a joint column never vanishes)
    assert np.all(np.linalg.norm(jac[:, on_path], axis=0) > 1e-6)
    floating = model.joints[1].shortname() == "JointModelFreeFlyer"
    if floating:
        base_on_path = "world" in (action, reaction)
        assert bool(on_path[:6].all()) == base_on_path
        if base_on_path:
            assert np.linalg.matrix_rank(jac[:, :6]) == 6


def admissibility_cases():
    return [
        ("solo12", "base_link", "FL_FOOT", "world", AXES),  # 3 joints: rank 3 of 6
        ("anymal", "base", "RH_FOOT", "base", AXES),
        ("ur5_robot", "tool0", "world", "world", AXES),  # rank 6: everything admissible
        ("panda", "panda_hand", "panda_link4", "world", AXES),  # 3 joints: rank 3
        ("talos_reduced", "left_sole_link", "torso_2_link", "world", AXES),  # 8 joints
        ("solo12", "FL_FOOT", "base_link", "world", ("x", "z", "ry")),
    ]


@pytest.mark.parametrize("case", admissibility_cases(), ids=lambda c: f"{c[0]}:{c[1]}<-{c[2]}")
@given(seed=st.integers(0, 2**32 - 1))
@settings(max_examples=8)
def test_is_admissible_accepts_range_of_jacobian_and_rejects_left_null_space(case, seed):
    """J x is admissible; a wrench with a left-null-space component is not (when one exists)."""
    name, action, reaction, reference, axes = case
    rob = robot(name)
    rng = np.random.default_rng(seed)
    q = random_configuration(rob, rng)
    leg = va.VirtualActuator(rob, action, reaction, reference, axes)
    jac = leg.jacobian(q)
    assert jac.shape == (len(axes), rob.model.nv)
    inside = jac @ rng.normal(size=rob.model.nv)
    assert leg.is_admissible(q, inside)
    u, s, _ = np.linalg.svd(jac)
    rank = int(np.sum(s > 1e-8 * s[0]))
    expected_rank = min(len(axes), len(path_columns(rob.model, action, reaction)))
    assert rank == expected_rank
    if rank < len(axes):
        null = u[:, rank:] @ rng.normal(size=len(axes) - rank)
        null *= 1.0 / np.linalg.norm(null)
        assert not leg.is_admissible(q, null)
        assert not leg.is_admissible(q, inside + 1e-3 * np.linalg.norm(inside) * null)
        # the projection on the range is admissible again
        assert leg.is_admissible(q, inside + null - u[:, rank:] @ (u[:, rank:].T @ null))
    else:
        assert leg.is_admissible(q, rng.normal(size=len(axes)))


def test_single_joint_arm_moment_about_other_axis_is_inadmissible():
    """UR5 wrist_3 relative to wrist_2: one joint, only a moment about its axis is producible."""
    rob = robot("ur5_robot")
    q = random_configuration(rob, np.random.default_rng(3))
    leg = va.VirtualActuator(
        rob, "wrist_3_link", "wrist_2_link", "wrist_3_link", ("rx", "ry", "rz")
    )
    jac = leg.jacobian(q)
    assert np.linalg.matrix_rank(jac) == 1
    axis = jac[:, np.flatnonzero(np.linalg.norm(jac, axis=0))[0]]
    assert leg.is_admissible(q, 2.5 * axis)
    other = np.cross(axis, np.array([0.3, -0.4, 0.5]))
    assert not leg.is_admissible(q, other)
