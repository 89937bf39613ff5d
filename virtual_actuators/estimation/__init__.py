"""The base state of a legged robot estimated from what it measures (IMU, encoders, efforts)."""

from .estimate import Estimate
from .legged import LeggedEstimator
from .reading import SensorReading
from .tuning import EstimatorTuning

__all__ = ["Estimate", "EstimatorTuning", "LeggedEstimator", "SensorReading"]
