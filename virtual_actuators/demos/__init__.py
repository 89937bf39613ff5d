"""Runnable demos: the walks in MuJoCo (``python -m virtual_actuators demo``) and their sweeps.

The walks themselves are registered by the gaits (:mod:`virtual_actuators.gaits.registry`);
``WalkSpec`` is the former name of :class:`~virtual_actuators.gaits.base.Walk`.
"""

from ..gaits.base import Walk
from ..gaits.registry import WALKS, run_walk
from ..gaits.runner import WalkResult

WalkSpec = Walk

__all__ = ["WALKS", "Walk", "WalkResult", "WalkSpec", "run_walk"]
