"""MeshCat viewer of robots and virtual actuators: ``va.viz.Viewer(robot)``.

Re-exports `virtual_actuators.visualization`; importing it imports MeshCat.
"""

from .visualization import *  # noqa: F403
from .visualization import __all__  # noqa: F401
