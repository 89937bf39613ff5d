"""MuJoCo simulation: model building, conversions, terrain, simulator.

Oracles share no code with the library: the Pinocchio <-> MuJoCo maps used as references below are
rebuilt here by joint name from Pinocchio's and MuJoCo's own APIs (``pin.Quaternion``,
``mj_name2id``), and the dynamics references are Pinocchio's CRBA, RNEA and ABA.
"""

from __future__ import annotations

import functools
import math
import warnings

import mujoco
import numpy as np
import pinocchio as pin
import pytest
from oracles import random_configuration, relative_error

import virtual_actuators as va
from virtual_actuators.simulation import (
    ContactParameters,
    Simulator,
    Terrain,
    build_mujoco_model,
    configuration_from_mujoco,
    configuration_to_mujoco,
    torques_to_ctrl,
    velocity_from_mujoco,
    velocity_to_mujoco,
)

G = 9.81
ORACLE_ROBOTS = ["spring_turkey", "spring_flamingo", "hexapod", "solo12", "ur5_robot"]


@functools.cache
def robot(name: str) -> va.Robot:
    return va.load_robot(name)


@functools.cache
def floating_model(name: str):
    """MuJoCo model with the ground far below (no contact), meshes included (they must not
    change the inertias), for the dynamics oracles."""
    return build_mujoco_model(robot(name), Terrain.flat(-100.0))


# -- reference maps, rebuilt from Pinocchio and MuJoCo only ---------------------------------------
def _mj_joint(mj_model, name):
    jid = mujoco.mj_name2id(mj_model, mujoco.mjtObj.mjOBJ_JOINT, name)
    assert jid >= 0, name
    return jid, int(mj_model.jnt_qposadr[jid]), int(mj_model.jnt_dofadr[jid])


def ref_qpos(model: pin.Model, mj_model, q):
    qpos = np.array(mj_model.qpos0)
    for j in range(1, model.njoints):
        joint, name = model.joints[j], model.names[j]
        _, a, _ = _mj_joint(mj_model, name)
        i = joint.idx_q
        if joint.shortname() == "JointModelFreeFlyer":
            placement = model.jointPlacements[j] * pin.XYZQUATToSE3(q[i : i + 7])
            quat = pin.Quaternion(placement.rotation)
            qpos[a : a + 3] = placement.translation
            qpos[a + 3 : a + 7] = [quat.w, quat.x, quat.y, quat.z]
        elif joint.shortname() == "JointModelSpherical":
            qpos[a : a + 4] = [q[i + 3], q[i], q[i + 1], q[i + 2]]
        elif joint.nq == 2:
            qpos[a] = math.atan2(q[i + 1], q[i])
        else:
            qpos[a] = q[i]
    return qpos


def ref_velocity_map(model: pin.Model, mj_model, q):
    """T with qvel = T v, and the vector (dT/dt) v as a function of v."""
    t = np.zeros((mj_model.nv, model.nv))
    rotations = []
    for j in range(1, model.njoints):
        joint, name = model.joints[j], model.names[j]
        _, _, d = _mj_joint(mj_model, name)
        i = joint.idx_v
        if joint.shortname() == "JointModelFreeFlyer":
            rot = model.jointPlacements[j] * pin.XYZQUATToSE3(q[joint.idx_q : joint.idx_q + 7])
            t[d : d + 3, i : i + 3] = rot.rotation
            t[d + 3 : d + 6, i + 3 : i + 6] = np.eye(3)
            rotations.append((d, i, rot.rotation))
        else:
            t[d : d + joint.nv, i : i + joint.nv] = np.eye(joint.nv)

    def tdot_v(v):
        out = np.zeros(mj_model.nv)
        for d, i, rot in rotations:  # d/dt (R v_lin) with v_lin held: R (w x v_lin)
            out[d : d + 3] = rot @ np.cross(v[i + 3 : i + 6], v[i : i + 3])
        return out

    return t, tdot_v


def mj_state(name, q, v):
    mm = floating_model(name)
    model, mj_model = robot(name).model, mm.model
    data = mujoco.MjData(mj_model)
    data.qpos[:] = ref_qpos(model, mj_model, q)
    t, tdot_v = ref_velocity_map(model, mj_model, q)
    data.qvel[:] = t @ v
    return mj_model, data, t, tdot_v


def full_mass_matrix(mj_model, data):
    m = np.zeros((mj_model.nv, mj_model.nv))
    if hasattr(data, "qM"):  # MuJoCo 3: mj_fullM(model, dst, qM)
        mujoco.mj_fullM(mj_model, m, data.qM)
    else:  # MuJoCo 4: mj_fullM(model, data, dst)
        mujoco.mj_fullM(mj_model, data, m)
    return m


def symmetric(upper):
    return np.triu(upper) + np.triu(upper, 1).T


# -- physics oracles --------------------------------------------------------------------------
@pytest.mark.parametrize("name", ORACLE_ROBOTS)
def test_mass_matrix_and_gravity_match_pinocchio(name):
    rob = robot(name)
    model, data_pin = rob.model, rob.model.createData()
    rng = np.random.default_rng(7)
    for _ in range(4):
        q = random_configuration(rob, rng)
        mj_model, data, t, _ = mj_state(name, q, np.zeros(model.nv))
        mujoco.mj_forward(mj_model, data)
        m_mj = full_mass_matrix(mj_model, data)
        m_pin = symmetric(pin.crba(model, data_pin, q))
        assert relative_error(t.T @ m_mj @ t, m_pin) < 1e-11
        gravity = pin.rnea(model, data_pin, q, np.zeros(model.nv), np.zeros(model.nv))
        assert relative_error(t.T @ data.qfrc_bias, gravity) < 1e-11


@pytest.mark.parametrize("name", ORACLE_ROBOTS)
def test_bias_and_forward_dynamics_match_pinocchio(name):
    rob = robot(name)
    model, data_pin = rob.model, rob.model.createData()
    rng = np.random.default_rng(11)
    for _ in range(4):
        q = random_configuration(rob, rng)
        v = rng.uniform(-1.5, 1.5, model.nv)
        mj_model, data, t, tdot_v = mj_state(name, q, v)
        effort = np.minimum(model.effortLimit, 2.0)
        tau = np.zeros(model.nv)
        for k in range(mj_model.nu):  # motors named after their joints
            joint = model.joints[model.getJointId(mj_model.actuator(k).name)]
            tau[joint.idx_v] = rng.uniform(-1.0, 1.0) * effort[joint.idx_v]
            data.ctrl[k] = tau[joint.idx_v]
        mujoco.mj_forward(mj_model, data)
        m_mj = full_mass_matrix(mj_model, data)
        bias = pin.rnea(model, data_pin, q, v, np.zeros(model.nv))
        assert relative_error(t.T @ (data.qfrc_bias + m_mj @ tdot_v(v)), bias) < 1e-11
        # qacc_smooth = M^-1 (actuators + passive damping - bias): no contact, no limit forces
        damped = tau - model.damping * v
        accel = pin.aba(model, data_pin, q, v, damped)
        assert relative_error(data.qacc_smooth, t @ accel + tdot_v(v)) < 1e-10
        assert data.ncon == 0


def test_ball_and_unaligned_joints_match_pinocchio():
    rob = custom_robot()
    model, data_pin = rob.model, rob.model.createData()
    mm = build_mujoco_model(rob, Terrain.flat(-100.0))
    rng = np.random.default_rng(3)
    for _ in range(5):
        q = pin.randomConfiguration(model, -np.ones(model.nq), np.ones(model.nq))
        v = rng.uniform(-1.0, 1.0, model.nv)
        data = mujoco.MjData(mm.model)
        data.qpos[:] = ref_qpos(model, mm.model, q)
        t, tdot_v = ref_velocity_map(model, mm.model, q)
        data.qvel[:] = t @ v
        mujoco.mj_forward(mm.model, data)
        m_mj = full_mass_matrix(mm.model, data)
        assert relative_error(t.T @ m_mj @ t, symmetric(pin.crba(model, data_pin, q))) < 1e-9
        bias = pin.rnea(model, data_pin, q, v, np.zeros(model.nv))
        assert relative_error(t.T @ (data.qfrc_bias + m_mj @ tdot_v(v)), bias) < 1e-11
        # the library's conversions agree with the reference maps
        assert np.allclose(
            _canonical(configuration_to_mujoco(mm, q)), _canonical(np.array(data.qpos)), atol=1e-12
        )
        assert np.allclose(configuration_from_mujoco(mm, data.qpos), q, atol=1e-12) or np.allclose(
            configuration_from_mujoco(mm, data.qpos)[3:7], -q[3:7], atol=1e-12
        )
        assert np.allclose(velocity_to_mujoco(mm, q, v), t @ v, atol=1e-12)


def _canonical(qpos):
    """Flip the free-joint quaternion (qpos[3:7]) to w >= 0 (q and -q are the same rotation)."""
    out = qpos.copy()
    if out[3] < 0:
        out[3:7] *= -1
    return out


# -- robots for the joint-type tests ------------------------------------------------------------
def custom_robot() -> va.Robot:
    """Free-flyer (placement not identity), spherical, continuous about an unaligned axis,
    unaligned revolute and prismatic joints, each body with a random inertia."""
    model = pin.Model()
    rng = np.random.default_rng(5)

    def inertia():  # a box of random size, mass, centre and orientation
        x, y, z = rng.uniform(0.05, 0.3, 3)
        mass = rng.uniform(0.5, 2.0)
        moments = mass / 12.0 * np.array([y * y + z * z, x * x + z * z, x * x + y * y])
        rot = pin.exp3(rng.normal(size=3))
        return pin.Inertia(mass, rng.uniform(-0.1, 0.1, 3), rot @ np.diag(moments) @ rot.T)

    placement = pin.SE3(pin.rpy.rpyToMatrix(0.1, -0.2, 0.3), np.array([0.1, 0.2, 0.3]))
    root = model.addJoint(0, pin.JointModelFreeFlyer(), placement, "root_joint")
    model.appendBodyToJoint(root, inertia(), pin.SE3.Identity())
    ball = model.addJoint(root, pin.JointModelSpherical(), pin.SE3.Random(), "ball")
    model.appendBodyToJoint(ball, inertia(), pin.SE3.Identity())
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    hinge = model.addJoint(ball, pin.JointModelRevoluteUnaligned(axis), pin.SE3.Random(), "hinge")
    model.appendBodyToJoint(hinge, inertia(), pin.SE3.Identity())
    wheel = model.addJoint(hinge, pin.JointModelRUBY(), pin.SE3.Random(), "wheel")
    model.appendBodyToJoint(wheel, inertia(), pin.SE3.Identity())
    slider = model.addJoint(
        wheel, pin.JointModelPrismaticUnaligned(axis[::-1].copy()), pin.SE3.Random(), "slider"
    )
    model.appendBodyToJoint(slider, inertia(), pin.SE3.Identity())
    model.addFrame(pin.Frame("tip", slider, pin.SE3.Random(), pin.FrameType.OP_FRAME))
    model.lowerPositionLimit[:] = -1.0
    model.upperPositionLimit[:] = 1.0
    model.effortLimit[:] = 5.0
    return va.Robot(name="custom", model=model, data=model.createData(), floating_base=True)


def test_joint_types_in_mujoco():
    rob = custom_robot()
    mm = build_mujoco_model(rob)
    kinds = {j.name: j.kind for j in mm.joints}
    assert kinds == {
        "root_joint": "free",
        "ball": "ball",
        "hinge": "hinge",
        "wheel": "continuous",
        "slider": "slide",
    }
    m = mm.model
    types = {m.joint(i).name: int(m.jnt_type[i]) for i in range(m.njnt)}
    assert types["root_joint"] == mujoco.mjtJoint.mjJNT_FREE
    assert types["ball"] == mujoco.mjtJoint.mjJNT_BALL
    assert types["hinge"] == types["wheel"] == mujoco.mjtJoint.mjJNT_HINGE
    assert types["slider"] == mujoco.mjtJoint.mjJNT_SLIDE
    limited = {m.joint(i).name: bool(m.jnt_limited[i]) for i in range(m.njnt)}
    assert limited == {
        "root_joint": False,
        "ball": False,
        "hinge": True,
        "wheel": False,
        "slider": True,
    }
    assert mm.actuated == ("hinge", "wheel", "slider")  # 1-DoF joints only
    assert np.allclose(m.actuator_ctrlrange, [[-5.0, 5.0]] * 3)
    assert set(m.actuator(k).name for k in range(m.nu)) == {"hinge", "wheel", "slider"}


def test_unsupported_joint_is_named():
    model = pin.Model()
    j = model.addJoint(0, pin.JointModelPlanar(), pin.SE3.Identity(), "sled")
    model.appendBodyToJoint(j, pin.Inertia.Random(), pin.SE3.Identity())
    rob = va.Robot(name="sled", model=model, data=model.createData())
    with pytest.raises(va.RobotDescriptionError, match="'sled'.*Planar"):
        build_mujoco_model(rob)


def test_massless_bodies_compile():
    model = pin.Model()
    a = model.addJoint(0, pin.JointModelRX(), pin.SE3.Identity(), "a")  # massless
    b = model.addJoint(a, pin.JointModelRY(), pin.SE3.Identity(), "b")
    model.appendBodyToJoint(
        b, pin.Inertia(1.0, np.array([0, 0, -0.3]), np.eye(3) * 0.01), pin.SE3.Identity()
    )
    rob = va.Robot(name="gimbal", model=model, data=model.createData())
    mm = build_mujoco_model(rob)
    assert mm.model.nbody == 3 and mm.model.body_mass[1] > 0.0


# -- conversions ------------------------------------------------------------------------------
ROUND_TRIP_ROBOTS = [
    "solo12",
    "anymal",
    "hexapod",
    "spring_turkey",
    "spring_flamingo",
    "double_pendulum_continuous",  # continuous joints (RUBX)
]


@pytest.mark.parametrize("name", ROUND_TRIP_ROBOTS)
def test_round_trips(name):
    rob = robot(name)
    model = rob.model
    mm = floating_model(name)
    rng = np.random.default_rng(2)
    for _ in range(5):
        q = random_configuration(rob, rng, scale=1.0)
        v = rng.normal(size=model.nv)
        qpos = configuration_to_mujoco(mm, q)
        assert np.allclose(
            _canonical_free(model, mm.model, qpos),
            _canonical_free(model, mm.model, ref_qpos(model, mm.model, q)),
            atol=1e-12,
        )
        assert np.allclose(configuration_from_mujoco(mm, qpos), q, atol=1e-12)
        qvel = velocity_to_mujoco(mm, q, v)
        t, _ = ref_velocity_map(model, mm.model, q)
        assert np.allclose(qvel, t @ v, atol=1e-12)
        assert np.allclose(velocity_from_mujoco(mm, qpos, qvel), v, atol=1e-12)
        qvel2 = rng.normal(size=mm.model.nv)
        assert np.allclose(
            velocity_to_mujoco(mm, q, velocity_from_mujoco(mm, qpos, qvel2)), qvel2, atol=1e-12
        )
    names = [model.names[j] for j in range(1, model.njoints)]
    assert [j.name for j in mm.joints] == names


def _canonical_free(model, mj_model, qpos):
    out = np.array(qpos, dtype=float)
    if model.joints[1].shortname() == "JointModelFreeFlyer":
        _, a, _ = _mj_joint(mj_model, model.names[1])
        if out[a + 3] < 0:
            out[a + 3 : a + 7] *= -1
    return out


def test_continuous_joint_round_trip_angle():
    mm = floating_model("double_pendulum_continuous")
    q = np.array([math.cos(2.5), math.sin(2.5), math.cos(-3.0), math.sin(-3.0)])
    assert np.allclose(configuration_to_mujoco(mm, q), [2.5, -3.0], atol=1e-15)
    assert not any(mm.model.jnt_limited)


@pytest.mark.parametrize(
    "name, frames",
    [
        ("solo12", ["FL_FOOT", "HR_FOOT", "base_link", "FR_KFE"]),
        ("spring_flamingo", ["left_heel", "right_toe", "body"]),
        ("hexapod", None),
        ("ur5_robot", ["ee_link", "tool0"]),
    ],
)
def test_frame_placements_match_pinocchio(name, frames):
    rob = robot(name)
    model, data_pin = rob.model, rob.model.createData()
    mm = floating_model(name)
    data = mujoco.MjData(mm.model)
    rng = np.random.default_rng(4)
    frames = frames or [frame.name for frame in model.frames]
    for _ in range(3):
        q = random_configuration(rob, rng, scale=1.0)
        data.qpos[:] = configuration_to_mujoco(mm, q)
        mujoco.mj_forward(mm.model, data)
        pin.framesForwardKinematics(model, data_pin, q)
        for frame in frames:
            site = mujoco.mj_name2id(mm.model, mujoco.mjtObj.mjOBJ_SITE, frame)
            expected = data_pin.oMf[model.getFrameId(frame)]
            assert np.allclose(data.site_xpos[site], expected.translation, atol=1e-12)
            assert np.allclose(data.site_xmat[site].reshape(3, 3), expected.rotation, atol=1e-12)


def test_primitive_geoms_match_pinocchio_geometry():
    rob = robot("spring_flamingo")
    model = rob.model
    geometry = pin.buildGeomFromUrdf(model, str(rob.urdf_path), pin.GeometryType.COLLISION)
    mm = build_mujoco_model(rob)
    data = mujoco.MjData(mm.model)
    q = random_configuration(rob, np.random.default_rng(0))
    data.qpos[:] = configuration_to_mujoco(mm, q)
    mujoco.mj_forward(mm.model, data)
    data_pin, geom_data = model.createData(), geometry.createData()
    pin.updateGeometryPlacements(model, data_pin, geometry, geom_data, q)
    for k, obj in enumerate(geometry.geometryObjects):
        gid = mujoco.mj_name2id(mm.model, mujoco.mjtObj.mjOBJ_GEOM, obj.name)
        assert np.allclose(data.geom_xpos[gid], geom_data.oMg[k].translation, atol=1e-12)
        shape = obj.geometry
        kind = type(shape).__name__
        if kind == "Sphere":
            expected = [shape.radius]
        elif kind == "Box":
            expected = list(shape.halfSide)
        else:
            assert kind == "Cylinder", kind
            expected = [shape.radius, shape.halfLength]
        size = mm.model.geom_size[gid][: len(expected)]
        assert size == pytest.approx(expected, abs=1e-15)
    # the heel and toe frames each own the contact sphere they sit on
    heel, toe = set(mm.frame_geoms["left_heel"]), set(mm.frame_geoms["left_toe"])
    assert len(heel) == 1 and len(toe) == 1 and not heel & toe
    assert mm.model.geom_type[next(iter(heel))] == mujoco.mjtGeom.mjGEOM_SPHERE


def test_free_flyer_velocity_frames():
    rob = robot("solo12")
    mm = floating_model("solo12")
    data = mujoco.MjData(mm.model)
    q = rob.neutral()
    q[3:7] = [0.0, 0.0, math.sin(math.pi / 4), math.cos(math.pi / 4)]  # yaw +90 degrees
    root = next(joint for joint in mm.joints if joint.name == "root_joint")
    data.qpos[:] = configuration_to_mujoco(mm, q)
    assert np.allclose(
        data.qpos[root.qpos_adr + 3 : root.qpos_adr + 7],
        [math.cos(math.pi / 4), 0.0, 0.0, math.sin(math.pi / 4)],
    )
    data.qvel[root.dof_adr : root.dof_adr + 3] = [1.0, 0.0, 0.0]  # world x
    data.qvel[root.dof_adr + 3 : root.dof_adr + 6] = [0.0, 0.0, 0.5]  # body yaw rate
    v = velocity_from_mujoco(mm, data.qpos, data.qvel)
    assert np.allclose(v[:3], [0.0, -1.0, 0.0], atol=1e-12)  # world x is body -y
    assert np.allclose(v[3:6], [0.0, 0.0, 0.5], atol=1e-12)
    # MuJoCo's own body velocity agrees with Pinocchio's at the base origin
    mujoco.mj_forward(mm.model, data)
    body = int(mm.model.jnt_bodyid[_mj_joint(mm.model, "root_joint")[0]])
    vel = np.zeros(6)
    mujoco.mj_objectVelocity(mm.model, data, mujoco.mjtObj.mjOBJ_BODY, body, vel, 0)
    data_pin = rob.model.createData()
    pin.forwardKinematics(rob.model, data_pin, q, v)
    twist = pin.getVelocity(rob.model, data_pin, 1, pin.LOCAL_WORLD_ALIGNED)
    assert np.allclose(vel[3:], twist.linear, atol=1e-12)
    assert np.allclose(vel[:3], twist.angular, atol=1e-12)


def test_torques_to_ctrl():
    rob = robot("spring_turkey")
    mm = floating_model("spring_turkey")
    model = rob.model
    tau = np.zeros(model.nv)
    for k, name in enumerate(["left_hip", "left_knee", "right_hip", "right_knee"]):
        tau[model.joints[model.getJointId(name)].idx_v] = k + 1.0
    ctrl = torques_to_ctrl(mm, tau)
    for k, name in enumerate(["left_hip", "left_knee", "right_hip", "right_knee"]):
        act = mujoco.mj_name2id(mm.model, mujoco.mjtObj.mjOBJ_ACTUATOR, name)
        assert ctrl[act] == k + 1.0
    assert sorted(ctrl.tolist()) == [1.0, 2.0, 3.0, 4.0]  # the efforts, nothing else
    tau[model.joints[model.getJointId("boom_pitch")].idx_v] = 0.5
    with pytest.raises(va.InvalidInputError, match="'boom_pitch'"):
        torques_to_ctrl(mm, tau)
    assert np.array_equal(torques_to_ctrl(mm, tau, ignore_unactuated=True), ctrl)
    tau[model.joints[model.getJointId("boom_pitch")].idx_v] = 1e-10  # within tolerance
    assert np.array_equal(torques_to_ctrl(mm, tau), ctrl)
    with pytest.raises(va.InvalidInputError, match="7 entries"):
        torques_to_ctrl(mm, np.zeros(3))


def test_passive_joints_from_srdf():
    assert robot("spring_turkey").passive_joints == ("boom_x", "boom_z", "boom_pitch")
    assert robot("spring_flamingo").passive_joints == ("boom_x", "boom_z", "boom_pitch")
    assert robot("solo12").passive_joints == ()
    mm = floating_model("spring_flamingo")
    assert mm.actuated == tuple(
        f"{side}_{j}" for side in ("left", "right") for j in ("hip", "knee", "ankle")
    )
    assert floating_model("solo12").model.nu == 12  # free-flyer never actuated


def test_actuated_option():
    rob = robot("spring_turkey")
    mm = build_mujoco_model(rob, actuated=["right_knee", "left_hip"])
    assert mm.actuated == ("left_hip", "right_knee") and mm.model.nu == 2
    with pytest.raises(va.JointNotFoundError, match="left_hip"):
        build_mujoco_model(rob, actuated=["left_hipp"])
    with pytest.raises(va.InvalidInputError, match="root_joint"):
        build_mujoco_model(robot("solo12"), actuated=["root_joint"], collisions="none")


def test_meshes_and_skipped_geometry():
    mm = build_mujoco_model(robot("ur5_robot"))
    assert mm.model.nmesh >= 7 and not mm.skipped_geometries
    visual = build_mujoco_model(robot("ur5_robot"), collisions="visual")  # .dae meshes, read
    assert visual.model.nmesh == 7 and not visual.skipped_geometries
    assert not visual.approximated_geometries and len(visual.geom_frames) == 7
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        primitives = build_mujoco_model(robot("ur5_robot"), collisions="primitives")
    assert primitives.model.nmesh == 0


# -- terrain ----------------------------------------------------------------------------------
def test_builtin_terrains():
    assert set(Terrain.names()) == {"flat", "profile-one", "profile-two", "rolling"}
    for name in Terrain.names():
        terrain = Terrain.builtin(name)
        points = terrain.points
        assert np.all(np.diff(points[:, 0]) > 0)
        assert np.max(np.abs(terrain.slopes), initial=0.0) <= math.radians(20.0) + 1e-12
        xs = np.linspace(-5.0, 1.999, 50)
        assert np.all(terrain.height(xs) == 0.0)  # level start of at least 2 m
        assert np.all(terrain.slope(xs) == 0.0)
        for x in points[:, 0]:  # no vertical steps
            assert abs(terrain.height(x - 1e-9) - terrain.height(x + 1e-9)) < 1e-8
        if name != "flat":
            assert points[-1, 0] - points[0, 0] >= 14.0
            assert np.array_equal(points, Terrain.parse(name).points)  # deterministic
    one = Terrain.builtin("profile-one")
    degrees = np.round(np.degrees(one.slopes), 9)
    assert set(degrees) >= {15.0, -15.0, 20.0, -20.0, 0.0}
    inner = np.diff(one.points[:, 0])[1:]
    assert np.all((inner >= 1.0 - 1e-9) & (inner <= 2.0 + 1e-9))
    two = Terrain.builtin("profile-two")
    lengths = np.diff(two.points[:, 0])[1:]
    assert len(lengths) >= 10 and np.all((lengths >= 0.6 - 1e-9) & (lengths <= 1.5 + 1e-9))
    assert len(set(np.round(np.degrees(two.slopes), 6))) >= 8
    assert np.max(np.abs(np.degrees(Terrain.builtin("rolling").slopes))) <= 10.0 + 1e-9


def test_terrain_through_points():
    terrain = Terrain([(1.0, 0.0), (2.0, 0.5), (4.0, 0.5), (5.0, 0.0)])
    assert terrain.height(0.0) == 0.0 and terrain.height(10.0) == 0.0
    assert terrain.height(1.5) == pytest.approx(0.25)
    assert terrain.height(3.0) == pytest.approx(0.5)
    assert terrain.slope(1.5) == pytest.approx(math.atan(0.5))
    assert terrain.slope(4.5) == pytest.approx(-math.atan(0.5))
    assert terrain.slope(3.0) == 0.0 and terrain.slope(-1.0) == 0.0 and terrain.slope(9.0) == 0.0
    xs = np.array([[0.5, 1.5], [3.0, 4.5]])
    assert terrain.height(xs).shape == (2, 2) and terrain.slope(xs).shape == (2, 2)
    assert isinstance(terrain.height(1.0), float)
    assert "4 points" in repr(terrain) and "Terrain.flat(height=0.2)" == repr(Terrain.flat(0.2))
    assert Terrain.flat(0.2).height(123.0) == 0.2


def test_terrain_errors():
    with pytest.raises(va.InvalidInputError, match=r"point 2 \(1\.0, 0\.3\)"):
        Terrain([(0.0, 0.0), (1.0, 0.0), (1.0, 0.3)])
    with pytest.raises(va.InvalidInputError, match="shape"):
        Terrain([])
    with pytest.raises(va.InvalidInputError, match="not finite"):
        Terrain([(0.0, math.nan)])
    with pytest.raises(va.InvalidInputError, match="'2:abc'.*profile-one"):
        Terrain.parse("0:0,2:abc")
    with pytest.raises(va.InvalidInputError, match="'hilly'.*profile-one"):
        Terrain.parse("hilly")
    with pytest.raises(va.InvalidInputError, match="'profile-tw'.*Closest terrains: 'profile-two'"):
        Terrain.parse("profile-tw")
    with pytest.raises(va.InvalidInputError, match="'1:2:3'"):
        Terrain.parse("0:0,1:2:3")
    with pytest.raises(va.InvalidInputError, match="increasing"):
        Terrain.parse("0:0,3:1,2:0")
    # "profile3" is 3 edits from both profiles; equal lengths: alphabetical order
    closest = "Closest terrains: 'profile-one', 'profile-two'"
    with pytest.raises(va.InvalidInputError, match=closest):
        Terrain.builtin("profile-3")
    with pytest.raises(va.InvalidInputError, match="'x'"):
        Terrain.parse("flat:x")
    assert Terrain.parse("flat:0.3").height(0.0) == 0.3
    parsed = Terrain.parse(" 0:0, 2:0 ,3:0.27 ")
    assert np.allclose(parsed.points, [[0, 0], [2, 0], [3, 0.27]])


def test_terrain_boxes_lie_on_the_profile():
    terrain = Terrain.builtin("profile-two")
    mm = build_mujoco_model(robot("spring_turkey"), terrain)
    model, data = mm.model, mujoco.MjData(mm.model)
    mujoco.mj_forward(model, data)
    points = terrain.points
    tops = []
    for gid in sorted(mm.terrain_geoms):
        assert model.geom(gid).name.startswith("terrain_")
        assert model.geom_type[gid] == mujoco.mjtGeom.mjGEOM_BOX
        half = model.geom_size[gid]
        rot = data.geom_xmat[gid].reshape(3, 3)
        left = data.geom_xpos[gid] + rot @ [-half[0], 0.0, half[2]]
        right = data.geom_xpos[gid] + rot @ [half[0], 0.0, half[2]]
        tops.append((left[[0, 2]], right[[0, 2]]))
    tops.sort(key=lambda segment: segment[0][0])
    assert len(tops) == len(points) + 1  # segments plus run-in and run-out
    for k, (x, z) in enumerate(points):
        assert np.allclose(tops[k][1], [x, z], atol=1e-12)
        assert np.allclose(tops[k + 1][0], [x, z], atol=1e-12)
    assert tops[0][0][0] <= points[0, 0] - 50.0 + 1e-9
    assert tops[-1][1][0] >= points[-1, 0] + 50.0 - 1e-9


def ball_robot(tmp_path, radius=0.05):
    urdf = tmp_path / "ball.urdf"
    urdf.write_text(
        f"""<robot name="ball"><link name="ball">
        <inertial><mass value="1.0"/><inertia ixx="0.001" iyy="0.001" izz="0.001"
        ixy="0" ixz="0" iyz="0"/></inertial>
        <collision><geometry><sphere radius="{radius}"/></geometry></collision>
        </link></robot>"""
    )
    return va.load_robot(urdf, floating_base=True)


def test_ball_rests_on_the_slopes(tmp_path):
    rob = ball_robot(tmp_path)
    terrain = Terrain.builtin("profile-one")
    sim = Simulator(rob, terrain, control_rate=100.0)
    points = terrain.points
    for x in (1.0, 2.75, 5.0, 5.8, 7.9, 10.0, 12.3):
        q = rob.neutral()
        q[0], q[2] = x, terrain.height(x) + 0.08
        sim.reset(q)
        for _ in range(15):
            sim.step(np.zeros(6))
        centre = sim.q[[0, 2]]
        # distance from the ball centre to the profile polyline (with long level ends)
        ext = np.vstack(
            ([points[0, 0] - 50, points[0, 1]], points, [points[-1, 0] + 50, points[-1, 1]])
        )
        dist = min(_point_segment_distance(centre, ext[k], ext[k + 1]) for k in range(len(ext) - 1))
        assert dist == pytest.approx(0.05, abs=1e-3), x
        assert sim.in_contact("ball")
        assert sim.touching_terrain() == {"ball"}


def _point_segment_distance(p, a, b):
    ab = b - a
    s = np.clip(np.dot(p - a, ab) / np.dot(ab, ab), 0.0, 1.0)
    return float(np.linalg.norm(p - (a + s * ab)))


# -- simulator --------------------------------------------------------------------------------
LEGS = {
    "spring_turkey": ["left_hip", "left_knee", "right_hip", "right_knee"],
    "spring_flamingo": [
        f"{side}_{j}" for side in ("left", "right") for j in ("hip", "knee", "ankle")
    ],
}
FEET = {
    "spring_turkey": ["left_foot", "right_foot"],
    "spring_flamingo": ["left_heel", "left_toe", "right_heel", "right_toe"],
}


def hold_pose(sim, seconds, kp=200.0, kd=5.0, q_ref=None):
    """Joint PD on the legs towards the standing pose."""
    model = sim.robot.model
    q_ref = sim.robot.neutral() if q_ref is None else q_ref
    joints = [model.joints[model.getJointId(name)] for name in LEGS[sim.robot.name]]
    for _ in range(round(seconds / sim.control_period)):
        q, v = sim.q, sim.v
        tau = np.zeros(model.nv)
        for j in joints:
            tau[j.idx_v] = kp * (q_ref[j.idx_q] - q[j.idx_q]) - kd * v[j.idx_v]
        sim.step(tau)


@pytest.mark.parametrize("name", ["spring_turkey", "spring_flamingo"])
def test_biped_stands_with_joint_pd(name):
    rob = robot(name)
    sim = Simulator(rob)
    height = rob.neutral()[1]
    hold_pose(sim, 1.0)
    assert sim.time == pytest.approx(1.0, abs=1e-9)
    q = sim.q
    assert abs(q[1] - height) < 0.02 and abs(q[2]) < 0.05
    for foot in FEET[name]:
        assert sim.in_contact(foot), foot
    touching = sim.touching_terrain()
    assert touching >= set(FEET[name])
    assert all(any(word in frame for word in ("foot", "heel", "toe")) for frame in touching)
    force = sum(sim.contact_force(foot) for foot in FEET[name])
    weight = pin.computeTotalMass(rob.model) * G
    assert force[2] == pytest.approx(weight, rel=0.05)
    assert abs(force[1]) < 1e-9  # planar robot: no lateral force
    # sinking: the foot spheres' centres are at most 3 mm below one radius above the ground
    for gid in (g for foot in FEET[name] for g in sim.mujoco_model.frame_geoms[foot]):
        depth = sim.model.geom_size[gid][0] - sim.data.geom_xpos[gid][2]
        assert -1e-4 < depth < 3e-3


def test_biped_collapses_without_torque():
    rob = robot("spring_turkey")
    sim = Simulator(rob, collisions="visual")
    start = sim.q[1]
    for _ in range(1000):
        sim.step(np.zeros(rob.model.nv))
    assert sim.q[1] < start - 0.2
    touching = sim.touching_terrain()
    assert touching - {"left_foot", "right_foot", "left_foot_joint", "right_foot_joint"}, touching


def test_step_duration_and_substeps():
    rob = robot("spring_turkey")
    sim = Simulator(rob, control_rate=500.0)
    assert sim.substeps == 4 and sim.control_period == pytest.approx(2e-3)
    for k in range(1, 4):
        sim.step(np.zeros(rob.model.nv))
        assert sim.time == pytest.approx(k * 2e-3, abs=1e-12)
    sim.reset()
    assert sim.time == 0.0
    assert np.allclose(sim.q, rob.neutral(), atol=1e-12) and not np.any(sim.v)
    with pytest.raises(va.InvalidInputError, match="whole number"):
        Simulator(rob, control_rate=300.0)
    with pytest.raises(va.InvalidInputError, match="control_rate"):
        Simulator(rob, control_rate=0.0)


def test_effort_limits_clip():
    rob = robot("spring_turkey")
    sim = Simulator(rob)
    model = rob.model
    hip = model.joints[model.getJointId("left_hip")].idx_v
    tau = np.zeros(model.nv)
    tau[hip] = 1000.0
    sim.step(tau)
    act = mujoco.mj_name2id(sim.model, mujoco.mjtObj.mjOBJ_ACTUATOR, "left_hip")
    assert sim.data.actuator_force[act] == pytest.approx(model.effortLimit[hip])


def test_unactuated_torque_raises():
    rob = robot("spring_turkey")
    sim = Simulator(rob)
    tau = np.zeros(rob.model.nv)
    tau[0] = 1.0  # boom_x
    with pytest.raises(va.InvalidInputError, match="'boom_x'"):
        sim.step(tau)
    assert sim.time == 0.0
    sim.step(tau, ignore_unactuated=True)
    solo = Simulator(robot("solo12"), collisions="primitives")
    tau = np.zeros(18)
    tau[2] = 3.0
    with pytest.raises(va.InvalidInputError, match="'root_joint'"):
        solo.step(tau)


def test_push_changes_the_velocity():
    rob = robot("spring_turkey")
    pushed, still = Simulator(rob), Simulator(rob)
    pushed.push([40.0, 0.0, 0.0], "body", duration=0.1)
    hold_pose(pushed, 0.2)
    hold_pose(still, 0.2)
    assert pushed.v[0] > still.v[0] + 0.1  # boom_x velocity
    assert not np.any(pushed.data.xfrc_applied)  # the push has ended


def test_push_impulse_and_moment():
    """Zero gravity, no contact: a push at a foot changes the momenta by its impulse."""
    rob = robot("solo12")
    sim = Simulator(rob, Terrain.flat(-100.0), collisions="none")
    sim.model.opt.gravity[:] = 0.0
    # RK4: the light leg swings fast, and Euler's momentum drift would hide a wrong impulse
    sim.model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    q0 = rob.neutral()
    sim.reset(q0)
    data_pin = rob.model.createData()
    pin.framesForwardKinematics(rob.model, data_pin, q0)
    foot = data_pin.oMf[rob.model.getFrameId("FL_FOOT")].translation.copy()
    force, duration = np.array([0.0, 3.0, 5.0]), 0.004
    sim.push(force, "FL_FOOT", duration=duration)
    for _ in range(4):
        sim.step(np.zeros(18))
    q, v = sim.q, sim.v
    momentum = pin.computeCentroidalMomentum(rob.model, data_pin, q, v)
    com = data_pin.com[0]
    assert np.allclose(momentum.linear, force * duration, atol=1e-10)
    # angular momentum about the centre of mass: the force acts at the foot (which moves by
    # about a millimetre during the push)
    com0 = pin.centerOfMass(rob.model, rob.model.createData(), q0)
    expected = np.cross(foot - com0, force) * duration
    assert np.linalg.norm(momentum.angular - expected) < 3e-3 * np.linalg.norm(expected)
    assert np.linalg.norm(com - com0) < 1e-4


def test_unknown_frames():
    sim = Simulator(robot("spring_turkey"))
    for call in (
        lambda: sim.in_contact("left_fot"),
        lambda: sim.contact_force("left_fot"),
        lambda: sim.push([1.0, 0.0, 0.0], frame="left_fot"),
    ):
        with pytest.raises(va.FrameNotFoundError, match="left_fot.*Closest frames: 'left_foot'"):
            call()
    for call in (
        lambda: sim.in_contact(["left_foot"]),
        lambda: sim.contact_force(3),
        lambda: sim.contact_switches(("left_foot", ["right_foot"])),
        lambda: sim.contact_forces([["left_foot"]]),
        lambda: sim.push([1.0, 0.0, 0.0], frame={"left_foot": 1}),
    ):  # not a name (unhashable ones too): a typed error, never a TypeError
        with pytest.raises(va.FrameNotFoundError, match="named by a str"):
            call()
    with pytest.raises(va.InvalidInputError, match="world"):
        sim.push([1.0, 0.0, 0.0], frame="world")
    assert not sim.in_contact("body") and not np.any(sim.contact_force("body"))
    with pytest.raises(va.InvalidInputError, match="q must have 7"):
        sim.reset(np.zeros(3))


def test_repr_and_contact_parameters():
    sim = Simulator(
        robot("spring_turkey"),
        Terrain.builtin("rolling"),
        contact=ContactParameters(friction=0.8, cone="elliptic"),
    )
    text = repr(sim)
    assert "spring_turkey" in text and "rolling" in text and "t=0.0000 s" in text
    gid = sim.mujoco_model.frame_geoms["left_foot"][0]
    assert sim.model.geom_friction[gid][0] == 0.8
    assert sim.model.opt.cone == mujoco.mjtCone.mjCONE_ELLIPTIC
    with pytest.raises(va.InvalidInputError, match="condim"):
        ContactParameters(condim=2)


def test_srdf_passive_joints_in_any_urdf(tmp_path):
    (tmp_path / "arm.urdf").write_text(
        """<robot name="arm"><link name="base"/>
        <link name="a"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01"
        ixy="0" ixz="0" iyz="0"/></inertial></link>
        <link name="b"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01"
        ixy="0" ixz="0" iyz="0"/></inertial></link>
        <joint name="j1" type="revolute"><parent link="base"/><child link="a"/>
        <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="5" velocity="1"/></joint>
        <joint name="j2" type="continuous"><parent link="a"/><child link="b"/>
        <origin xyz="0.3 0 0"/><axis xyz="0 1 0"/><limit effort="0" velocity="1"/></joint>
        </robot>"""
    )
    (tmp_path / "arm.srdf").write_text(
        '<robot name="arm"><passive_joint name="j1"/><passive_joint name="nope"/></robot>'
    )
    rob = va.load_robot(tmp_path / "arm.urdf", floating_base=False)
    assert rob.passive_joints == ("j1",)  # unknown names are ignored
    mm = build_mujoco_model(rob)
    assert mm.actuated == ("j2",)
    assert not mm.model.actuator_ctrllimited[0]  # effort 0: no control range


def _tetrahedron_stl(path, binary):
    vertices = np.array([[0, 0, 0], [0.1, 0, 0], [0, 0.1, 0], [0, 0, 0.1]], dtype=np.float32)
    faces = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
    if binary:
        out = bytearray(b"\0" * 80) + len(faces).to_bytes(4, "little")
        for face in faces:
            out += np.zeros(3, np.float32).tobytes() + vertices[list(face)].tobytes() + b"\0\0"
        path.write_bytes(bytes(out))
    else:
        lines = ["solid t"]
        for face in faces:
            lines += ["facet normal 0 0 0", "outer loop"]
            lines += [f"vertex {x} {y} {z}" for x, y, z in vertices[list(face)]]
            lines += ["endloop", "endfacet"]
        path.write_text("\n".join([*lines, "endsolid t"]) + "\n")


def test_mesh_files_binary_and_ascii_stl(tmp_path, caplog):
    _tetrahedron_stl(tmp_path / "binary.stl", binary=True)
    _tetrahedron_stl(tmp_path / "ascii.stl", binary=False)
    inertial = (
        '<inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" '
        'iyz="0"/></inertial>'
    )
    (tmp_path / "meshy.urdf").write_text(
        f"""<robot name="meshy"><link name="base">{inertial}
        <collision><geometry><mesh filename="{tmp_path / "binary.stl"}"/></geometry></collision>
        <collision><geometry><mesh filename="{tmp_path / "ascii.stl"}"/></geometry></collision>
        </link></robot>"""
    )
    rob = va.load_robot(tmp_path / "meshy.urdf", floating_base=True)
    with caplog.at_level("WARNING", logger="virtual_actuators"):
        mm = build_mujoco_model(rob)  # MuJoCo reads binary STL only: the ASCII one is a box
    assert [r.getMessage() for r in caplog.records] == [
        "Robot 'meshy': simulated as bounding boxes, the meshes that neither MuJoCo (OBJ, "
        "binary STL) nor the Collada reader reads (1): base_1"
    ]
    assert mm.approximated_geometries == ("base_1",) and not mm.skipped_geometries
    assert mm.model.nmesh == 1
    ids = [mujoco.mj_name2id(mm.model, mujoco.mjtObj.mjOBJ_GEOM, f"base_{k}") for k in (0, 1)]
    assert mm.frame_geoms["base"] == tuple(ids)
    assert mm.model.geom_type[ids[1]] == mujoco.mjtGeom.mjGEOM_BOX
    assert np.allclose(mm.model.geom_size[ids[1]], 0.05) and np.allclose(
        mm.model.geom_pos[ids[1]], 0.05
    )  # the tetrahedron's box: from 0 to 0.1 m on each axis


def test_impossible_inertia_is_repaired_with_a_warning():
    model = pin.Model()
    j = model.addJoint(0, pin.JointModelRX(), pin.SE3.Identity(), "bad")
    model.appendBodyToJoint(
        j, pin.Inertia(1.0, np.zeros(3), np.diag([0.01, 0.02, 0.1])), pin.SE3.Identity()
    )  # 0.01 + 0.02 < 0.1: no rigid body has these principal moments
    rob = va.Robot(name="bad", model=model, data=model.createData())
    with pytest.warns(UserWarning, match="'bad'.*not physically possible"):
        mm = build_mujoco_model(rob)
    moments = np.sort(mm.model.body_inertia[1])
    assert moments[0] + moments[1] >= moments[2] - 1e-12


def test_contact_queries_follow_steps_and_resets():
    """Contact queries are cached per physics state: a reset or a step refreshes them, and the
    cached answer equals a direct scan of MuJoCo's contact list."""
    sim = Simulator(robot("spring_turkey"), Terrain.builtin("flat"))
    for _ in range(50):
        sim.step(np.zeros(sim.robot.model.nv), ignore_unactuated=True)
    assert sim.in_contact("left_foot") and sim.in_contact("right_foot")
    terrain = sim.mujoco_model.terrain_geoms
    direct = {
        int(geom)
        for g1, g2 in zip(sim.data.contact.geom1, sim.data.contact.geom2, strict=True)
        for geom in (g1, g2)
        if (g1 in terrain) != (g2 in terrain) and geom not in terrain
    }
    assert {geom for _, geom, _ in sim._terrain_contacts()} == direct
    q = sim.robot.neutral()
    q[sim.robot.model.joints[sim.robot.model.getJointId("boom_z")].idx_q] += 0.5  # in the air
    sim.reset(q)
    assert not sim.in_contact("left_foot") and sim.touching_terrain() == set()
    assert not np.any(sim.contact_force("left_foot"))


def test_model_module_keeps_the_names_imported_from_it() -> None:
    """``simulation.model`` still exports what other modules import from it (same objects)."""
    from virtual_actuators.simulation import geoms, ground, model

    assert model.__all__ == ["ContactParameters", "JointMap", "MujocoModel", "build_mujoco_model"]
    assert model.ContactParameters is ground.ContactParameters is ContactParameters
    assert model.Collisions is geoms.Collisions
