"""MeshCat viewer: what is sent to the scene, checked without a browser or a server.

Every viewer here draws into a :class:`CommandRecorder` (or an :class:`OfflineWindow`), so the
tests read the commands themselves: object paths, ``set_transform`` matrices, ``visible``
properties. Expected positions come from Pinocchio's forward kinematics, never from the viewer.
"""

from __future__ import annotations

import base64
import functools
import re
from types import SimpleNamespace

import meshcat.geometry as mg
import numpy as np
import pinocchio as pin
import pytest
import scene_commands as sent
import umsgpack
from lab_colors import chroma, color_distance
from meshcat.commands import SetTransform
from meshcat.path import Path as MeshcatPath

import virtual_actuators as va
from virtual_actuators.__main__ import main
from virtual_actuators.gaits.hexapod.body import HeadingDamper
from virtual_actuators.visualization import PALETTE, CommandRecorder, OfflineWindow, Viewer
from virtual_actuators.visualization.legend import OVERLAY_MIN_CHROMA, ROBOT_MAX_CHROMA, to_lab
from virtual_actuators.visualization.live import _matrix_bytes, _transform_header
from virtual_actuators.visualization.shapes import (
    HEAD_SPACING,
    arrow_matrices,
    rotation_y_to,
    span_matrix,
)

ROOT = "/meshcat/virtual_actuators"
FEET = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]


@functools.cache
def robot(name: str) -> va.Robot:
    return va.load_robot(name)


def placements(rob: va.Robot, q: np.ndarray) -> pin.Data:
    data = pin.Data(rob.model)
    pin.framesForwardKinematics(rob.model, data, q)
    return data


def frame_pose(rob: va.Robot, data: pin.Data, name: str) -> pin.SE3:
    return pin.SE3.Identity() if name == "world" else data.oMf[rob.model.getFrameId(name)]


def arrow(rec: CommandRecorder, name: str) -> tuple[np.ndarray, np.ndarray]:
    """``(tail, tip)`` of an arrow from its last shaft and head transforms and head geometry."""
    shaft = sent.last_transform(rec, f"{ROOT}/{name}/shaft")
    head = sent.last_transform(rec, f"{ROOT}/{name}/head0")
    assert shaft is not None and head is not None, name
    height = sent.objects(rec)[f"{ROOT}/{name}/head0"]["geometries"][0]["height"]
    tail = shaft[:3, 3] - shaft[:3, 1] / 2.0  # unit cylinder centred on its node
    tip = head[:3, 3] + head[:3, 1] * height / 2.0  # cone apex at +height/2
    return tail, tip


def color_of(rec: CommandRecorder, path: str) -> int:
    return sent.objects(rec)[path]["materials"][0]["color"]


def shown(rec: CommandRecorder, name: str) -> bool:
    """Whether a dynamic node is visible: objects start visible until a property hides them."""
    path = f"{ROOT}/{name}"
    created = any(p == path or p.startswith(path + "/") for p in sent.objects(rec))
    return created and sent.visible(rec, path) is not False


def rotated_solo12() -> tuple[va.Robot, np.ndarray]:
    rob = robot("solo12")
    q = rob.neutral()
    q[3:7] = pin.Quaternion(pin.rpy.rpyToMatrix(0.2, -0.15, 0.5)).coeffs()  # base yawed, tilted
    return rob, q


@pytest.fixture(scope="module")
def solo_view():
    rob, q = rotated_solo12()
    body = va.ParallelVirtualActuator(rob, "base_link", FEET, reference="base_link")
    wrench = np.array([3.0, -2.0, 25.0, 0.4, -0.3, 0.2])
    sol = body.solve(q, wrench)
    rec = CommandRecorder()
    viewer = Viewer(rob, window=rec, force_scale=0.02, moment_scale=0.3)
    rec.commands.clear()
    viewer.show(q, sol, actuator=body)
    return SimpleNamespace(robot=rob, q=q, body=body, sol=sol, rec=rec, viewer=viewer)


# -- pure geometry ---------------------------------------------------------------------------


def test_rotation_y_to_is_a_rotation_onto_the_direction():
    rng = np.random.default_rng(5)
    directions = [*rng.normal(size=(20, 3)), [0, 1, 0], [0, -1, 0], [0, -1, 1e-13], [3, 0, 0]]
    for direction in directions:
        rot = rotation_y_to(direction)
        unit = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
        np.testing.assert_allclose(rot @ [0, 1, 0], unit, atol=1e-12)
        np.testing.assert_allclose(rot.T @ rot, np.eye(3), atol=1e-12)
        assert np.linalg.det(rot) == pytest.approx(1.0, abs=1e-12)
    with pytest.raises(ValueError):
        rotation_y_to([0, 0, 0])


def test_arrow_tip_lands_on_origin_plus_vector():
    origin, vector = np.array([0.1, -0.2, 0.3]), np.array([0.3, -0.4, 1.2])
    for heads, head_length in ((1, 0.1), (2, 0.1), (1, 5.0), (2, 5.0)):
        shaft, *cones = arrow_matrices(origin, vector, head_length, heads)
        assert len(cones) == heads
        tail = shaft[:3, 3] - shaft[:3, 1] / 2
        np.testing.assert_allclose(tail, origin, atol=1e-12)
        tip = cones[0][:3, 3] + cones[0][:3, 1] * head_length / 2  # head scaled down if long
        np.testing.assert_allclose(tip, origin + vector, atol=1e-12)
        used = min(head_length, np.linalg.norm(vector) / (heads + 1))
        assert np.linalg.norm(cones[0][:3, 1]) == pytest.approx(used / head_length, rel=1e-12)
        length = np.linalg.norm(vector)
        np.testing.assert_allclose(  # the shaft ends at the base of the first head
            shaft[:3, 3] + shaft[:3, 1] / 2, origin + vector * (1 - used / length), atol=1e-12
        )
        if heads == 2:
            gap = cones[0][:3, 3] - cones[1][:3, 3]
            np.testing.assert_allclose(gap, vector / length * HEAD_SPACING * used, atol=1e-12)
    assert arrow_matrices(origin, np.zeros(3), 0.1) is None


def test_span_matrix_maps_the_unit_shape_onto_the_segment():
    start, end = np.array([1.0, 2.0, 3.0]), np.array([0.5, 2.5, 2.0])
    matrix = span_matrix(start, end)
    np.testing.assert_allclose(matrix @ [0, -0.5, 0, 1], [*start, 1], atol=1e-12)
    np.testing.assert_allclose(matrix @ [0, 0.5, 0, 1], [*end, 1], atol=1e-12)
    assert span_matrix(start, start) is None


def test_fast_transform_packing_equals_meshcat_packing():
    matrix = np.arange(16.0).reshape(4, 4) / 7.0
    path = "/meshcat/virtual_actuators/robot/visuals/body_0"
    expected = SetTransform(matrix, MeshcatPath(tuple(path.split("/")[1:]))).lower()
    packed = _transform_header(path) + _matrix_bytes(matrix)  # what LiveWindow sends
    assert umsgpack.unpackb(packed) == expected


# -- a quadruped with meshes: wrench arrows against the solution -----------------------------


def test_robot_meshes_and_their_placements(solo_view):
    rob, q, rec = solo_view.robot, solo_view.q, solo_view.rec
    geometry = pin.buildGeomFromUrdfString(
        rob.model, rob.urdf_string, pin.GeometryType.VISUAL, package_dirs=rob.package_dirs
    )
    data = placements(rob, q)
    geometry_data = pin.GeometryData(geometry)
    pin.updateGeometryPlacements(rob.model, data, geometry, geometry_data)
    assert solo_view.viewer.bodies.kind == "urdf"
    for k, geometry_object in enumerate(geometry.geometryObjects):
        path = f"{ROOT}/robot/visuals/{geometry_object.name}"
        expected = geometry_data.oMg[k].homogeneous @ np.diag([*geometry_object.meshScale, 1])
        np.testing.assert_allclose(sent.last_transform(rec, path), expected, atol=1e-12)
    meshes = [p for p in solo_view.viewer.window._nodes if "/robot/visuals/" in p]
    assert len(meshes) == geometry.ngeoms == 17


def test_requested_force_and_moment_arrows_follow_the_wrench(solo_view):
    rob, q, rec, sol = solo_view.robot, solo_view.q, solo_view.rec, solo_view.sol
    base = frame_pose(rob, placements(rob, q), "base_link")
    rotation = base.rotation  # {O} = base_link: the wrench is along the tilted body's axes
    tail, tip = arrow(rec, "wrench/actuator/requested/force")
    np.testing.assert_allclose(tail, base.translation, atol=1e-12)
    np.testing.assert_allclose(tip - tail, rotation @ sol.requested[:3] * 0.02, atol=1e-12)
    assert np.linalg.norm(tip - tail) == pytest.approx(np.linalg.norm(sol.requested[:3]) * 0.02)
    tail, tip = arrow(rec, "wrench/actuator/requested/moment")
    np.testing.assert_allclose(tail, base.translation, atol=1e-12)
    np.testing.assert_allclose(tip - tail, rotation @ sol.requested[3:] * 0.3, atol=1e-12)
    assert sent.last_transform(rec, f"{ROOT}/wrench/actuator/requested/moment/head1") is not None
    assert color_of(rec, f"{ROOT}/wrench/actuator/requested/force/shaft") == 0x1E88E5


def test_each_chain_share_is_drawn_at_its_reaction_frame(solo_view):
    rob, q, rec, sol = solo_view.robot, solo_view.q, solo_view.rec, solo_view.sol
    data = placements(rob, q)
    rotation = frame_pose(rob, data, "base_link").rotation
    total = np.zeros(3)
    for foot, share in zip(FEET, sol.forces, strict=True):
        tail, tip = arrow(rec, f"wrench/actuator/share/{foot}/force")
        np.testing.assert_allclose(tail, frame_pose(rob, data, foot).translation, atol=1e-12)
        np.testing.assert_allclose(tip - tail, rotation @ share[:3] * 0.02, atol=1e-12)
        total += (tip - tail) / 0.02
        # point feet: no moment about the foot, so no moment arrow
        assert not shown(rec, f"wrench/actuator/share/{foot}/moment")
    np.testing.assert_allclose(total, rotation @ sol.requested[:3], atol=1e-9)
    # an admissible request: the produced wrench is the request, not drawn twice
    assert not shown(rec, "wrench/actuator/produced/force")
    assert not shown(rec, "wrench/actuator/inadmissible/force")


def test_triads_sit_on_the_action_reaction_and_reference_frames(solo_view):
    rob, q, rec = solo_view.robot, solo_view.q, solo_view.rec
    data = placements(rob, q)
    for role, frame in [("action", "base_link"), ("reference", "base_link")] + [
        ("reaction", foot) for foot in FEET
    ]:
        matrix = sent.last_transform(rec, f"{ROOT}/frames/{role}/{frame}")
        np.testing.assert_allclose(matrix, frame_pose(rob, data, frame).homogeneous, atol=1e-12)
        assert shown(rec, f"frames/{role}/{frame}")


def test_moment_shares_are_moments_about_the_reaction_frame():
    rob = robot("spring_flamingo")  # flat feet on actuated ankles: moments at the feet
    q = rob.neutral()
    feet = ["left_foot", "right_foot"]
    body = va.ParallelVirtualActuator(rob, "body", feet, "world", ("x", "z", "ry"), contact="flat")
    sol = body.solve(q, np.array([10.0, 120.0, 4.0]))
    rec = CommandRecorder()
    viewer = Viewer(rob, window=rec, moment_scale=0.5, legend=False)
    viewer.show(q, sol, actuator=body)
    data = placements(rob, q)
    origin = frame_pose(rob, data, "body").translation
    moments = []
    for foot, (fx, fz, m_ry) in zip(feet, sol.forces, strict=True):
        at = frame_pose(rob, data, foot).translation
        moved = m_ry + np.cross(origin - at, [fx, 0.0, fz])[1]  # about the foot, on ry only
        tail, tip = arrow(rec, f"wrench/actuator/share/{foot}/moment")
        np.testing.assert_allclose(tail, at, atol=1e-12)
        np.testing.assert_allclose(tip - tail, [0.0, moved * 0.5, 0.0], atol=1e-12)
        moments.append(moved)
    assert min(abs(m) for m in moments) > 0.05  # both really drawn (each is 0.1 N m here)


# -- produced versus requested ---------------------------------------------------------------


def test_an_inadmissible_request_shows_the_produced_wrench_in_red():
    rob = robot("spring_flamingo")  # planar, on a boom: no force along y
    q = rob.neutral()
    body = va.ParallelVirtualActuator(
        rob, "body", ["left_foot", "right_foot"], "world", axes=("x", "y", "z"), contact="point"
    )
    sol = body.solve(q, np.array([5.0, 30.0, 120.0]))
    assert sol.method == "least-squares" and abs(sol.wrench[1]) < 1e-6
    rec = CommandRecorder()
    viewer = Viewer(rob, window=rec, force_scale=0.005)
    viewer.show(q, sol, actuator=body)
    origin = frame_pose(rob, placements(rob, q), "body").translation
    tail, tip = arrow(rec, "wrench/actuator/requested/force")
    np.testing.assert_allclose(tip - tail, sol.requested * 0.005, atol=1e-12)
    tail, tip = arrow(rec, "wrench/actuator/inadmissible/force")
    np.testing.assert_allclose(tail, origin, atol=1e-12)
    np.testing.assert_allclose(tip - tail, sol.wrench * 0.005, atol=1e-12)
    assert color_of(rec, f"{ROOT}/wrench/actuator/inadmissible/force/shaft") == 0xE53935
    assert shown(rec, "wrench/actuator/inadmissible/force")
    # the same actuator asked for something it can do: the red arrow goes away
    rec.commands.clear()
    viewer.show(q, body.solve(q, np.array([5.0, 0.0, 120.0])), actuator=body)
    assert sent.visible(rec, f"{ROOT}/wrench/actuator/inadmissible/force") is False
    assert sent.visible(rec, f"{ROOT}/wrench/actuator/requested/force") is not False


def test_a_serial_actuator_draws_its_wrench_and_the_share_at_its_reaction():
    rob = robot("spring_flamingo")
    q = rob.neutral()
    swing = va.VirtualActuator(rob, "left_foot", "body", "world", ("x", "z"))
    rec = CommandRecorder()
    viewer = Viewer(rob, window=rec, force_scale=0.05)
    viewer.show(q, actuator=swing, wrench=np.array([2.0, -3.0]))
    data = placements(rob, q)
    tail, tip = arrow(rec, "wrench/actuator/requested/force")
    np.testing.assert_allclose(tail, frame_pose(rob, data, "left_foot").translation, atol=1e-12)
    np.testing.assert_allclose(tip - tail, [0.1, 0.0, -0.15], atol=1e-12)
    tail, tip = arrow(rec, "wrench/actuator/share/body/force")
    np.testing.assert_allclose(tail, frame_pose(rob, data, "body").translation, atol=1e-12)
    np.testing.assert_allclose(tip - tail, [0.1, 0.0, -0.15], atol=1e-12)


# -- controller output: components, efforts, support, state changes ---------------------------


@pytest.fixture(scope="module")
def turkey_control():
    rob = robot("spring_turkey")
    q = rob.neutral()
    axes = ("x", "z", "ry")
    feet = ["left_foot", "right_foot"]
    double = va.ParallelVirtualActuator(rob, "body", feet, "world", axes, contact="point")
    stance = va.ParallelVirtualActuator(rob, "body", ["left_foot"], "world", axes)
    swing = va.VirtualActuator(rob, "right_foot", "body", "world", ("x", "z"))
    granny = va.GrannyWalker(height=0.6, stiffness=(1500, 200), damping=(150, 20), weight=98.1)
    bunny = va.DogtrackBunny(speed=0.5, damping=80)
    linkage = va.SwingLegLinkage((400, 600), (20, 25), setpoint=(0.1, -0.4))
    controller = va.Controller(rob)
    controller.add("double", double, [granny, bunny])
    controller.add("stance", stance, [granny], free=("x",))
    controller.add("swing", swing, [linkage])
    bunny.reset(np.array([-0.2]), 0.0)  # the bunny 20 cm behind the world origin
    v = np.zeros(rob.model.nv)
    states = {
        "double_support": va.State("double_support", ("double",), tuple(feet)),
        "left_support": va.State("left_support", ("stance", "swing"), ("left_foot",)),
    }
    outputs = {name: controller.compute(q, v, 0.0, state.active) for name, state in states.items()}
    return SimpleNamespace(robot=rob, q=q, controller=controller, states=states, outputs=outputs)


def test_springs_dampers_and_set_points_between_their_frames(turkey_control):
    tc = turkey_control
    rec = CommandRecorder()
    viewer = Viewer(tc.robot, window=rec)
    viewer.show(
        tc.q, controller=tc.controller, output=tc.outputs["double_support"],
        state=tc.states["double_support"],
    )  # fmt: skip
    body = frame_pose(tc.robot, placements(tc.robot, tc.q), "body").translation
    # granny walker: a spring-damper from the ground below the body up to the body (z only)
    spring = sent.last_transform(rec, f"{ROOT}/components/double/0/spring")
    np.testing.assert_allclose(spring[:3, 1], [0.0, 0.0, body[2]], atol=1e-12)
    offset = spring[:3, 3] - (body + [body[0], body[1], 0.0]) / 2
    assert abs(offset[2]) < 1e-12 and np.linalg.norm(offset) > 0  # side by side with the damper
    marker = sent.last_transform(rec, f"{ROOT}/components/double/0/setpoint")
    np.testing.assert_allclose(marker[:3, 3], [body[0], body[1], 0.6], atol=1e-12)
    housing = sent.last_transform(rec, f"{ROOT}/components/double/0/damper/housing")
    rod = sent.last_transform(rec, f"{ROOT}/components/double/0/damper/rod")
    np.testing.assert_allclose(
        housing[:3, 3] + offset, [body[0], body[1], 0.3 * body[2]], atol=1e-12
    )
    np.testing.assert_allclose(rod[:3, 3] + rod[:3, 1] / 2 + offset, body, atol=1e-12)
    # dogtrack bunny (a damper only): from the bunny, 20 cm behind x = 0, to the body
    rod = sent.last_transform(rec, f"{ROOT}/components/double/1/damper/rod")
    housing = sent.last_transform(rec, f"{ROOT}/components/double/1/damper/housing")
    np.testing.assert_allclose(
        housing[:3, 3] - housing[:3, 1] / 2, [-0.2, body[1], body[2]], atol=1e-12
    )
    np.testing.assert_allclose(rod[:3, 3] + rod[:3, 1] / 2, body, atol=1e-12)
    assert not shown(rec, "components/double/1/spring")
    assert shown(rec, "support/left_foot") and shown(rec, "support/right_foot")
    assert shown(rec, "hud/state/double_support")


def test_a_state_change_hides_what_the_new_state_does_not_use(turkey_control):
    tc = turkey_control
    rec = CommandRecorder()
    viewer = Viewer(tc.robot, window=rec)
    for name in ("double_support", "left_support"):
        viewer.show(tc.q, controller=tc.controller, output=tc.outputs[name], state=tc.states[name])
    for hidden in (
        "wrench/double/requested/force",
        "wrench/double/share/left_foot/force",
        "components/double/0/spring",
        "frames/reaction/right_foot",
        "support/right_foot",
        "hud/state/double_support",
    ):
        assert sent.visible(rec, f"{ROOT}/{hidden}") is False, hidden
    for name in ("wrench/stance/requested/force", "components/swing/0/spring", "support/left_foot"):
        assert shown(rec, name), name
    assert shown(rec, "hud/state/left_support")
    # the stance leg's x is free: produced differs from the request, drawn in orange
    output = tc.outputs["left_support"]
    assert not np.allclose(output.produced["stance"], output.wrenches["stance"])
    assert shown(rec, "wrench/stance/produced/force")
    assert color_of(rec, f"{ROOT}/wrench/stance/produced/force/shaft") == 0xFB8C00
    body = frame_pose(tc.robot, placements(tc.robot, tc.q), "body").translation
    tail, tip = arrow(rec, "wrench/stance/produced/force")
    produced = output.produced["stance"]
    np.testing.assert_allclose(tail, body, atol=1e-12)
    np.testing.assert_allclose(
        tip - tail, np.array([produced[0], 0, produced[1]]) * 0.01, atol=1e-12
    )


def test_effort_gauges_show_saturation():
    rob = robot("hexapod")  # effort limits of 5 N m
    q = rob.neutral()
    feet = ["foot_1", "foot_3", "foot_5"]
    body = va.ParallelVirtualActuator(rob, "body", feet, "world")
    sol = body.solve(q, np.array([0.0, 40.0, 150.0, 0.0, 0.0, 0.0]))
    rec = CommandRecorder()
    viewer = Viewer(rob, window=rec)
    viewer.show(q, sol, actuator=body)
    radius = viewer.robot_scene.sizes["effort"]
    model = rob.model
    saturated = 0
    for j in range(2, model.njoints):  # after the free-flyer
        name, index = model.names[j], model.joints[j].idx_v
        tau, limit = sol.tau[index], model.effortLimit[index]
        over = abs(tau) > limit
        saturated += over
        assert shown(rec, f"efforts/{name}/saturated") == over, name
        if abs(tau) > 1e-9:
            sign = "positive" if tau > 0 else "negative"
            ball = sent.last_transform(rec, f"{ROOT}/efforts/{name}/{sign}/ball")
            assert ball[0, 0] == pytest.approx(radius * min(1.0, abs(tau) / limit), rel=1e-12)
            assert not shown(rec, f"efforts/{name}/{'negative' if tau > 0 else 'positive'}")
    assert 0 < saturated < 18  # some joints over the limit, others not
    # a controller's own saturation flags win over the limits
    flags = np.zeros(model.nv, dtype=bool)
    flags[model.joints[model.getJointId("knee_1")].idx_v] = True
    output = SimpleNamespace(
        tau=np.zeros(model.nv), saturated=flags, active=(), failed={}, wrenches={}
    )
    viewer.show(q, controller=SimpleNamespace(attachments={}), output=output)
    assert shown(rec, "efforts/knee_1/saturated")
    assert sent.visible(rec, f"{ROOT}/efforts/hip1_1/saturated") is False


def test_support_highlight_follows_the_frames():
    rob = robot("solo12")
    q = rob.neutral()
    rec = CommandRecorder()
    viewer = Viewer(rob, window=rec, legend=False)
    viewer.show(q, support=["FL_FOOT", "HR_FOOT"])
    data = placements(rob, q)
    for foot in ("FL_FOOT", "HR_FOOT"):
        matrix = sent.last_transform(rec, f"{ROOT}/support/{foot}")
        np.testing.assert_allclose(matrix[:3, 3], frame_pose(rob, data, foot).translation)
        assert shown(rec, f"support/{foot}")
    viewer.show(q, support=["FL_FOOT"])
    assert sent.visible(rec, f"{ROOT}/support/HR_FOOT") is False
    assert shown(rec, "support/FL_FOOT")


# -- robots without meshes -------------------------------------------------------------------


def test_urdf_primitives_are_drawn_with_their_colours():
    rob = robot("hexapod")
    rec = CommandRecorder()
    viewer = Viewer(rob, window=rec, legend=False)
    assert viewer.bodies.kind == "urdf"
    objects = {p: o for p, o in sent.objects(rec).items() if "/robot/visuals/" in p}
    kinds = sorted(o["geometries"][0]["type"] for o in objects.values())
    assert kinds.count("BoxGeometry") == 1
    assert kinds.count("SphereGeometry") == 12 and kinds.count("CylinderGeometry") == 12
    geometry = pin.buildGeomFromUrdfString(rob.model, rob.urdf_string, pin.GeometryType.VISUAL)
    data = placements(rob, rob.neutral())
    geometry_data = pin.GeometryData(geometry)
    pin.updateGeometryPlacements(rob.model, data, geometry, geometry_data)
    for k, geometry_object in enumerate(geometry.geometryObjects):
        path = f"{ROOT}/robot/visuals/{geometry_object.name}"
        np.testing.assert_allclose(
            sent.last_transform(rec, path), geometry_data.oMg[k].homogeneous, atol=1e-12
        )
        red, green, blue = (int(round(c * 255)) for c in geometry_object.meshColor[:3])
        urdf_color = (red << 16) | (green << 8) | blue
        drawn = objects[path]["materials"][0]["color"]
        # the URDF colour with its chroma limited: same lightness and hue
        urdf_lab, drawn_lab = to_lab(urdf_color), to_lab(drawn)
        assert abs(urdf_lab[0] - drawn_lab[0]) < 1.0
        assert chroma(drawn) <= ROBOT_MAX_CHROMA + 1.5
        if chroma(urdf_color) <= ROBOT_MAX_CHROMA:
            assert drawn == urdf_color
        else:
            cosine = urdf_lab[1:] @ drawn_lab[1:] / np.hypot(*urdf_lab[1:]) / chroma(drawn)
            assert cosine > 0.99


def test_a_urdf_without_visuals_gets_a_skeleton(tmp_path):
    source = (va.models.loader.robots_dir / "spring_flamingo" / "spring_flamingo.urdf").read_text()
    bare = re.sub(r"<visual>.*?</visual>", "", source, flags=re.S)
    assert "<visual" not in bare
    path = tmp_path / "bare_flamingo.urdf"
    path.write_text(bare)
    rob = va.load_robot(path)
    rec = CommandRecorder()
    viewer = Viewer(rob, window=rec, legend=False)
    assert viewer.bodies.kind == "skeleton"
    q = rob.neutral()
    q[rob.model.joints[rob.model.getJointId("left_knee")].idx_q] = 0.7
    viewer.show(q)
    data = placements(rob, q)
    model = rob.model
    for j in range(1, model.njoints):
        name = model.names[j]
        sphere = sent.last_transform(rec, f"{ROOT}/robot/skeleton/joint_{name}")
        np.testing.assert_allclose(sphere, data.oMi[j].homogeneous, atol=1e-12)
    link = sent.last_transform(rec, f"{ROOT}/robot/skeleton/link_left_ankle")  # knee to ankle
    np.testing.assert_allclose(
        link @ [0, -0.5, 0, 1],
        [*data.oMi[model.getJointId("left_knee")].translation, 1],
        atol=1e-12,
    )
    np.testing.assert_allclose(
        link @ [0, 0.5, 0, 1],
        [*data.oMi[model.getJointId("left_ankle")].translation, 1],
        atol=1e-12,
    )
    heel = sent.last_transform(rec, f"{ROOT}/robot/skeleton/tip_left_heel")
    np.testing.assert_allclose(
        heel[:3, 3], data.oMf[model.getFrameId("left_heel")].translation, atol=1e-12
    )


def test_skeleton_on_request_boxes_a_floating_base():
    rec = CommandRecorder()
    viewer = Viewer(robot("hexapod"), window=rec, geometry="skeleton", legend=False)
    objects = sent.objects(rec)
    assert f"{ROOT}/robot/skeleton/base" in objects
    assert objects[f"{ROOT}/robot/skeleton/base"]["geometries"][0]["type"] == "BoxGeometry"
    assert not any("/robot/visuals/" in p for p in objects)
    assert viewer.bodies.kind == "skeleton"


def test_terrain_slabs_follow_the_ground_profile():
    from virtual_actuators.simulation import Terrain

    terrain = Terrain([(0.0, 0.0), (2.0, 0.0), (3.0, 0.5), (4.0, 0.5)], width=1.5)
    rec = CommandRecorder()
    viewer = Viewer(robot("spring_turkey"), window=rec, legend=False)
    viewer.set_terrain(terrain, run=10.0)
    slabs = sorted(p for p in sent.objects(rec) if "/terrain/slab_" in p)
    segments = terrain.segments(10.0)
    assert len(slabs) == len(segments) == 5
    for path, ((x0, z0), (x1, z1)) in zip(slabs, segments, strict=True):
        box = sent.objects(rec)[path]["geometries"][0]
        matrix = sent.last_transform(rec, path)
        start, end = np.array([x0, 0.0, z0]), np.array([x1, 0.0, z1])
        assert box["width"] == pytest.approx(np.linalg.norm(end - start))
        assert box["height"] == pytest.approx(1.5)  # along y: the terrain's width
        top = matrix @ [0.0, 0.0, box["depth"] / 2, 1.0]
        normal = matrix[:3, 2]
        np.testing.assert_allclose(top[:3] + 1e-3 * normal, (start + end) / 2, atol=1e-12)
        np.testing.assert_allclose(matrix[:3, 0], (end - start) / np.linalg.norm(end - start))
    assert sent.visible(rec, f"{ROOT}/ground") is False  # the terrain replaces the grid


# -- recording -------------------------------------------------------------------------------


def decode_page(page: str) -> list[dict]:
    script = page.split("var commands = [", 1)[1].split("];", 1)[0]
    return [
        umsgpack.unpackb(base64.b64decode(b)) for b in re.findall(r'"([A-Za-z0-9+/=]+)"', script)
    ]


def test_recording_writes_a_standalone_animated_page(tmp_path):
    rob = robot("spring_turkey")
    window = OfflineWindow()
    viewer = Viewer(rob, window=window)
    q = rob.neutral()
    x_index = rob.model.joints[rob.model.getJointId("boom_x")].idx_q
    viewer.start_recording(fps=30)
    positions = []
    for k in range(12):
        q[x_index] = 0.05 * k
        state = "double_support" if k < 6 else "left_support"
        viewer.show(q, state=state, time=k / 30)
        positions.append(placements(rob, q).oMf[rob.model.getFrameId("body")].translation.copy())
    assert viewer.pacer.recording is not None and "12 frames" in repr(viewer)
    path = viewer.save_html(str(tmp_path / "run.html"))
    page = open(path, encoding="utf-8").read()
    assert "MeshCat.Viewer" in page and len(page) > 500_000  # the viewer bundle is inlined
    assert not re.search(r"<script[^>]*\bsrc\s*=", page)
    assert not re.search(r"<link[^>]*\bhref\s*=\s*[\"']https?:", page)
    assert not re.search(r"fetch\(\s*[\"']https?:", page)
    commands = decode_page(page)
    animations = [c for c in commands if c["type"] == "set_animation"]
    assert len(animations) == 1
    clips = {a["path"]: a["clip"] for a in animations[0]["animations"]}
    assert all(c["fps"] == 30 for c in clips.values())
    tracks = {t["name"]: t for t in clips[f"{ROOT}/robot/visuals/body_0"]["tracks"]}
    times = np.frombuffer(tracks[".position"]["times"].data, dtype=np.float32)
    np.testing.assert_allclose(times, np.arange(12), atol=1e-5)  # frames at 30 fps
    values = np.frombuffer(tracks[".position"]["values"].data, dtype=np.float32).reshape(-1, 3)
    body_visual = viewer.bodies.parts[0]
    offsets = values - np.array(positions)
    np.testing.assert_allclose(offsets, offsets[:1].repeat(12, axis=0), atol=1e-6)
    np.testing.assert_allclose(np.diff(values[:, 0]), 0.05, atol=1e-6)
    assert body_visual.name == "visuals/body_0"
    visible = {t["name"]: t for t in clips[f"{ROOT}/hud/state/left_support"]["tracks"]}[".visible"]
    assert visible["values"] == [False, True]
    np.testing.assert_allclose(np.frombuffer(visible["times"].data, np.float32), [0, 6])
    # the final scene is in the page too (objects and the last transforms)
    types = {c["type"] for c in commands}
    assert {"set_object", "set_transform", "set_property"} <= types


def test_throttled_updates_and_the_on_tick_adapter(turkey_control):
    tc = turkey_control
    rec = CommandRecorder()
    viewer = Viewer(tc.robot, window=rec, rate_hz=1e-3)  # one live update per 1000 s
    assert viewer.maybe_show(tc.q) is False  # the constructor's frame was the last update
    viewer.pacer.last_live = -np.inf
    assert viewer.maybe_show(tc.q) is True and viewer.maybe_show(tc.q) is False
    viewer.start_recording(fps=10)
    updater = viewer.tick_callback()
    gait = SimpleNamespace(
        controller=tc.controller,
        last=tc.outputs["double_support"],
        machine=SimpleNamespace(current=tc.states["double_support"]),
    )
    before = len(sent.transform_paths(rec))
    for tick in range(1000):  # 1 s of 1 kHz ticks: 10 recorded frames, no live update
        updater(SimpleNamespace(time=tick * 1e-3, q=tc.q, terrain=None), gait)
    assert updater.updates == 10 and viewer.pacer.recording.frames == 10
    np.testing.assert_allclose(viewer.pacer.recording.times, np.arange(10) * 0.1, atol=1e-12)
    assert len(sent.transform_paths(rec)) == before  # recorded frames are not sent live


def test_a_new_overlay_is_one_small_class(solo_view):
    from virtual_actuators.visualization import FrameSnapshot, Overlay, RobotScene

    class ActionMarker(Overlay):
        """A ball at the drawn actuator's action frame."""

        def draw(self, scene: RobotScene, frame: FrameSnapshot) -> None:
            if frame.actuator is not None:
                at = scene.data.oMf[scene.frame(frame.actuator.action, "action")].translation
                scene.marker("marker/ball", lambda: (mg.Sphere(0.02), None), at)

    rob, q, body, sol = solo_view.robot, solo_view.q, solo_view.body, solo_view.sol
    rec = CommandRecorder()
    viewer = Viewer(rob, window=rec, legend=False)
    overlay = viewer.add_overlay(ActionMarker())
    viewer.show(q, sol, actuator=body)
    ball = sent.last_transform(rec, f"{ROOT}/marker/ball")
    base = frame_pose(rob, placements(rob, q), "base_link").translation
    np.testing.assert_allclose(ball[:3, 3], base, atol=1e-12)
    assert shown(rec, "marker/ball") and "ActionMarker(" in repr(overlay)
    viewer.show(q)  # nothing to mark: hidden like every dynamic node not drawn
    assert sent.visible(rec, f"{ROOT}/marker/ball") is False
    with pytest.raises(va.InvalidInputError, match="Overlay"):
        viewer.add_overlay(object())


# -- command line ----------------------------------------------------------------------------


def test_command_line_records_an_example_and_a_walk(tmp_path, capsys):
    example = tmp_path / "hexapod.html"
    assert main(["example", "hexapod-tripod", "--record", str(example)]) == 0
    commands = decode_page(example.read_text(encoding="utf-8"))
    assert any("/wrench/actuator/share/foot_3/force" in c.get("path", "") for c in commands)
    walk = tmp_path / "walk.html"
    assert main(["demo", "turkey-walk", "--duration", "0.3", "--quiet", "--record", str(walk)]) == 0
    animation = [
        c for c in decode_page(walk.read_text(encoding="utf-8")) if c["type"] == "set_animation"
    ]
    assert animation and any("/robot/visuals/" in a["path"] for a in animation[0]["animations"])
    out = capsys.readouterr().out
    assert f"recording: {walk}" in out and f"recording: {example}" in out


# -- errors and representations --------------------------------------------------------------


def test_bad_inputs_raise_typed_errors_naming_the_argument(solo_view):
    viewer, q, body, sol = solo_view.viewer, solo_view.q, solo_view.body, solo_view.sol
    with pytest.raises(va.InvalidInputError, match="q has shape"):
        viewer.show(q[:-1])
    with pytest.raises(va.InvalidInputError, match="NaN"):
        viewer.show(np.full_like(q, np.nan))
    with pytest.raises(va.FrameNotFoundError, match="FL_FOOOT"):
        viewer.show(q, support=["FL_FOOOT"])
    with pytest.raises(va.InvalidInputError, match="actuator="):
        viewer.show(q, sol)
    with pytest.raises(va.InvalidInputError, match="controller= and output="):
        viewer.show(q, output=SimpleNamespace())
    other = va.ParallelVirtualActuator(solo_view.robot, "base_link", FEET[:2])
    with pytest.raises(va.InvalidInputError, match="not one of this actuator"):
        viewer.show(q, sol, actuator=other)
    with pytest.raises(va.InvalidInputError, match="wrench"):
        viewer.show(q, actuator=body, wrench=np.zeros(2))
    with pytest.raises(va.InvalidInputError, match="force_scale"):
        Viewer(solo_view.robot, window=CommandRecorder(), force_scale=0.0)
    with pytest.raises(va.InvalidInputError, match="geometry"):
        Viewer(solo_view.robot, window=CommandRecorder(), geometry="meshes")
    with pytest.raises(va.InvalidInputError, match="window must be None or a SceneWindow"):
        Viewer(solo_view.robot, window=object())
    with pytest.raises(va.InvalidInputError, match="Robot"):
        Viewer("solo12", window=CommandRecorder())
    with pytest.raises(va.InvalidInputError, match="fps"):
        viewer.start_recording(fps=-1)
    with pytest.raises(va.InvalidInputError, match="folder"):
        viewer.save_html("/no/such/folder/run.html")


def test_reprs_and_the_lazy_viz_module(solo_view):
    assert va.viz.Viewer is Viewer
    assert repr(solo_view.viewer).startswith("Viewer(robot='solo12'")
    assert "CommandRecorder(" in repr(solo_view.rec)
    assert "urdf" in repr(solo_view.viewer.bodies)
    assert "Scene(" in repr(solo_view.viewer.scene)
    assert "Palette(" in repr(solo_view.viewer.robot_scene.palette)
    colors, texts = zip(*solo_view.viewer.legend_entries(), strict=True)
    assert 0x1E88E5 in colors and any(" N" in text for text in texts)


# -- palette, legend, dashpots, framing, one-joint robots ------------------------------------


def test_lab_conversion_matches_published_values():
    # CIELAB (D65) of sRGB primaries and greys, from the CIE / sRGB reference tables
    for color, expected in (
        (0xFFFFFF, [100.0, 0.0, 0.0]), (0x000000, [0.0, 0.0, 0.0]),
        (0xFF0000, [53.24, 80.09, 67.20]), (0x00FF00, [87.73, -86.18, 83.18]),
        (0x0000FF, [32.30, 79.19, -107.86]), (0x808080, [53.59, 0.0, 0.0]),
    ):  # fmt: skip
        np.testing.assert_allclose(to_lab(color), expected, atol=0.05)


def test_palette_colours_are_distinguishable_and_far_from_robot_colours():
    colors = {name: getattr(PALETTE, name) for name in PALETTE.__dataclass_fields__}
    assert len(set(colors.values())) == len(colors)
    names = sorted(colors)
    for i, first in enumerate(names):
        assert chroma(colors[first]) >= OVERLAY_MIN_CHROMA, first
        for second in names[i + 1 :]:
            assert color_distance(colors[first], colors[second]) >= 25.0, (first, second)
    # the three former oranges (produced, spring, positive effort) are now far apart
    for a, b in (("produced", "spring"), ("produced", "effort_positive"),
                 ("spring", "effort_positive")):  # fmt: skip
        assert color_distance(colors[a], colors[b]) > 40.0


def robot_colors(rec: CommandRecorder) -> list[int]:
    """Colours of every object drawn for the robot (URDF visuals or skeleton)."""
    return [
        material["color"]
        for path, obj in sent.objects(rec).items()
        if f"{ROOT}/robot/" in path
        for material in obj.get("materials", [])
        if "color" in material
    ]


def test_robot_colours_never_come_close_to_overlay_colours():
    # hexapod and turkey: saturated URDF primitives; talos: STL meshes; ur5: Collada meshes
    for name in ("hexapod", "spring_turkey", "talos", "ur5"):
        rec = CommandRecorder()
        Viewer(robot(name), window=rec, legend=False)
        drawn = robot_colors(rec)
        assert drawn, name
        for color in set(drawn):
            assert chroma(color) <= ROBOT_MAX_CHROMA + 1.5, (name, hex(color))
            for key in PALETTE.__dataclass_fields__:
                assert color_distance(color, getattr(PALETTE, key)) > 25.0, (name, key)


def legend_keys(viewer: Viewer) -> set[str]:
    words = {
        "force:": "requested_force", "moment:": "requested_moment",
        "chain share": "share_force", "chain moment": "share_moment",
        "virtual spring": "spring", "virtual damper": "damper", "set point": "setpoint",
        "effort +": "effort_positive", "effort -": "effort_negative",
        "saturated": "saturated", "support": "support", "frames:": "frames",
        "no limit": "no_limit", "(adjusted)": "produced", "(inadmissible)": "inadmissible",
    }  # fmt: skip
    text = "\n".join(text for _, text in viewer.legend_entries())
    return {key for word, key in words.items() if word in text}


def test_the_legend_lists_only_what_is_drawn(turkey_control):
    rob, q = rotated_solo12()
    viewer = Viewer(rob, window=CommandRecorder())
    assert viewer.legend_entries() == []  # nothing drawn over the robot yet
    body = va.VirtualActuator(rob, "base_link", "FL_FOOT", "world", ("z",))
    viewer.show(q, actuator=body, wrench=np.array([20.0]))
    assert legend_keys(viewer) == {"requested_force", "share_force", "frames"}
    scene_lines = [p for p in sent.objects(viewer.window) if "/hud/legend/line_" in p]
    assert len(scene_lines) == 2 * 3  # the legend in the scene has the same lines (two faces)
    tc = turkey_control
    viewer = Viewer(tc.robot, window=CommandRecorder())
    viewer.show(
        tc.q, controller=tc.controller, output=tc.outputs["double_support"],
        state=tc.states["double_support"],
    )  # fmt: skip
    keys = legend_keys(viewer)
    assert {"spring", "damper", "setpoint", "support", "frames", "requested_force"} <= keys
    assert "inadmissible" not in keys and "produced" not in keys
    signs = np.sign(tc.outputs["double_support"].tau[np.abs(tc.outputs["double_support"].tau) > 0])
    assert ("effort_positive" in keys) == bool(np.any(signs > 0))
    assert ("effort_negative" in keys) == bool(np.any(signs < 0))


def test_dampers_are_dashpots_distinct_from_springs_and_legs(turkey_control):
    tc = turkey_control
    rec = CommandRecorder()
    viewer = Viewer(tc.robot, window=rec)
    viewer.show(tc.q, controller=tc.controller, output=tc.outputs["double_support"])
    damper = f"{ROOT}/components/double/1/damper"
    names = ("housing", "cap", "piston")
    parts = {name: sent.last_transform(rec, f"{damper}/{name}") for name in names}
    parts["rod"] = sent.last_transform(rec, f"{damper}/rod")
    radius = {
        name: sent.objects(rec)[f"{damper}/{name}"]["geometries"][0]["radiusTop"] for name in parts
    }
    assert radius["rod"] < radius["piston"] < radius["housing"] == radius["cap"]
    housing = sent.objects(rec)[f"{damper}/housing"]["materials"][0]
    assert housing["opacity"] < 1.0 and housing["transparent"]  # the piston shows through
    # the piston sits inside the housing, on the rod, between the cap and the open end
    axis = parts["housing"][:3, 1] / np.linalg.norm(parts["housing"][:3, 1])
    start = parts["housing"][:3, 3] - parts["housing"][:3, 1] / 2
    along = {name: (m[:3, 3] - start) @ axis for name, m in parts.items()}
    length = np.linalg.norm(parts["housing"][:3, 1])
    assert 0 < along["cap"] < along["piston"] < length
    rod_start = parts["rod"][:3, 3] - parts["rod"][:3, 1] / 2
    np.testing.assert_allclose((rod_start - start) @ axis, along["piston"] * 0 + 0.75 * length)
    assert not any("damper" in p for p in sent.objects(rec) if "/robot/" in p)


def test_a_robot_with_a_single_joint_is_drawn_with_its_effort_gauge(tmp_path):
    urdf = tmp_path / "pendulum.urdf"
    urdf.write_text(
        '<robot name="pendulum"><link name="base"/>'
        '<link name="arm"><inertial><origin xyz="0 0 -0.25"/><mass value="1"/>'
        '<inertia ixx="0.02" iyy="0.02" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial></link>'
        '<link name="tip"/><joint name="hinge" type="revolute"><parent link="base"/>'
        '<child link="arm"/><axis xyz="0 1 0"/>'
        '<limit lower="-3" upper="3" effort="5" velocity="10"/></joint>'
        '<joint name="tip_joint" type="fixed"><parent link="arm"/><child link="tip"/>'
        '<origin xyz="0 0 -0.5"/></joint></robot>',
        encoding="utf-8",
    )
    rob = va.load_robot(urdf)
    assert rob.model.nv == 1
    rec = CommandRecorder()
    viewer = Viewer(rob, window=rec)
    assert viewer.robot_scene.planar  # a hinge about y moves in the x-z plane
    tip = va.VirtualActuator(rob, "tip", "base", "world", ("x",))
    controller = va.Controller(rob)
    controller.add("tip", tip, [va.Spring(("x",), 40.0, setpoint=0.1)])
    q, v = np.array([0.2]), np.zeros(1)
    output = controller.compute(q, v, 0.0, ["tip"])
    viewer.show(q, controller=controller, output=output)
    assert shown(rec, "efforts/hinge") and shown(rec, "components/tip/0/spring")
    sign = "positive" if output.tau[0] > 0 else "negative"
    assert shown(rec, f"efforts/hinge/{sign}")


def camera_and_offset(commands: list[dict]) -> tuple[np.ndarray, np.ndarray]:
    """The page's last camera position (world axes) and the offset of ``/meshcat``."""
    camera = [c for c in commands if c["type"] == "set_property" and c["property"] == "position"]
    local = np.array(camera[-1]["value"], dtype=float)
    shift = [c for c in commands if c["type"] == "set_transform" and c["path"] == "/meshcat"]
    matrix = np.array(shift[-1]["matrix"], dtype=float).reshape(4, 4).T  # column-major
    return np.array([local[0], -local[2], local[1]]), matrix[:3, 3]


@pytest.mark.slow
def test_a_recorded_walk_is_framed_on_the_robot_over_its_whole_run(tmp_path):
    from virtual_actuators.demos import WALKS, run_walk

    rob = va.load_robot(WALKS["flamingo-slopes"].robot)
    viewer = Viewer(rob, window=OfflineWindow(), force_scale=1 / 250)
    viewer.start_recording(fps=30.0)
    bodies: list[np.ndarray] = []
    updater = viewer.tick_callback()

    def on_tick(simulator, gait):  # the viewer's own callback, then what it left visible
        recorded = viewer.pacer.recording.frames
        updater(simulator, gait)
        if viewer.pacer.recording.frames != recorded:
            root = viewer.scene.matrices[""]  # the view's shift of the robot's node
            parts = [m for n, m in viewer.scene.matrices.items() if n.startswith("robot/")]
            bodies.append(np.array([(root @ m)[:3, 3] for m in parts]))

    run_walk("flamingo-slopes", duration=1.5, progress=False, on_tick=on_tick)
    page = open(viewer.save_html(str(tmp_path / "walk.html")), encoding="utf-8").read()
    camera, offset = camera_and_offset(decode_page(page))
    every = np.vstack(bodies) + offset  # what the page shows, in the camera's world
    assert len(bodies) > 30  # 1.5 s at 30 fps
    # every body of every frame lies inside the view cone (vertical half-angle 37.5 deg)
    to_target = -camera / np.linalg.norm(camera)
    rays = every - camera
    cosines = rays @ to_target / np.linalg.norm(rays, axis=1)
    assert np.all(cosines > np.cos(np.radians(37.5)))
    # and the robot fills the view: the farthest body is beyond half the half-angle
    assert np.min(cosines) < np.cos(np.radians(37.5 / 2))
    # the camera looks at the robot: the box of its bodies over the run is centred in the view
    # (the world frame left behind at x = 0 pulled the view off the robot, 0.19 m of 1 m here)
    span = float(np.linalg.norm(every.max(axis=0) - every.min(axis=0)))
    centre = (every.min(axis=0) + every.max(axis=0)) / 2
    assert np.linalg.norm(centre - (centre @ to_target) * to_target) < 0.02 * span


def test_a_velocity_damper_is_drawn_on_the_body_wherever_it_walked():
    # the hexapod's heading damper (x, y; no spring, no set point) far from the world origin
    rob = robot("hexapod")
    q = rob.neutral()
    q[:2] = [3.0, -2.0]
    feet = ["foot_1", "foot_3", "foot_5"]
    body = va.ParallelVirtualActuator(rob, "body", feet, "world", contact="point")
    damper = HeadingDamper((40.0, 60.0), name="planar")
    controller = va.Controller(rob)
    controller.add("planar", body, [damper])
    output = controller.compute(q, np.zeros(rob.model.nv), 0.0, ("planar",))
    rec = CommandRecorder()
    viewer = Viewer(rob, window=rec)
    viewer.show(q, controller=controller, output=output)
    action = frame_pose(rob, placements(rob, q), "body").translation
    housing = sent.last_transform(rec, f"{ROOT}/components/planar/0/damper/housing")
    rod = sent.last_transform(rec, f"{ROOT}/components/planar/0/damper/rod")
    start = housing[:3, 3] - housing[:3, 1] / 2  # the housing's closed end
    np.testing.assert_allclose(rod[:3, 3] + rod[:3, 1] / 2, action, atol=1e-12)
    extent = viewer.robot_scene.extent
    assert np.linalg.norm(start - action) <= extent  # on the robot, not 3.6 m away
    assert abs(start[2] - action[2]) < 1e-12  # along the damper's x axis


def page_pose(commands: list[dict], path: str) -> np.ndarray:
    """World matrix of ``path`` in a page: the last transform of each node along it, composed."""
    last = {
        c["path"]: np.array(c["matrix"], dtype=float).reshape(4, 4).T  # column-major
        for c in commands
        if c["type"] == "set_transform"
    }
    matrix, prefix = np.eye(4), ""
    for part in path.strip("/").split("/"):
        prefix += "/" + part
        matrix = matrix @ last.get(prefix, np.eye(4))
    return matrix


@pytest.mark.parametrize(
    ("name", "recorded"), [("spring_turkey", True), ("spring_turkey", False), ("hexapod", False)]
)
def test_the_state_name_faces_the_camera_and_reads_left_to_right(name, recorded):
    rob = robot(name)
    viewer = Viewer(rob, window=OfflineWindow())
    q = rob.neutral()
    if recorded:  # a walk: the view follows the robot and the page is framed on the run
        viewer.start_recording(fps=30)
        for k in range(10):
            q[0] = 0.05 * k
            viewer.show(q, state="right_support", time=k / 30)
    else:
        viewer.show(q, state="right_support")
    commands = decode_page(viewer.static_html())
    position = [c for c in commands if c["type"] == "set_property" and c["property"] == "position"]
    local = np.array(position[-1]["value"], dtype=float)  # three.js is y-up
    camera = np.array([local[0], -local[2], local[1]])  # looking at the origin (orbit controls)
    label = page_pose(commands, f"{ROOT}/hud/state/right_support")
    normal, across, up = label[:3, 2], label[:3, 0], label[:3, 1]  # text drawn on +z, along +x
    to_camera = camera - label[:3, 3]
    right = np.cross(-camera, [0.0, 0.0, 1.0])  # the camera's right on the screen
    assert normal @ to_camera > 0.9 * np.linalg.norm(to_camera) * np.linalg.norm(normal)
    assert across @ right > 0.9 * np.linalg.norm(right) * np.linalg.norm(across)  # not mirrored
    assert up[2] > 0.9 * np.linalg.norm(up)  # upright


def face_poses(commands: list[dict], path: str) -> dict[str, tuple[np.ndarray, int]]:
    """World matrix and three.js ``side`` of each text face under ``path`` in a page."""
    faces = {}
    for command in commands:
        if command["type"] != "set_object" or not command["path"].startswith(path + "/"):
            continue
        obj = command["object"]
        inner = np.array(obj["object"]["matrix"], dtype=float).reshape(4, 4).T  # column-major
        side = obj["materials"][0]["side"]
        world = page_pose(commands, command["path"]) @ inner
        faces[command["path"].rsplit("/", 1)[1]] = (world, side)
    return faces


@pytest.mark.parametrize("name", ["spring_turkey", "hexapod"])
def test_text_reads_left_to_right_from_any_side(name):
    # a user orbiting a live viewer sees the labels from behind too: a double-sided plane would
    # show the text mirrored there; two single-sided faces back to back read correctly from both
    rob = robot(name)
    viewer = Viewer(rob, window=OfflineWindow())
    viewer.show(rob.neutral(), state="right_support")
    commands = decode_page(viewer.static_html())
    for label in (f"{ROOT}/hud/state/right_support",):  # the legend's lines are made alike
        faces = face_poses(commands, label)
        assert sorted(faces) == ["back", "front"], label
        assert all(side == 0 for _, side in faces.values())  # FrontSide: invisible from behind
        for direction in ([0.0, -1.0, 0.2], [0.0, 1.0, 0.2], [1.0, 0.3, 0.5], [-1.0, -0.4, 0.3]):
            camera = 10.0 * np.array(direction)
            right = np.cross(-camera, [0.0, 0.0, 1.0])  # the camera's right on the screen
            seen = []
            for pose, _ in faces.values():
                normal, across, up = pose[:3, 2], pose[:3, 0], pose[:3, 1]
                if normal @ (camera - pose[:3, 3]) > 0:  # this face is towards the camera
                    seen.append(pose)
                    assert across @ right > 0, (label, direction)  # not mirrored
                    assert up[2] > 0.9 * np.linalg.norm(up)  # upright
            assert len(seen) == 1, (label, direction)  # exactly one face shows
