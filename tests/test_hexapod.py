"""Tests of the hexapod description in robots/hexapod (seed 000_..., section 3)."""

from __future__ import annotations

import importlib.util
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

import virtual_actuators as va

BUILD = Path(__file__).resolve().parents[1] / "robots" / "hexapod" / "build.py"
LEGS = range(1, 7)
TRIPOD = ["foot_1", "foot_3", "foot_5"]
WEIGHT = 3.8 * 9.81


@pytest.fixture(scope="module")
def robot():
    return va.load_robot("hexapod")


@pytest.fixture(scope="module")
def build():
    spec = importlib.util.spec_from_file_location("hexapod_build", BUILD)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def feet(robot, q):
    model, data = robot.model, robot.data
    pin.framesForwardKinematics(model, data, q)
    return {i: data.oMf[model.getFrameId(f"foot_{i}")].translation.copy() for i in LEGS}


def test_files_match_build_script(robot, build):
    folder = BUILD.parent
    assert (folder / "hexapod.urdf").read_text(encoding="utf-8") == build.build_urdf()
    assert (folder / "hexapod.srdf").read_text(encoding="utf-8") == build.build_srdf()
    assert robot.urdf_path == (folder / "hexapod.urdf").resolve()


def test_names_mass_and_size(robot):
    model = robot.model
    assert robot.floating_base
    assert model.joints[1].shortname() == "JointModelFreeFlyer"
    assert (model.nq, model.nv) == (7 + 18, 6 + 18)
    for name in ["body", *(f"foot_{i}" for i in LEGS)]:
        assert model.existFrame(name), name
    for i in LEGS:
        for joint in (f"hip1_{i}", f"hip2_{i}", f"knee_{i}"):
            assert model.existJointName(joint), joint
    assert pin.computeTotalMass(model) == pytest.approx(3.8, abs=0.1)

    root = ET.fromstring(robot.urdf_string)
    body = root.find("link[@name='body']")
    size = [float(x) for x in body.find("visual/geometry/box").get("size").split()]
    assert size[0] == pytest.approx(0.45)
    mounts = [
        [float(x) for x in j.find("origin").get("xyz").split()]
        for j in root.findall("joint")
        if j.get("name").startswith("hip1_")
    ]
    xs = sorted({m[0] for m in mounts})
    assert xs == pytest.approx([-0.15, 0.0, 0.15])
    assert sorted({abs(m[1]) for m in mounts}) == pytest.approx([0.075])


def test_joint_axes(robot):
    model = robot.model
    for i in LEGS:
        for name, axis in (("hip1", 2), ("hip2", 0), ("knee", 0)):
            joint = model.joints[model.getJointId(f"{name}_{i}")]
            assert joint.shortname() == f"JointModelR{'XYZ'[axis]}", (name, i)


def test_zero_configuration_legs_straight_down(robot):
    model = robot.model
    q = pin.neutral(model)
    model_mounts = {
        i: model.jointPlacements[model.getJointId(f"hip1_{i}")].translation for i in LEGS
    }
    for i, p in feet(robot, q).items():
        np.testing.assert_allclose(p, model_mounts[i] + [0.0, 0.0, -0.2], atol=1e-12)


def test_standing_pose(robot):
    model = robot.model
    q = robot.neutral()
    np.testing.assert_allclose(q[:7], [0, 0, 0.13, 0, 0, 0, 1], atol=1e-12)
    assert np.all(q[7:] >= model.lowerPositionLimit[7:])
    assert np.all(q[7:] <= model.upperPositionLimit[7:])
    for i, p in feet(robot, q).items():
        assert p[2] == pytest.approx(0.02, abs=1e-6), i
        # Each foot sits outside its hip's yaw axis and each knee is bent: no leg is singular.
        jac = pin.computeFrameJacobian(
            model, robot.data, q, model.getFrameId(f"foot_{i}"), pin.LOCAL_WORLD_ALIGNED
        )
        cols = [model.joints[model.getJointId(f"{n}_{i}")].idx_v for n in ("hip1", "hip2", "knee")]
        sv = np.linalg.svd(jac[:3, cols], compute_uv=False)
        assert sv[-1] > 0.01, (i, sv)
    body = robot.data.oMf[model.getFrameId("body")].translation
    assert body[2] == pytest.approx(0.13, abs=1e-12)


def test_tripod_pseudo_inverse(robot):
    body = va.ParallelVirtualActuator(robot, "body", TRIPOD, reference="body")
    sizes = body.sizes()
    assert {k: sizes[k] for k in ("n", "p", "l_total", "d_total", "r")} == {
        "n": 6,
        "p": 3,
        "l_total": 9,
        "d_total": 9,
        "r": 3,
    }
    wrench = [0, 0, WEIGHT / 2, 0, 0, 0]
    sol = body.solve(robot.neutral(), wrench)
    assert sol.method == "pseudo-inverse"
    assert sol.residual < 1e-9
    np.testing.assert_allclose(sol.wrench, wrench, atol=1e-9)


def test_tripod_seed_design_constraints(robot):
    design = [
        va.Equal((TRIPOD[2], "x"), (TRIPOD[1], "x")),
        va.Equal((TRIPOD[2], "y"), (TRIPOD[1], "y")),
        va.Linear({(TRIPOD[0], "y"): 1.0, (TRIPOD[1], "y"): -2.0}),
    ]
    body = va.ParallelVirtualActuator(robot, "body", TRIPOD, reference="body", design=design)
    assert body.sizes()["design"] == 3
    q = robot.neutral()
    wrench = np.array([1.0, 0.5, WEIGHT / 2, 0.1, 0.2, 0.05])
    sol = body.solve(q, wrench)
    dense = body.solve(q, wrench, method="dense")
    assert sol.method == "partitioned"
    assert [len(sol.sets[k]) for k in ("MFS", "RFS", "CFS")] == [6, 3, 9]
    assert sol.residual < 1e-9
    np.testing.assert_allclose(sol.forces, dense.forces, atol=1e-9)
    f = sol.forces
    assert f[2, 0] == pytest.approx(f[1, 0], abs=1e-9)
    assert f[2, 1] == pytest.approx(f[1, 1], abs=1e-9)
    assert f[0, 1] == pytest.approx(2 * f[1, 1], abs=1e-9)
    np.testing.assert_allclose(f.sum(axis=0), wrench, atol=1e-9)
