"""Robots: load any URDF or a known robot by name, or generate a millipede."""

from virtual_actuators.models.catalog import list_robots, robots_dir
from virtual_actuators.models.loader import load_robot
from virtual_actuators.models.millipede import millipede
from virtual_actuators.models.robot import Robot

__all__ = ["Robot", "list_robots", "load_robot", "millipede", "robots_dir"]
