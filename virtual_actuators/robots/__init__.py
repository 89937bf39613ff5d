"""Robots: load any URDF or a known robot by name, or generate a millipede."""

from virtual_actuators.robots.catalog import list_robots, robots_dir
from virtual_actuators.robots.loader import load_robot
from virtual_actuators.robots.millipede import millipede
from virtual_actuators.robots.robot import Robot

__all__ = ["Robot", "list_robots", "load_robot", "millipede", "robots_dir"]
