"""``Robot.center_of_mass`` against MuJoCo's centre of mass; ``Snapshot.center_of_mass`` against
Pinocchio's."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from oracles import random_configuration, requires_core

import virtual_actuators as va
from virtual_actuators.simulation import Simulator


@pytest.mark.parametrize("name", ["solo12", "talos", "g1"])
def test_center_of_mass_matches_mujoco(name):
    robot = va.load_robot(name)
    simulator = Simulator(robot, collisions="none")
    rng = np.random.default_rng(7)
    for _ in range(3):
        q = random_configuration(robot, rng, scale=0.6)
        simulator.reset(q)
        mujoco_com = simulator.data.subtree_com[0]  # the world body's subtree: the whole robot
        assert np.allclose(robot.center_of_mass(q), mujoco_com, atol=1e-9)


def test_center_of_mass_follows_the_base():
    robot = va.load_robot("solo12")
    q = robot.neutral()
    moved = q.copy()
    moved[:3] += (0.3, -0.2, 0.5)
    assert np.allclose(robot.center_of_mass(moved) - robot.center_of_mass(q), (0.3, -0.2, 0.5))


def test_center_of_mass_bad_configuration():
    robot = va.load_robot("solo12")
    with pytest.raises(va.InvalidInputError, match="19 finite numbers"):
        robot.center_of_mass(np.zeros(5))
    q = robot.neutral()
    q[8] = np.nan
    with pytest.raises(va.InvalidInputError, match="finite"):
        robot.center_of_mass(q)


@pytest.mark.parametrize("name", ["solo12", "go2", "talos", "g1"])
@pytest.mark.parametrize("backend", [pytest.param("compiled", marks=requires_core), "pinocchio"])
def test_snapshot_center_of_mass_matches_pinocchio(name, backend):
    """The tick's reading (from the snapshot's joint placements) is Pinocchio's centerOfMass."""
    robot = va.load_robot(name)
    data = pin.Data(robot.model)
    rng = np.random.default_rng(11)
    for _ in range(5):
        q = random_configuration(robot, rng, scale=0.8)
        q[:3] += rng.uniform(-2.0, 2.0, 3)  # away from the origin: the base's position counts
        snapshot = va.Snapshot(robot, q, backend=backend)
        expected = pin.centerOfMass(robot.model, data, snapshot.q, False)
        assert np.abs(snapshot.center_of_mass() - expected).max() <= 1e-12
