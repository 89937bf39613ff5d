"""Every collision element of a URDF becomes a MuJoCo geom: Collada meshes too (issue 35).

hyq's trunk and hip assemblies are Collada (``.dae``) meshes, which MuJoCo does not read: they
were left out, so its trunk could never touch the floor and the fall test could not see it. The
project's Collada reader (the viewer's) now hands them to MuJoCo; a mesh that nothing reads is
simulated as its bounding box, said in one line that quotes no source.
"""

from __future__ import annotations

import os
import subprocess
import sys
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import numpy as np

import virtual_actuators as va
from virtual_actuators.gaits.runner import foot_geoms
from virtual_actuators.simulation import Simulator
from virtual_actuators.simulation.model import build_mujoco_model

ROOT = Path(__file__).resolve().parents[1]


def collision_elements(urdf: Path) -> list[str]:
    """``link:geometry kind`` of every ``<collision>`` of a URDF (read here, not by Pinocchio)."""
    return [
        f"{link.get('name')}:{next(iter(collision.find('geometry'))).tag}"
        for link in ElementTree.parse(urdf).getroot().iter("link")
        for collision in link.findall("collision")
    ]


def test_hyq_has_a_collision_geom_for_every_collision_element():
    robot = va.load_robot("hyq")
    elements = collision_elements(robot.urdf_path)
    assert len(elements) == 17 and sum(e.endswith(":mesh") for e in elements) == 9
    mm = build_mujoco_model(robot)
    assert len(mm.geom_frames) == len(elements)  # was 8: the 9 .dae meshes were left out
    assert not mm.skipped_geometries and not mm.approximated_geometries
    owners = [frames[0] for frames in mm.geom_frames.values()]
    assert sorted(owners) == sorted(e.split(":")[0] for e in elements)


def test_hyqs_trunk_touches_the_floor_and_counts_as_a_fall():
    robot = va.load_robot("hyq")
    simulator = Simulator(robot)
    q = robot.neutral()
    q[3:7] = (1.0, 0.0, 0.0, 0.0)  # upside down: the trunk's top is its lowest part
    q = simulator.on_ground(q)
    q[2] -= 0.002  # [m] into the floor: in contact
    simulator.reset(q)
    assert "trunk" in simulator.touching_terrain()
    assert simulator.touches_outside(foot_geoms(simulator))  # the fall test sees it
    lowest = float(simulator.q[2])
    for _ in range(300):  # 0.3 s without torques: it rests on its trunk, not through the floor
        simulator.step(np.zeros(robot.model.nv), ignore_unactuated=True)
    assert "trunk" in simulator.touching_terrain()
    assert abs(float(simulator.q[2]) - lowest) < 0.02


def test_a_mesh_nothing_reads_is_a_box_told_in_one_line(tmp_path):
    """An ASCII STL (MuJoCo reads binary STL only) becomes its bounding box, and the notice is
    one line on stderr: no file name, line number or quoted source of a Python warning."""
    (tmp_path / "box.stl").write_text(
        "solid t\n"
        + "".join(
            f"facet normal 0 0 0\nouter loop\n{corners}endloop\nendfacet\n"
            for corners in (
                "vertex 0 0 0\nvertex 0.2 0 0\nvertex 0 0.1 0\n",
                "vertex 0 0 0\nvertex 0 0 0.3\nvertex 0.2 0 0\n",
                "vertex 0 0 0\nvertex 0 0.1 0\nvertex 0 0 0.3\n",
                "vertex 0.2 0 0\nvertex 0 0 0.3\nvertex 0 0.1 0\n",
            )
        )
        + "endsolid t\n"
    )
    (tmp_path / "boxy.urdf").write_text(
        '<robot name="boxy"><link name="base"><inertial><mass value="1"/><inertia ixx="0.01" '
        'iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial><collision><geometry><mesh '
        f'filename="{tmp_path / "box.stl"}"/></geometry></collision></link></robot>'
    )
    urdf = str(tmp_path / "boxy.urdf")
    script = (
        "import virtual_actuators as va\n"
        "from virtual_actuators.simulation.model import build_mujoco_model\n"
        f"mm = build_mujoco_model(va.load_robot({urdf!r}, floating_base=True))\n"
        "geom = next(iter(mm.geom_frames))\n"
        "print(mm.approximated_geometries, mm.model.geom_size[geom].round(6).tolist())\n"
    )
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    run = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=120, env=env
    )
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "('base_0',) [0.1, 0.05, 0.15]"
    assert run.stderr.splitlines() == [
        "Robot 'boxy': simulated as bounding boxes, the meshes that neither MuJoCo (OBJ, "
        "binary STL) nor the Collada reader reads (1): base_0"
    ]
