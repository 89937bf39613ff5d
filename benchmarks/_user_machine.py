"""A user's own state machine, built only from the public classes, in ``va.run``'s loop.

solo12 stands on its four point feet and bobs: a body spring-damper on all six axes of the base
(``ParallelVirtualActuator`` over the feet), one set point high and one low, two states that
take turns every half second (``va.events.after``), every joint's own gravity
(``GravityCompensation``). Nothing in it is a gait of the library: it is what a user writes after
the tutorials, and the figure times the whole loop (``va.run`` on ``MujocoHardware``) beside
MuJoCo stepping the same robot alone, in the same run.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

FEET = ("FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT")


def bobbing_machine(robot: Any, height: float) -> Any:
    """The user's machine: ``high`` and ``low``, half a second each, on solo12's four feet."""
    import virtual_actuators as va

    body = va.ParallelVirtualActuator(robot, "base_link", list(FEET), "world", contact="point")
    weight = robot.mass * 9.81
    stiffness = [600.0, 600.0, 900.0, 60.0, 60.0, 30.0]
    damping = [40.0, 40.0, 60.0, 4.0, 4.0, 2.0]
    controller = va.Controller(robot, clip=True)
    for name, z in (("high", height), ("low", height - 0.03)):
        spring = va.SpringDamper(body.axes, stiffness, damping, setpoint=[0, 0, z, 0, 0, 0],
                                 force=[0, 0, weight, 0, 0, 0])  # fmt: skip
        controller.add(name, body, [spring])
    machine = va.StateMachine(
        states=[va.State("high", active=("high",), support=FEET),
                va.State("low", active=("low",), support=FEET)],
        transitions=[va.Transition("high", "low", va.events.after(0.5)),
                     va.Transition("low", "high", va.events.after(0.5))],
        initial="high",
    )  # fmt: skip
    return va.MachineController(controller, machine)


def _after(ticks: int):
    """A ``should_stop`` that ends ``va.run`` after ``ticks`` ticks."""
    count = [0]

    def stop() -> bool:
        count[0] += 1
        return count[0] > ticks

    return stop


def _stepping(simulator: Any):
    """MuJoCo alone: one step of the robot at zero effort (the loop's baseline)."""
    tau = np.zeros(simulator.robot.model.nv)
    return lambda: simulator.step(tau, ignore_unactuated=True)


def _loop_seconds(step_once, ticks: int) -> float:
    start = time.perf_counter()
    for _ in range(ticks):
        step_once()
    return time.perf_counter() - start


def user_machine_loop(ticks: int = 2000, runs: int = 3) -> dict[str, Any]:
    """The loop's and MuJoCo's per-tick wall time [us], alternated ``runs`` times, and their
    ratio (MuJoCo alone / the whole loop, the medians)."""
    import virtual_actuators as va
    from virtual_actuators.simulation import MujocoHardware, Simulator

    robot = va.load_robot("solo12")
    simulator = Simulator(robot)
    q0 = simulator.on_ground(robot.neutral())  # solo12's SRDF standing pose, on the floor
    loops, alone, last = [], [], None
    for _ in range(runs):
        simulator.reset(q0)
        machine = bobbing_machine(robot, float(q0[2]))  # the base's height standing [m]
        hardware = MujocoHardware(simulator)
        start = time.perf_counter()
        stats = va.run(machine, hardware.read_state, hardware.write_effort, rate_hz=1000.0,
                       realtime=False, should_stop=_after(ticks))  # fmt: skip
        loops.append((time.perf_counter() - start) / hardware.efforts_written)
        last = (machine, stats, simulator.q.copy())
        simulator.reset(q0)
        alone.append(_loop_seconds(_stepping(simulator), ticks) / ticks)
    machine, stats, q_end = last
    compiled = machine.compiled
    loop_us, alone_us = 1e6 * float(np.median(loops)), 1e6 * float(np.median(alone))
    return {
        "ticks": ticks,
        "loop_us": loop_us,
        "mujoco_alone_us": alone_us,
        "ratio": alone_us / loop_us,
        "loops_us": [1e6 * x for x in loops],
        "alone_us": [1e6 * x for x in alone],
        "compiled": compiled is not None,
        "python_pieces": [] if compiled is None else [what for what, _ in compiled.pieces],
        "failed_ticks": stats.failed_ticks,
        "base_height_end_m": float(q_end[2]),
        "states": [name for _, name in machine.machine.history[:4]],
    }


if __name__ == "__main__":
    import json

    print(json.dumps(user_machine_loop(), indent=1))
