"""MeshCat viewer of robots and virtual actuators: ``va.viz.Viewer(robot)``.

Re-exports `virtual_actuators.visualization` (see there for the details). Importing this
module imports MeshCat; ``import virtual_actuators`` alone does not (``va.viz`` is loaded on
first use).
"""

from .visualization import *  # noqa: F403
from .visualization import __all__  # noqa: F401
