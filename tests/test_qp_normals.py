"""QP contact normals that follow the reaction frames (``normals="frames"`` or ``"frame"``).

Oracles: Pinocchio's frame placements (each frame's z axis, the pyramid rebuilt here from it),
RNEA with external forces for the torques, the numpy path of the QP (all force entries) for the
compiled path (free coordinates), and the same QP declared with fixed world normals equal to the
frames' z axes at that configuration (the fixed-vector code path).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from oracles import chain_forces_world, requires_core
from test_qp import TOL, _check_torques, _weight
from test_qp_paths import SOLES, _check_paths, _check_soles, _request

import virtual_actuators as va
from virtual_actuators.exceptions import InvalidInputError

SOLO_FEET = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]


def _tilted_q(robot: va.Robot, rng: np.random.Generator, scale: float) -> np.ndarray:
    """A random configuration with the base tilted too (so the frames' normals are not z)."""
    step = rng.uniform(-scale, scale, robot.model.nv)
    step[:3] = 0.0
    return pin.integrate(robot.model, robot.neutral(), step)


def _frame_normals(body, q) -> np.ndarray:
    """``(p, 3)`` each reaction frame's z axis in the world (Pinocchio)."""
    model = body.robot.model
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    return np.array([data.oMf[model.getFrameId(r)].rotation[:, 2] for r in body.reactions])


def _check_frame_cone(body, q, sol, mu, min_normal) -> None:
    """Each chain's force against the pyramid about its frame's z axis (to 1e-8 relative).

    The pyramid's tangents as documented: ``t1 = n x e`` normalised (``e`` the world x axis, or
    y when ``|n_x| >= 0.9``), ``t2 = n x t1``.
    """
    force_world = chain_forces_world(body, q, sol.forces)  # rows: R_O f
    scale = max(np.abs(sol.forces).max(), 1.0)
    for normal, force in zip(_frame_normals(body, q), force_world, strict=True):
        helper = np.array([1.0, 0.0, 0.0] if abs(normal[0]) < 0.9 else [0.0, 1.0, 0.0])
        tangent1 = np.cross(normal, helper)
        tangent1 /= np.linalg.norm(tangent1)
        tangent2 = np.cross(normal, tangent1)
        f_n = normal @ force
        assert f_n >= min_normal - TOL * scale, f_n
        assert abs(tangent1 @ force) <= mu * f_n + TOL * scale
        assert abs(tangent2 @ force) <= mu * f_n + TOL * scale


def _flamingo_body(**kwargs) -> va.ParallelVirtualActuator:
    robot = va.load_robot("spring_flamingo")
    return va.ParallelVirtualActuator(
        robot, "body", ["left_foot", "right_foot"], "world", ("x", "z", "ry"), contact="flat",
        unactuated=["left_ankle", "right_ankle"], **kwargs,
    )  # fmt: skip


CASES = [  # robot, friction, least normal force, spread of the request, cases
    ("solo12", 0.5, 1.0, 0.4, 150),
    ("talos_reduced", 0.7, 20.0, 0.02, 100),
    ("spring_flamingo", 0.6, 10.0, 0.3, 150),
]


def _declare(name: str, **kwargs) -> va.ParallelVirtualActuator:
    if name == "spring_flamingo":
        return _flamingo_body(**kwargs)
    robot = va.load_robot(name)
    if name == "talos_reduced":
        return va.ParallelVirtualActuator(
            robot, "base_link", list(SOLES), "world", contact="flat", soles=SOLES, **kwargs
        )
    return va.ParallelVirtualActuator(robot, "base_link", SOLO_FEET, "world", **kwargs)


def _planar_request(robot: va.Robot, rng: np.random.Generator, spread: float) -> np.ndarray:
    weight = _weight(robot)
    return np.array([rng.normal() * weight * spread, weight * rng.uniform(0.5, 1.5),
                     rng.normal() * weight * spread * 0.05])  # fmt: skip


@requires_core
@pytest.mark.parametrize(("name", "mu", "min_normal", "spread", "count"), CASES)
def test_cones_about_the_frames_normals_on_both_paths(name, mu, min_normal, spread, count):
    """Random tilted configurations and requests pressing on the cones: every answer meets the
    pyramid about each reaction frame's own z axis (Pinocchio) to 1e-8, its torques are the
    RNEA of its forces, and the compiled path gives the numpy path's answer."""
    robot = va.load_robot(name)
    body = _declare(name, friction=mu, min_normal=min_normal, normals="frames")
    assert body.qp.matrices.applicable
    assert body.contacts.normals.frame.all()
    rng = np.random.default_rng(len(name) + 40)
    tilt = {"talos_reduced": 0.05, "spring_flamingo": 0.3}.get(name, 0.25)
    active = 0
    for _ in range(count):
        q = _tilted_q(robot, rng, tilt)
        wrench = (_planar_request if name == "spring_flamingo" else _request)(robot, rng, spread)
        sol = body.solve(q, wrench, method="qp")
        active += bool(sol.active)
        _check_frame_cone(body, q, sol, mu, min_normal)
        if name == "talos_reduced":
            _check_soles(body, q, sol, mu)
        _check_torques(name, body, q, sol)
        _check_paths(body, q, wrench, sol)
    assert active >= 0.2 * count  # the requests do press on the cones


def test_frame_normals_equal_fixed_normals_at_the_same_configuration():
    """At one configuration, ``"frame"`` normals give the answer of the same QP declared with
    fixed world normals equal to the frames' z axes there (the fixed-vector path, numpy
    oracle for the axes), one reaction following its frame and one left at world z."""
    robot = va.load_robot("solo12")
    rng = np.random.default_rng(3)
    following = {"FL_FOOT": "frame", "HR_FOOT": "frame"}
    body = _declare("solo12", friction=0.5, min_normal=1.0, normals=following)
    assert list(body.contacts.normals.frame) == [True, False, False, True]
    for _ in range(15):
        q = _tilted_q(robot, rng, 0.3)
        wrench = _request(robot, rng, 0.4)
        normals = _frame_normals(body, q)
        fixed = _declare("solo12", friction=0.5, min_normal=1.0,
                         normals={"FL_FOOT": normals[0], "HR_FOOT": normals[3]})  # fmt: skip
        sol = body.solve(q, wrench, method="qp")
        ref = fixed.solve(q, wrench, method="qp")
        scale = max(np.abs(wrench).max(), 1.0)
        np.testing.assert_allclose(sol.forces, ref.forces, rtol=0, atol=1e-6 * scale)
        assert sol.active == ref.active


def test_frame_normals_differ_from_world_z_when_the_feet_tilt():
    """The option is not a no-op: on a sole tilted 0.3 rad, a sideways push that the world-z
    pyramid allows leaves the frame's pyramid (the answers differ and only one meets it)."""
    body = _flamingo_body(friction=0.6, min_normal=10.0, normals="frames")
    world = _flamingo_body(friction=0.6, min_normal=10.0)
    robot = body.robot
    q = robot.neutral().copy()
    model = robot.model
    for joint in ("left_ankle", "right_ankle"):
        q[model.joints[model.getJointId(joint)].idx_q] = 0.3  # both soles pitched
    wrench = np.array([0.55 * _weight(robot), _weight(robot), 0.0])
    follow = body.solve(q, wrench, method="qp")
    plain = world.solve(q, wrench, method="qp")
    _check_frame_cone(body, q, follow, 0.6, 10.0)
    assert np.abs(follow.forces - plain.forces).max() > 1e-3 * _weight(robot)


@pytest.mark.parametrize(
    ("normals", "word"),
    [("frame", "'frames'"), ({"left_foot": "frames"}, "'frame'"), ({"left_foot": [0, 0, 0]},
     "nonzero"), ({"nose": "frame"}, "nose"), (3.0, "mapping")],
)  # fmt: skip
def test_bad_normals_are_named(normals, word):
    with pytest.raises(InvalidInputError, match=word):
        _flamingo_body(friction=0.6, normals=normals)
