"""Runnable demos: the seeds' walking robots in MuJoCo (``python -m virtual_actuators demo``)."""

from ..gaits.runner import WALKS, WalkResult, WalkSpec, run_walk

__all__ = ["WALKS", "WalkResult", "WalkSpec", "run_walk"]
