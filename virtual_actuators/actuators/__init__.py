"""Virtual actuators: serial (a wrench between two frames), parallel (over several chains)."""

from .parallel import ParallelVirtualActuator
from .serial import ActuatorReading, VirtualActuator

__all__ = ["ParallelVirtualActuator", "ActuatorReading", "VirtualActuator"]
