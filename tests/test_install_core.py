"""The core install: torques need only Pinocchio, example-robot-data, numpy and proxsuite.

``pip install .`` installs the core (and builds the compiled core); the viewer, MuJoCo, plots and
yourdfpy come with extras. Here: the declared dependencies, a solve that imports none of the
optional packages (checked in a fresh interpreter's ``sys.modules``), the same solve with the
optional packages made unimportable (as in a core-only environment), and the
typed error naming the extra to install when an optional feature is used without its package.
The solve is checked against force balance (the feet's forces and moments add up to the
requested wrench), not against itself.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
OPTIONAL = ("mujoco", "meshcat", "matplotlib", "yourdfpy", "trimesh", "tqdm")
#: Not needed by a solve either: made unimportable too. (proxsuite declares scipy as a
#: dependency, so the core install has it: it is not checked in sys.modules.)
NOT_IN_CORE = (*OPTIONAL, "scipy", "shapely")

#: Solve with solo12 (point feet, then the QP with friction), check force balance (the chains'
#: shares, moments about the base, add up to the wrench; a point foot's moment is r x f), report
#: the optional packages that got imported. Runs in a fresh interpreter (also in a core-only venv).
CORE_SCRIPT = r"""
import sys
import numpy as np
import pinocchio as pin
import virtual_actuators as va

robot = va.load_robot("solo12")
feet = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
q = robot.neutral()
wrench = np.array([3.0, -2.0, 24.5, 0.2, 0.1, -0.3])  # [N, N m] on the base, world axes
for kwargs in ({}, {"friction": 0.8}):
    body = va.ParallelVirtualActuator(robot, "base_link", feet, "world", **kwargs)
    solution = body.solve(q, wrench)
    assert solution.admissible, kwargs
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, q)
    base = data.oMf[robot.model.getFrameId("base_link")].translation
    scale = np.abs(wrench).max()
    for foot, share in zip(feet, solution.forces, strict=True):  # moments about the base
        at = data.oMf[robot.model.getFrameId(foot)].translation
        moment = np.cross(at - base, share[:3])  # a point foot transmits a force only
        assert np.allclose(share[3:], moment, rtol=0, atol=1e-9 * scale), (kwargs, foot)
    total = solution.forces.sum(axis=0)
    assert np.allclose(total, wrench, rtol=0, atol=1e-9 * scale), (kwargs, total)
    assert np.all(np.isfinite(solution.tau)) and solution.tau.shape == (robot.model.nv,)
OPTIONAL = __OPTIONAL__
print("IMPORTED", sorted({m.split(".")[0] for m in sys.modules} & set(OPTIONAL)))
from virtual_actuators.core import CORE
print("CORE", CORE is not None)
""".replace("__OPTIONAL__", repr(OPTIONAL))

#: Make packages unimportable, as if they were not installed (run before the script).
BLOCKER = r"""
import importlib.abc, sys
BLOCKED = __BLOCKED__
class _NotInstalled(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in BLOCKED:
            raise ModuleNotFoundError(f"No module named {name!r}", name=name)
sys.meta_path.insert(0, _NotInstalled())
"""


def run(code: str) -> str:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=ROOT,
        timeout=300,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr[-3000:]
    return result.stdout


def test_the_core_dependencies_are_the_torque_stack_and_extras_bring_the_rest():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    core = {spec.split(">")[0].split("[")[0] for spec in project["dependencies"]}
    assert core == {"pin", "example-robot-data", "numpy", "proxsuite"}
    extras = project["optional-dependencies"]
    names = {key: {s.split(">")[0].split("[")[0] for s in value} for key, value in extras.items()}
    assert "meshcat" in names["viz"] and "mujoco" in names["sim"]
    assert "matplotlib" in names["plots"] and "yourdfpy" in names["urdf"]
    assert {"pytest", "hypothesis", "ruff"} <= names["dev"]
    assert "reference" not in names  # one implementation per kernel: no numba
    assert "mkdocs-material" in names["docs"]
    everything = extras["all"][0]
    assert everything.startswith("virtual_actuators[")
    assert set(everything[len("virtual_actuators[") : -1].split(",")) >= {
        "viz", "sim", "urdf"}


@pytest.mark.slow
def test_a_solve_imports_no_optional_package():
    out = run(CORE_SCRIPT)
    assert "IMPORTED []" in out, out


@pytest.mark.slow
def test_the_core_works_without_the_optional_packages(tmp_path):
    urdf = tmp_path / "arm.urdf"  # a path: validated without yourdfpy
    urdf.write_text(
        '<robot name="arm"><link name="base"/><link name="upper"><inertial><mass value="1"/>'
        '<inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>'
        '<joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>'
        '<axis xyz="0 one 0"/><limit lower="-1" upper="1" effort="5" velocity="5"/></joint>'
        "</robot>",
        encoding="utf-8",
    )
    check = f"""
import virtual_actuators as va
import pytest
with pytest.raises(va.RobotDescriptionError, match="'one' is not a number"):
    va.load_robot({str(urdf)!r})
fixed = {str(urdf)!r}.replace("arm.urdf", "fixed.urdf")
open(fixed, "w").write(open({str(urdf)!r}).read().replace("0 one 0", "0 1 0"))
assert va.load_robot(fixed).model.nv == 1
for attempt in (lambda: va.viz, lambda: __import__("virtual_actuators.visualization")):
    with pytest.raises(va.MissingDependencyError) as error:
        attempt()
    assert isinstance(error.value, ImportError) and error.value.extra == "viz"
    assert "extra [viz]" in str(error.value) and '[viz]" ' in str(error.value), error.value
    assert error.value.package == "meshcat"
print("FALLBACKS OK")
"""
    out = run(BLOCKER.replace("__BLOCKED__", repr(NOT_IN_CORE)) + CORE_SCRIPT + check)
    assert "IMPORTED []" in out and "FALLBACKS OK" in out, out
