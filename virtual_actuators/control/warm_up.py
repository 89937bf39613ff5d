"""Make what a controller's first tick would build, before that tick (`warm_up`)."""

from __future__ import annotations

import contextlib
import threading

import numpy as np

from ..actuators import ParallelVirtualActuator
from ..exceptions import VirtualActuatorError
from ..kinematics.kernels import velocity_of_point
from ..kinematics.snapshot import Snapshot, thread_data
from ..models.robot import Robot
from .contact_limits import largest_scale, least_margin


def warm_up(controller: object, q: np.ndarray) -> None:
    """Run every compiled kernel the controller's ticks use once, at configuration ``q``.

    Raises:
        InvalidInputError: A bad ``q``.
    """
    robot = controller.robot
    snapshot = Snapshot(robot, q, np.zeros(robot.model.nv))
    thread_data(robot.model)
    if robot.mass > 0.0:
        robot.center_of_mass(snapshot.q)
    # a frame's velocity outside the tick's table (a frame first named mid-run)
    no_columns = np.zeros(0, dtype=np.int64)
    velocity_of_point(snapshot.jacobian_world, snapshot.v, no_columns, 0.0, 0.0, 0.0)
    for attachment in controller.attachments.values():
        kinematics = attachment.sensor.kinematics
        kinematics.sense(snapshot, velocity=True)
        snapshot.frame_velocity(kinematics.action_id)
        if attachment.spring_tick is not None:  # the spring-dampers' one-call tick
            attachment.spring_tick.warm_up(snapshot)
        actuator = attachment.actuator
        if not isinstance(actuator, ParallelVirtualActuator):
            continue
        try:
            if attachment.method == "qp":
                _on_own_thread(actuator, snapshot, attachment)
                if attachment.plan is not None and actuator.qp.matrices.applicable:
                    actuator.qp.matrices.workspace(attachment.plan.keep)  # this thread's
                continue
            solution = actuator.solve(
                snapshot, np.zeros(actuator.n), attachment.free, method=attachment.method
            )
        except VirtualActuatorError:  # singular at q, say: the kernels load on the first tick
            continue
        if attachment.yield_mask is not None:
            least_margin(attachment, snapshot, solution.forces)
            largest_scale(attachment, snapshot, solution.forces, solution.forces)


def _on_own_thread(actuator: ParallelVirtualActuator, snapshot: Snapshot, attachment) -> None:
    """A QP solve on a new thread: its kernels load, this thread's warm start is untouched."""

    def solve() -> None:
        with contextlib.suppress(VirtualActuatorError):
            zero = np.zeros(actuator.n)
            actuator.solve(snapshot, zero, attachment.free, method="qp", weights=attachment.weights)

    worker = threading.Thread(target=solve, name="va-warm-up")
    worker.start()
    worker.join()


def warm_up_driven(controller: object, robot: Robot) -> None:
    """Warm up what a loop drives before its clock starts (``va.run``'s first step).

    [`Controller.warm_up`][] at the robot's neutral configuration, on ``controller`` or the
    ``controller`` it drives (a gait, a tracker), when it controls ``robot``.
    """
    for owner in (controller, getattr(controller, "controller", None)):
        model = getattr(getattr(owner, "robot", None), "model", None)
        if callable(getattr(owner, "warm_up", None)) and model is robot.model:  # a gait too
            owner.warm_up(robot.neutral())
            return
