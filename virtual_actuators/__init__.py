"""Virtual Actuator Control and Virtual Model Control for any robot described by a URDF.

Declare virtual actuators between frames of a robot, distribute their wrenches over parallel
chains with the extended Partitioned Actuator Set method, and map them to joint efforts.
"""

from . import estimation
from .actuators import ActuatorReading, ParallelVirtualActuator, VirtualActuator
from .components import (
    Component,
    ConstantForce,
    Damper,
    DogtrackBunny,
    EnergyTank,
    GrannyWalker,
    GravityCompensation,
    Inertance,
    Posture,
    Spring,
    SpringDamper,
    SwingLegLinkage,
)
from .control import (
    Context,
    Controller,
    ControlOutput,
    LimitFraction,
    MachineController,
    RunStats,
    State,
    StateMachine,
    TickRate,
    Transition,
    events,
    run,
    tick_rate,
)
from .control.plan.memory import Memory
from .distribution.result import Solution
from .estimation import SensorReading
from .exceptions import (
    ConcurrentUseError,
    ConstraintError,
    FrameNotFoundError,
    GaitPatternError,
    InadmissibleWrenchError,
    InvalidAxisError,
    InvalidInputError,
    JointNotFoundError,
    MissingDependencyError,
    RobotDescriptionError,
    RobotNotFoundError,
    SingularConfigurationError,
    TraceError,
    VirtualActuatorError,
)
from .gaits.legged import GaitPattern, LeggedParameters, LeggedWalker, npod
from .kinematics.snapshot import Snapshot
from .models import Robot, list_robots, load_robot, millipede
from .models.directory import RobotInfo, describe_robots
from .vocabulary import scalar
from .vocabulary.axes import AXES, WORLD
from .vocabulary.constraints import DesignConstraint, Equal, EqualTorque, Linear
from .vocabulary.traced import lowerable

__version__ = "0.1.0"


def __getattr__(name: str) -> object:
    """Load ``va.viz`` (MeshCat) on first use, keeping ``import virtual_actuators`` light.

    Raises:
        MissingDependencyError: ``va.viz`` without MeshCat (the extra ``viz``).
        AttributeError: Any other unknown name.
    """
    if name == "viz":
        import importlib

        return importlib.import_module(".viz", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "AXES",
    "WORLD",
    "Component",
    "ConstantForce",
    "Context",
    "ControlOutput",
    "Controller",
    "Damper",
    "DogtrackBunny",
    "EnergyTank",
    "GaitPattern",
    "GrannyWalker",
    "GravityCompensation",
    "Inertance",
    "LeggedParameters",
    "LeggedWalker",
    "LimitFraction",
    "MachineController",
    "Memory",
    "Posture",
    "RunStats",
    "ActuatorReading",
    "SensorReading",
    "estimation",
    "Spring",
    "SpringDamper",
    "State",
    "StateMachine",
    "SwingLegLinkage",
    "TickRate",
    "Transition",
    "events",
    "lowerable",
    "run",
    "scalar",
    "ConcurrentUseError",
    "TraceError",
    "ConstraintError",
    "DesignConstraint",
    "Equal",
    "EqualTorque",
    "FrameNotFoundError",
    "GaitPatternError",
    "InadmissibleWrenchError",
    "InvalidAxisError",
    "InvalidInputError",
    "JointNotFoundError",
    "Linear",
    "MissingDependencyError",
    "ParallelVirtualActuator",
    "Robot",
    "RobotDescriptionError",
    "RobotInfo",
    "RobotNotFoundError",
    "SingularConfigurationError",
    "Snapshot",
    "Solution",
    "VirtualActuator",
    "VirtualActuatorError",
    "describe_robots",
    "list_robots",
    "load_robot",
    "millipede",
    "npod",
    "tick_rate",
]
