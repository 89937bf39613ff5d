"""MuJoCo simulation of any loaded robot, on flat or sloped terrain."""

from ..exceptions import import_optional

import_optional("mujoco", "sim", "MuJoCo simulation (virtual_actuators.simulation)")

from .conversions import (  # noqa: E402
    configuration_from_mujoco,
    configuration_to_mujoco,
    torques_to_ctrl,
    velocity_from_mujoco,
    velocity_to_mujoco,
)
from .model import ContactParameters, JointMap, MujocoModel, build_mujoco_model  # noqa: E402
from .sensors import SensorModel  # noqa: E402
from .simulator import MujocoHardware, Simulator  # noqa: E402
from .terrain import Terrain  # noqa: E402

__all__ = [
    "ContactParameters",
    "JointMap",
    "MujocoHardware",
    "MujocoModel",
    "SensorModel",
    "Simulator",
    "Terrain",
    "build_mujoco_model",
    "configuration_from_mujoco",
    "configuration_to_mujoco",
    "torques_to_ctrl",
    "velocity_from_mujoco",
    "velocity_to_mujoco",
]
