"""``demo stand``: any legged robot standing, its body actuator and force distribution.

Feet come from `find_feet` or ``--feet``: three or more are point contacts, two (a biped) flat
ones; the robot stands in its `standing_pose`.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Sequence

import numpy as np

from .views import print_solution, show_static


def stand_robot(name: str = "solo12", feet: Sequence[str] | None = None):
    """Load the robot of ``demo stand`` and find its body and feet.

    Args:
        name: A robot name, alias or URDF path for [`load_robot`][].
        feet: Foot frame names (None: found on the robot).

    Returns:
        ``(robot, body frame, foot frames)``.

    Raises:
        RobotNotFoundError: If no robot has this name or path.
        RobotDescriptionError: If its URDF cannot be loaded.
        FrameNotFoundError: If it has no feet (an arm, a hand: the message says so), or a frame
            given in ``feet`` is not in the model.
    """
    import virtual_actuators as va
    from virtual_actuators.models.feet import body_frame, find_feet
    from virtual_actuators.vocabulary.axes import resolve_frame

    robot = va.load_robot(name)
    if feet is None:
        found = find_feet(robot)
        return robot, found.body, list(found.feet)
    for frame in feet:
        resolve_frame(robot.model, frame, "foot")
    return robot, body_frame(robot.model, robot.floating_base), list(feet)


def demo_stand(
    robot: object = "solo12",
    repeat: int = 2000,
    args: argparse.Namespace | None = None,
    feet: Sequence[str] | None = None,
) -> None:
    """Print a legged robot's body actuator distribution (and show it with ``--viz``).

    Args:
        robot: A name or path, or ``(robot, body, feet)`` from `stand_robot`.
        repeat: Solves per timing.
        args: The parsed command line (for the viewer options), or None.
        feet: Foot frames when ``robot`` is a name (None: found on the robot).

    Raises:
        RobotNotFoundError: If ``robot`` is a name that no robot has.
        RobotDescriptionError: If its URDF cannot be loaded.
        FrameNotFoundError: If it has no feet.
        SingularConfigurationError: If its standing pose has a straight leg, or a leg cannot
            reach the pose built for it.
    """
    import virtual_actuators as va
    from virtual_actuators.models.standing import standing_pose

    robot, body_frame, feet = robot if isinstance(robot, tuple) else stand_robot(robot, feet)
    q = standing_pose(robot, feet) if robot.floating_base else robot.neutral()
    weight = robot.mass * 9.81  # [N]
    contact = "point" if len(feet) >= 3 else "flat"
    print(
        f"{robot}  mass {robot.mass:.2f} kg; body {body_frame!r} on {len(feet)} feet "
        f"({', '.join(feet)}), {contact} contacts"
    )
    body = va.ParallelVirtualActuator(
        robot, action=body_frame, reactions=feet, reference=body_frame, contact=contact
    )
    wrench = np.array([2.0, 0.0, weight, 0.1, -0.2, 0.05])  # [N, N m] in the body frame
    sol = body.solve(q, wrench)
    print_solution("body actuator (minimum-norm distribution)", robot, body, q, wrench, sol)
    shown, actuator = sol, body
    timed = [("minimum-norm", body)]
    if len(feet) == 4 and contact == "point":
        # all x forces equal, y forces equal front and hind, diagonal z sums equal: r = 6
        design = [va.Equal((feet[0], "x"), (foot, "x")) for foot in feet[1:]]
        design += [
            va.Equal((feet[0], "y"), (feet[1], "y")),
            va.Equal((feet[2], "y"), (feet[3], "y")),
        ]
        z = {(feet[0], "z"): 1, (feet[3], "z"): 1, (feet[1], "z"): -1, (feet[2], "z"): -1}
        design.append(va.Linear(z))
        square = va.ParallelVirtualActuator(
            robot, action=body_frame, reactions=feet, reference=body_frame, design=design
        )
        shown, actuator = square.solve(q, wrench), square
        title = "with six design constraints (square, partitioned)"
        print_solution(title, robot, square, q, wrench, shown)
        timed.append(("partitioned", square))
    for name, timed_actuator in timed:
        start = time.perf_counter()
        for _ in range(repeat):
            timed_actuator.solve(q, wrench)
        elapsed = (time.perf_counter() - start) / repeat * 1e6
        print(f"\nsolve time ({name}): {elapsed:.1f} us per call (mean of one run)")
    if args is not None:
        show_static(args, robot, q, shown, actuator, wrench)
