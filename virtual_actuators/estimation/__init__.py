"""The base state of a legged robot estimated from what it measures (IMU, encoders, efforts)."""

from .estimate import Estimate
from .reading import SensorReading

__all__ = ["Estimate", "SensorReading"]
