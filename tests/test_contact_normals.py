"""Point-foot cones are about world z, whatever the foot frame's orientation, in both layers.

solo12's foot frames are ~46 degrees off vertical at the neutral stance (and turn with the
legs), so a cone about the frame's z would tilt with the leg. The QP's rows
(``ParallelVirtualActuator(friction=)``) and the controller's yield policy
(``Controller.add(friction=)``) read one :class:`~virtual_actuators.contacts.ContactSet`; both
must give the pyramid ``mu f_z -+ f_x``, ``mu f_z -+ f_y`` of the world force, an oracle built by
hand from ``mu`` and the world axes, with {O}'s rotation from Pinocchio. ``normals="frames"``
(the opt-in) gives faces about each foot frame's z axis instead.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from oracles import requires_core, robot

import virtual_actuators as va
from virtual_actuators.components import ConstantForce
from virtual_actuators.control import Controller
from virtual_actuators.control.failures import constraint_rows, least_margin

FEET = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
FORCES = ("x", "y", "z")


def _configuration(rob: va.Robot, rng: np.random.Generator) -> np.ndarray:
    """A random base orientation and joint angles around the neutral stance."""
    q = rob.neutral()
    q[3:7] = pin.Quaternion(pin.exp3(rng.uniform(-0.6, 0.6, 3))).coeffs()
    q[7:] += rng.uniform(-0.7, 0.7, rob.model.nq - 7)
    return q


def _rotations(rob: va.Robot, q: np.ndarray, reference: str) -> tuple[np.ndarray, list]:
    model = rob.model
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    rotation = data.oMf[model.getFrameId(reference)].rotation if reference != "world" else np.eye(3)
    return rotation, [data.oMf[model.getFrameId(foot)].rotation for foot in FEET]


def _world_pyramid(forces_o: np.ndarray, rotation_o: np.ndarray, mu: float) -> np.ndarray:
    """``(p, 4)`` sorted ``mu f_z -+ f_x, mu f_z -+ f_y`` of each foot's world force."""
    world = forces_o @ rotation_o.T  # rows: R_O f
    fx, fy, fz = world[:, 0], world[:, 1], world[:, 2]
    faces = np.stack((mu * fz - fx, mu * fz + fx, mu * fz - fy, mu * fz + fy), axis=1)
    return np.sort(faces, axis=1)


def _layers(reference: str, mu: float, normals=None):
    """The QP's contacts and the controller's attachment, on one solo12 body actuator."""
    rob = robot("solo12")
    body = va.ParallelVirtualActuator(
        rob, "base_link", FEET, reference, FORCES, friction=mu, normals=normals
    )
    controller = Controller(rob, clip=False)
    controller.add(
        "body", body, [ConstantForce(FORCES, [0.0, 0.0, 20.0])], yield_axes=("x", "y"),
        friction=mu,
    )  # fmt: skip
    return rob, body, controller.attachments["body"]


@requires_core
@pytest.mark.parametrize("reference", ["world", "base_link"])
def test_both_layers_put_the_cone_about_world_z_whatever_the_foot_frames(reference):
    rng = np.random.default_rng(3)
    mu = 0.6
    rob, body, attachment = _layers(reference, mu)
    tilts = []
    for _ in range(30):
        q = _configuration(rob, rng)
        snapshot = va.Snapshot(rob, q, np.zeros(rob.model.nv))
        rotation_o, feet = _rotations(rob, q, reference)
        tilts += [np.degrees(np.arccos(np.clip(foot[2, 2], -1, 1))) for foot in feet]
        forces = rng.normal(0.0, 20.0, (4, 3)) + [0.0, 0.0, 30.0]
        expected = _world_pyramid(forces, rotation_o, mu)
        # the QP's rows (the actuator's contacts) and the controller's, one row set each
        qp_rows = body.contacts.rows(*body.kinematics.rotations(snapshot))
        controller_rows, lows = constraint_rows(attachment, snapshot)
        for G in (qp_rows.G, controller_rows):
            values = (G @ forces.ravel()).reshape(4, 4)
            np.testing.assert_allclose(np.sort(values, axis=1), expected, rtol=0, atol=1e-11)
        assert np.all(lows == 0.0) and np.all(qp_rows.lows == 0.0)
        margin = least_margin(attachment, snapshot, forces)  # compiled, the same rows
        assert margin == pytest.approx(expected.min(), rel=1e-12, abs=1e-11)
    assert max(tilts) > 40.0  # the feet frames are far from vertical


def test_normals_frames_puts_each_cone_about_its_foot_frames_z():
    rng = np.random.default_rng(4)
    mu = 0.8
    rob, body, attachment = _layers("base_link", mu, normals="frames")
    for _ in range(20):
        q = _configuration(rob, rng)
        snapshot = va.Snapshot(rob, q, np.zeros(rob.model.nv))
        rotation_o, feet = _rotations(rob, q, "base_link")
        for G in (body.contacts.rows(*body.kinematics.rotations(snapshot)).G,
                  constraint_rows(attachment, snapshot)[0]):  # fmt: skip
            for chain, foot in enumerate(feet):
                normal = foot[:, 2]  # the foot frame's z in the world
                faces = G[4 * chain : 4 * chain + 4, 3 * chain : 3 * chain + 3] @ rotation_o.T
                tangents = faces - mu * normal  # each face is mu n -+ t, t a unit tangent
                np.testing.assert_allclose(faces @ normal, mu, atol=1e-12)
                np.testing.assert_allclose(np.linalg.norm(tangents, axis=1), 1.0, atol=1e-12)
                np.testing.assert_allclose(tangents[0], -tangents[1], atol=1e-12)
                np.testing.assert_allclose(tangents[2], -tangents[3], atol=1e-12)
                assert abs(tangents[0] @ tangents[2]) < 1e-12


def test_the_controller_reads_the_actuators_declared_normals():
    rob = robot("solo12")
    normal = np.array([0.2, -0.1, 1.0])
    body = va.ParallelVirtualActuator(
        rob, "base_link", FEET, "world", FORCES, normals={"FL_FOOT": normal, "HR_FOOT": "frame"}
    )
    controller = Controller(rob, clip=False)
    controller.add("body", body, [], yield_axes=("x",), friction=0.5)
    contacts = controller.attachments["body"].contacts
    assert contacts.normals is body.contacts.normals
    np.testing.assert_allclose(contacts.normals.world[0], normal / np.linalg.norm(normal))
    assert list(contacts.normals.frame) == [False, False, False, True]
