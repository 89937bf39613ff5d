"""The viewer draws every robot that loads by name, with a controller's output over it.

Each robot gets a serial virtual actuator from the body of its last joint to its base (or the
world), with a spring-damper on x, y and z, computed by a real :class:`va.Controller`; the frame
is drawn into a :class:`CommandRecorder` (no server, no browser). Checked: nothing raises, every
actuated one-dof joint gets its effort gauge, the spring and the dashpot are drawn, and no
colour of the robot comes close to an overlay colour.
"""

from __future__ import annotations

import warnings

import numpy as np
import pinocchio as pin
import pytest
import scene_commands as sent
from lab_colors import color_distance

import virtual_actuators as va
from virtual_actuators.visualization import PALETTE, CommandRecorder, Viewer

ROOT = "/meshcat/virtual_actuators"
NAMES = va.list_robots()


def tip_and_base(robot: va.Robot) -> tuple[str, str]:
    """The body frame of the last joint, and the base's body frame (or the world)."""
    model = robot.model
    bodies = [f for f in model.frames if f.type == pin.FrameType.BODY]
    tip = max(bodies, key=lambda f: (f.parentJoint, -len(f.name))).name
    if not robot.floating_base:
        return tip, "world"
    base = next(f.name for f in bodies if f.parentJoint == 1)
    return tip, "world" if base == tip else base  # a rigid body alone (a quadrotor)


@pytest.mark.slow
@pytest.mark.parametrize("name", NAMES)
def test_the_viewer_draws_every_robot(name):
    robot = va.load_robot(name)
    tip, base = tip_and_base(robot)
    controller = va.Controller(robot)
    actuator = va.VirtualActuator(robot, tip, base, "world", ("x", "y", "z"))
    component = va.SpringDamper(("x", "y", "z"), stiffness=50.0, damping=5.0, setpoint=0.05)
    controller.add("tip", actuator, [component])
    q = robot.neutral()
    v = np.full(robot.model.nv, 0.1)
    output = controller.compute(q, v, 0.0, ["tip"])
    rec = CommandRecorder()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # a missing mesh: a skeleton instead
        viewer = Viewer(robot, window=rec)
    viewer.show(q, controller=controller, output=output)

    gauges = {joint for joint, *_ in viewer.robot_scene.effort_joints}
    model = robot.model
    one_dof = {model.names[j] for j in range(1, model.njoints) if model.joints[j].nv == 1} - set(
        robot.passive_joints
    )
    assert gauges == one_dof
    for joint in gauges:
        assert shown(rec, f"efforts/{joint.replace('/', '_')}/shell"), joint
    data = viewer.robot_scene.data
    span = data.oMf[model.getFrameId(tip)].translation - (
        np.zeros(3) if base == "world" else data.oMf[model.getFrameId(base)].translation
    )
    if np.linalg.norm(output.wrenches["tip"]) > 1e-9 and np.linalg.norm(span) > 1e-9:
        assert shown(rec, "components/tip/0/spring")
        assert shown(rec, "components/tip/0/damper/piston")
    colors = {
        material["color"]
        for path, obj in sent.objects(rec).items()
        if f"{ROOT}/robot/" in path
        for material in obj.get("materials", [])
    }
    assert colors
    for color in colors:
        for key in PALETTE.__dataclass_fields__:
            assert color_distance(color, getattr(PALETTE, key)) > 25.0, (hex(color), key)


def shown(rec: CommandRecorder, name: str) -> bool:
    """Whether a node has objects and is visible (objects start visible until hidden)."""
    path = f"{ROOT}/{name}"
    created = any(p == path or p.startswith(path + "/") for p in sent.objects(rec))
    return created and sent.visible(rec, path) is not False
