"""Spring Turkey and Spring Flamingo (seed 003_01cbf1bf710fbcc7): descriptions and VMC 4.1-4.2."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import virtual_actuators as va

LEG_JOINTS = ["left_hip", "left_knee", "right_hip", "right_knee"]
BOOM = ["boom_x", "boom_z", "boom_pitch"]

# name: (nq, joints, total mass, toe to hip, standing hip height, foot frame height standing)
SPECS = {
    "spring_turkey": (7, BOOM + LEG_JOINTS, 10.0, 0.60, 0.54, 0.02),
    "spring_flamingo": (
        9,
        BOOM + ["left_hip", "left_knee", "left_ankle", "right_hip", "right_knee", "right_ankle"],
        12.0,
        0.84,
        0.78,
        0.0,
    ),
}


@pytest.fixture(scope="module", params=sorted(SPECS))
def robot(request):
    return va.load_robot(request.param)


def _frame(robot, q, name):
    pin.framesForwardKinematics(robot.model, robot.data, q)
    return robot.data.oMf[robot.model.getFrameId(name)]


def _idx_v(robot, joint):
    return robot.model.joints[robot.model.getJointId(joint)].idx_v


def test_structure_and_mass(robot):
    nq, joints, mass, _, _, _ = SPECS[robot.name]
    model = robot.model
    assert model.nq == nq and model.nv == nq  # fixed base: no free flyer
    assert [model.names[i] for i in range(1, model.njoints)] == joints
    for frame in ("body", "left_foot", "right_foot"):
        assert model.existFrame(frame)
    assert pin.computeTotalMass(model) == pytest.approx(mass, abs=0.5)


def test_toe_to_hip_length(robot):
    _, _, _, length, _, _ = SPECS[robot.name]
    q = np.zeros(robot.model.nq)
    for side in ("left", "right"):
        hip = _frame(robot, q, f"{side}_hip").translation
        foot = _frame(robot, q, f"{side}_foot").translation
        assert foot - hip == pytest.approx([0.0, 0.0, -length], abs=1e-12)


def test_standing_pose(robot):
    _, _, _, _, height, foot_z = SPECS[robot.name]
    q = robot.neutral()
    model = robot.model
    assert np.all(q >= model.lowerPositionLimit) and np.all(q <= model.upperPositionLimit)
    assert _frame(robot, q, "body").translation[2] == pytest.approx(height, abs=1e-9)
    xs = []
    for side in ("left", "right"):
        foot = _frame(robot, q, f"{side}_foot")
        assert foot.translation[2] == pytest.approx(foot_z, abs=1e-9)
        xs.append(foot.translation[0])
        assert q[model.joints[model.getJointId(f"{side}_knee")].idx_q] > 0.3  # bent
        if robot.name == "spring_flamingo":
            assert np.allclose(foot.rotation, np.eye(3), atol=1e-9)  # foot flat
            for point in ("heel", "toe"):
                assert _frame(robot, q, f"{side}_{point}").translation[2] == pytest.approx(
                    0.0, abs=1e-9
                )
    assert xs[0] > 0.05 and xs[1] < -0.05  # feet apart in x


def test_flamingo_knee_bends_one_way():
    robot = va.load_robot("spring_flamingo")
    model = robot.model
    for side in ("left", "right"):
        jid = model.getJointId(f"{side}_knee")
        i = model.joints[jid].idx_q
        assert model.lowerPositionLimit[i] == 0.0 and model.upperPositionLimit[i] > 2.0
        q = np.zeros(model.nq)
        q[i] = 0.5  # allowed bend: the foot goes back, the knee forward
        knee = _frame(robot, q, f"{side}_knee").translation
        foot = _frame(robot, q, f"{side}_foot").translation
        assert foot[0] < knee[0] - 0.1
    for ankle in ("left_ankle", "right_ankle"):
        i = model.joints[model.getJointId(ankle)].idx_q
        assert model.lowerPositionLimit[i] < -0.5 and model.upperPositionLimit[i] > 0.5


def test_flamingo_single_support():
    robot = va.load_robot("spring_flamingo")
    q = robot.neutral()
    body = va.ParallelVirtualActuator(
        robot,
        "body",
        ["left_foot"],
        reference="world",
        axes=("x", "z", "ry"),
        contact="flat",
        unactuated=["left_ankle"],
    )
    sol = body.solve(q, [0.0, 100.0, 5.0], free=("x",))
    assert sol.method == "partitioned"
    assert sol.residual < 1e-9
    assert abs(sol.tau[_idx_v(robot, "left_ankle")]) < 1e-9
    assert sol.wrench[1:] == pytest.approx([100.0, 5.0], abs=1e-9)
    # right leg and boom are not in the chain
    for joint in BOOM + ["right_hip", "right_knee", "right_ankle"]:
        assert sol.tau[_idx_v(robot, joint)] == 0.0


@pytest.mark.parametrize(
    ("name", "contact", "unactuated"),
    [
        ("spring_flamingo", "flat", ["left_ankle", "right_ankle"]),
        ("spring_turkey", "point", []),
    ],
)
def test_double_support(name, contact, unactuated):
    robot = va.load_robot(name)
    q = robot.neutral()
    body = va.ParallelVirtualActuator(
        robot,
        "body",
        ["left_foot", "right_foot"],
        reference="world",
        axes=("x", "z", "ry"),
        contact=contact,
        unactuated=unactuated,
        design=[va.EqualTorque("left_hip", "right_hip")],
    )
    wrench = [10.0, 110.0, 2.0]
    sol = body.solve(q, wrench)
    dense = body.solve(q, wrench, method="dense")
    assert sol.method == "partitioned"
    assert sol.residual < 1e-9
    assert sol.wrench == pytest.approx(wrench, abs=1e-9)
    assert np.allclose(sol.tau, dense.tau, atol=1e-9)
    assert np.allclose(sol.forces, dense.forces, atol=1e-9)
    assert sol.tau[_idx_v(robot, "left_hip")] == pytest.approx(
        sol.tau[_idx_v(robot, "right_hip")], abs=1e-9
    )
    for joint in unactuated:
        assert abs(sol.tau[_idx_v(robot, joint)]) < 1e-9
    assert np.any(np.abs(sol.tau) > 1.0)


def test_files_match_generator():
    import importlib.util
    import sys
    from pathlib import Path

    robots_dir = Path(__file__).resolve().parent.parent / "robots"
    spec = importlib.util.spec_from_file_location("bipeds_build", robots_dir / "bipeds/build.py")
    build = importlib.util.module_from_spec(spec)
    sys.modules["bipeds_build"] = build  # dataclasses look their module up there
    spec.loader.exec_module(build)
    for biped in build.BIPEDS:
        folder = robots_dir / biped.name
        assert (folder / f"{biped.name}.urdf").read_text() == build.urdf(biped)
        assert (folder / f"{biped.name}.srdf").read_text() == build.srdf(biped)
