"""A contact's friction pyramid belongs to the contact, not to the frame {O} of the wrench.

The same physical request written in world axes and in the base's axes must give the same
world-frame forces, and both must meet the pyramid about world z (faces along world x and y:
``|f_x|, |f_y| <= mu f_z``, the pyramid circumscribing the cone, exact along its tangents).
Oracles: Pinocchio's placement of the base (the request transformed here), Pinocchio's foot
positions, a small proxsuite QP written below over the world-frame foot forces (no library
code), and direct checks of the inequalities.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from oracles import chain_forces_world, requires_core
from proxsuite import proxqp
from test_qp import SOLO_FEET, _weight
from test_qp_paths import SOLES, _check_soles

import virtual_actuators as va

MU, MIN_NORMAL = 0.6, 1.0
#: same forces whatever {O}, and the oracle's: to this fraction of the request (ProxQP stops
#: at 1e-10 of the scaled problem; measured 2e-11 on the compiled path, 9e-10 on numpy's)
SAME = 2e-9


def _placement(robot: va.Robot, q: np.ndarray, frame: str) -> pin.SE3:
    model = robot.model
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    return data.oMf[model.getFrameId(frame)]


def _tilted_standing(robot: va.Robot, rpy: tuple[float, float, float], rng) -> np.ndarray:
    """The neutral stance, base rotated by ``rpy``, joints moved a little."""
    step = rng.uniform(-0.15, 0.15, robot.model.nv)
    step[:6] = 0.0
    q = pin.integrate(robot.model, robot.neutral(), step)
    q[3:7] = pin.Quaternion(pin.rpy.rpyToMatrix(*rpy)).coeffs()
    return q


def _in_base(rotation_b: np.ndarray, wrench_world: np.ndarray) -> np.ndarray:
    """The request in the base's axes (moments still about the base's origin)."""
    return np.concatenate((rotation_b.T @ wrench_world[:3], rotation_b.T @ wrench_world[3:]))


def _check_world_pyramid(force_world: np.ndarray, scale: float, least: float = MIN_NORMAL) -> None:
    """``|f_x|, |f_y| <= mu f_z`` and ``f_z >= least``, world axes, to 1e-8 of the scale."""
    slack = 1e-8 * scale
    normal = force_world[:, 2]
    assert np.all(normal >= least - slack), normal
    assert np.all(np.abs(force_world[:, 0]) <= MU * normal + slack), force_world
    assert np.all(np.abs(force_world[:, 1]) <= MU * normal + slack), force_world


def _oracle_point_feet(robot: va.Robot, q: np.ndarray, wrench_world: np.ndarray) -> np.ndarray:
    """``(4, 3)`` world foot forces: least ``sum |F_i|^2`` under the world pyramids (proxsuite).

    Each point foot exerts ``F_i = (f_i, r_i x f_i)`` on the base (``r_i`` from the base's
    origin to the foot, world axes); ``sum F_i = w``. Solved on the request scaled to 1.
    """
    p_base = _placement(robot, q, "base_link").translation
    scale = float(np.linalg.norm(wrench_world))
    hessian = np.zeros((12, 12))
    equality = np.zeros((6, 12))
    inequality = np.zeros((20, 12))
    lows = np.zeros(20)
    for i, foot in enumerate(SOLO_FEET):
        lever = pin.skew(_placement(robot, q, foot).translation - p_base)
        block = slice(3 * i, 3 * i + 3)
        hessian[block, block] = np.eye(3) + lever.T @ lever
        equality[:3, block] = np.eye(3)
        equality[3:, block] = lever
        rows = [(0, 0, 1), (-1, 0, MU), (1, 0, MU), (0, -1, MU), (0, 1, MU)]
        inequality[5 * i : 5 * i + 5, block] = rows
        lows[5 * i] = MIN_NORMAL / scale
    qp = proxqp.dense.QP(12, 6, 20)
    qp.settings.eps_abs = 1e-13
    qp.settings.eps_rel = 0.0
    qp.settings.max_iter = 10_000
    qp.settings.verbose = False
    qp.init(hessian, np.zeros(12), equality, wrench_world / scale, inequality, lows,
            np.full(20, 1e20))  # fmt: skip
    qp.solve()
    assert qp.results.info.status == proxqp.QPSolverOutput.PROXQP_SOLVED
    return qp.results.x.reshape(4, 3) * scale


def _requests(robot: va.Robot, q: np.ndarray, feet: list[str], rng: np.random.Generator,
              count: int, edge: float = 0.95) -> list[np.ndarray]:  # fmt: skip
    """World requests that lean on the pyramids: each the wrench ``sum_i (f_i, r_i x f_i)`` of
    foot forces at ``edge`` times the world pyramid's edge (lateral forces in a common
    direction, spread normals; ``r_i`` from Pinocchio), so feasible when ``edge < 1``."""
    p_base = _placement(robot, q, "base_link").translation
    levers = [_placement(robot, q, foot).translation - p_base for foot in feet]
    weight = _weight(robot)
    out = []
    for _ in range(count):
        heading = rng.uniform(-np.pi, np.pi)
        wrench = np.zeros(6)
        for lever in levers:
            normal = weight * rng.uniform(0.2, 1.8) / len(feet)
            angle = heading + rng.normal() * 0.3
            direction = np.array([np.cos(angle), np.sin(angle)])
            lateral = edge * MU * normal * direction / np.abs(direction).max()
            force = np.array([*lateral, normal])
            wrench += np.concatenate((force, np.cross(lever, force)))
        out.append(wrench)
    return out


@requires_core
@pytest.mark.parametrize("compiled", [True, False])
def test_solo12_same_forces_in_world_and_base_axes(compiled):
    """solo12 standing, base rolled, pitched and yawed: a world request and the same request in
    base_link's axes give the same world foot forces (to 1e-9 of |w|), both inside the world
    pyramid, equal to the proxsuite oracle; the faces are active in most cases."""
    robot = va.load_robot("solo12")
    kwargs = {"friction": MU, "min_normal": MIN_NORMAL}
    world = va.ParallelVirtualActuator(robot, "base_link", SOLO_FEET, "world", **kwargs)
    base = va.ParallelVirtualActuator(robot, "base_link", SOLO_FEET, "base_link", **kwargs)
    assert world.qp.matrices.applicable and base.qp.matrices.applicable  # both paths exist
    rng = np.random.default_rng(24)
    active = 0
    for rpy in ((0.25, -0.2, 0.8), (-0.3, 0.15, -2.4), (0.1, 0.3, 3.0)):
        q = _tilted_standing(robot, rpy, rng)
        rotation_b = _placement(robot, q, "base_link").rotation
        assert abs(rotation_b[0, 0]) < 0.95  # {O} = base_link is not the world's axes
        for wrench in _requests(robot, q, SOLO_FEET, rng, 6):
            size = float(np.linalg.norm(wrench))
            sol_w = world.solve(q, wrench, method="qp", compiled=compiled, strict=True)
            sol_b = base.solve(q, _in_base(rotation_b, wrench), method="qp", compiled=compiled,
                               strict=True)  # fmt: skip
            force_w = chain_forces_world(world, q, sol_w.forces)
            force_b = chain_forces_world(base, q, sol_b.forces)
            np.testing.assert_allclose(force_b, force_w, rtol=0, atol=SAME * size)
            _check_world_pyramid(force_w, size)
            _check_world_pyramid(force_b, size)
            oracle = _oracle_point_feet(robot, q, wrench)
            np.testing.assert_allclose(force_w, oracle, rtol=0, atol=SAME * size)
            active += any("friction" in name for name in sol_w.active)
            assert sorted(sol_w.active) == sorted(sol_b.active)  # same faces, same names
    assert active >= 9  # the requests do lean on the pyramids


@pytest.mark.parametrize("normals", [None, "frames"])
def test_talos_soles_same_forces_in_world_and_base_axes(normals):
    """talos on its soles (flat contacts, centre of pressure and yaw moment bounded), pyramids
    about world z or about each sole's normal: the same physical request in world and in
    base_link axes gives the same world-frame wrenches on both matrix paths."""
    robot = va.load_robot("talos_reduced")
    kwargs = {"contact": "flat", "soles": SOLES, "friction": MU, "min_normal": 20.0,
              "normals": normals}  # fmt: skip
    world = va.ParallelVirtualActuator(robot, "base_link", list(SOLES), "world", **kwargs)
    base = va.ParallelVirtualActuator(robot, "base_link", list(SOLES), "base_link", **kwargs)
    rng = np.random.default_rng(7)
    active = missed = 0
    for rpy in ((0.05, -0.04, 0.9), (-0.04, 0.05, -2.0)):
        step = rng.uniform(-0.05, 0.05, robot.model.nv)
        step[:6] = 0.0
        q = pin.integrate(robot.model, robot.neutral(), step)
        q[3:7] = pin.Quaternion(pin.rpy.rpyToMatrix(*rpy)).coeffs()
        rotation_b = _placement(robot, q, "base_link").rotation
        # feasible (0.8 of the edge: the soles tilt by up to 0.05 rad) and not (1.3)
        for wrench in _requests(robot, q, list(SOLES), rng, 3, 0.8) + _requests(
            robot, q, list(SOLES), rng, 2, 1.3
        ):
            size = float(np.linalg.norm(wrench))
            for compiled in (True, False):
                sol_w = world.solve(q, wrench, method="qp", compiled=compiled)
                sol_b = base.solve(q, _in_base(rotation_b, wrench), method="qp",
                                   compiled=compiled)  # fmt: skip
                assert abs(sol_b.residual - sol_w.residual) <= SAME * size
                full_w = np.hstack((chain_forces_world(world, q, sol_w.forces),
                                    sol_w.forces[:, 3:]))  # fmt: skip
                full_b = np.hstack((chain_forces_world(base, q, sol_b.forces),
                                    sol_b.forces[:, 3:] @ rotation_b.T))  # fmt: skip
                np.testing.assert_allclose(full_b, full_w, rtol=0, atol=1e-8 * size)
                _check_soles(world, q, sol_w, MU)
                if normals is None:
                    _check_world_pyramid(full_w[:, :3], size, 20.0)
                    _check_world_pyramid(full_b[:, :3], size, 20.0)
                active += any("friction" in name for name in sol_w.active)
                missed += not sol_w.admissible
    assert active >= 8 and 4 <= missed <= 8  # faces active; the closest wrench compared too
