"""One attachment's share of a controller's tick: sense, sum the wrenches, map to efforts."""

from __future__ import annotations

import numpy as np

from ..actuators import VirtualActuator
from ..kinematics.snapshot import Snapshot
from .attachment import Attachment
from .contact_limits import enforce_unilateral
from .failures import CAUGHT, reason_of, recover
from .tick import TickSums


def run_attachment(
    name: str,
    attachment: Attachment,
    snapshot: Snapshot,
    time: float,
    sums: TickSums,
    on_failure: str,
    limits: tuple[np.ndarray, np.ndarray],
) -> None:
    """Sense, sum the components, map to efforts (or recover from a failure) into ``sums``.

    ``limits`` are the controller's ``(lower, upper)`` effort limits (for ``"fallback"``).

    Raises:
        VirtualActuatorError: With ``on_failure="raise"``, the attachment's failure.
    """
    spring, wrench, solution = attachment.spring_tick, None, None
    try:
        if spring is not None:  # and a parallel actuator's distribution, in one call
            buffer, solution = spring.run_solve(attachment.components, snapshot, time)
        else:
            buffer = None
        if buffer is not None:  # spring-dampers: sensing and wrench in one compiled call
            at_position, at_velocity, at_wrench, at_efforts = spring.slices
            sums.positions[name] = buffer[at_position]
            sums.velocities[name] = buffer[at_velocity]
            wrench = sums.wrenches[name] = buffer[at_wrench]
            if at_efforts is not None:  # and a serial actuator's efforts
                sums.produced[name] = wrench
                sums.add(name, buffer[at_efforts], fresh=True)
                return
        else:
            sensor = attachment.sensor
            jacobian, position, velocity = sensor.kinematics.sense(snapshot, velocity=True)
            sums.positions[name], sums.velocities[name] = position, velocity
            wrench = attachment.wrench(position, velocity, time)
            sums.wrenches[name] = wrench
        one_call = attachment.snapshot_solve  # a parallel actuator's compiled solve
        if solution is None and one_call is not None:
            solution = one_call(snapshot, wrench)
        if solution is None:
            actuator = attachment.actuator
            if isinstance(actuator, VirtualActuator):
                jacobian_act = jacobian if actuator is sensor else actuator.jacobian(snapshot)
                sums.add(name, jacobian_act.T @ wrench, fresh=True)
                sums.produced[name] = wrench
                return
            # free axes, method and weights checked at add(); the wrench by Attachment.wrench
            solution = actuator.solve_checked(snapshot, wrench, attachment.plan)[0]
        if attachment.yield_mask is not None:
            solution = enforce_unilateral(attachment, snapshot, wrench, solution)
    except CAUGHT as error:
        if on_failure == "raise":
            raise
        solution, effort = recover(
            on_failure, attachment, snapshot, wrench, reason_of(error, wrench), error, limits, sums
        )
        if effort is None:
            return
    else:
        effort = solution.tau
    sums.solutions[name], sums.produced[name] = solution, solution.wrench
    sums.add(name, effort, fresh=False)


__all__ = ["run_attachment"]
