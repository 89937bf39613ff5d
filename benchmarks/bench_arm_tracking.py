"""Arms tracking a moving tool target in MuJoCo through ``va.run`` (issue 24, item 1).

    python benchmarks/bench_arm_tracking.py [--duration 8] [--json PATH]

A 6-axis :class:`~virtual_actuators.SpringDamper` (1000 N/m, 50 N m/rad) on the tool of a panda
(``panda_hand``, which starts pointing straight down: its rotation vector has norm pi) and of a
UR5 (``tool0``, pi too), with gravity compensation, run by ``va.run`` on
:class:`~virtual_actuators.simulation.MujocoHardware` at 1 kHz. The tool's target runs around a
horizontal circle of radius 10 cm at 0.25 Hz, in two cases:

* ``hold``: the target orientation is the start orientation;
* ``turn``: the target orientation also turns, 0.3 rad about the world's vertical and 0.2 rad
  about its x axis, sinusoidally at the circle's frequency.

The errors are measured with Pinocchio (frame placement of the simulated ``q``, independent of
the library's sensor): position error ``|p - p_target|`` and orientation error
``|log3(R R_target^T)|``, rms and max over the run. The issue's target: position rms < 8 mm,
orientation rms < 0.1 rad, orientation max < 0.3 rad.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np
import pinocchio as pin

import virtual_actuators as va
from virtual_actuators.simulation import MujocoHardware, Simulator

STIFFNESS = (1000.0, 1000.0, 1000.0, 50.0, 50.0, 50.0)  # [N/m, N m/rad]
DAMPING = (60.0, 60.0, 60.0, 2.0, 2.0, 2.0)  # [N s/m, N m s/rad]
RADIUS = 0.10  # [m]
FREQUENCY = 0.25  # [Hz]
ARMS = {"panda": "panda_hand", "ur5": "tool0"}


def start_pose(robot: va.Robot) -> np.ndarray:
    """The panda's ready pose; the UR5 as in the arm tutorial, its tool pointing down.

    Both tools start with a rotation vector of norm pi. (The UR5 with its wrist joints at 0 is
    at a wrist singularity, wrist 1 and wrist 3 parallel: no law holds its orientation there.)
    """
    q = robot.neutral()
    if robot.name.startswith("ur5"):
        q[1], q[2] = -1.2, 1.5  # shoulder lift, elbow [rad]
        q[3], q[4] = -(q[1] + q[2]) - math.pi / 2, -math.pi / 2  # wrist 1, wrist 2 [rad]
    return q


class ToolTracker:
    """A 6-axis spring-damper on the tool whose set points follow the moving target."""

    def __init__(self, robot: va.Robot, frame: str, q0: np.ndarray, turn: bool) -> None:
        self.turn = turn
        self.controller = va.Controller(robot)
        self.tool = va.VirtualActuator(robot, frame, "world", "world")  # all six axes
        start = self.tool.position(q0)  # position [m], rotation vector [rad]
        self.center = start[:3] - (RADIUS, 0.0, 0.0)
        self.rotation0 = pin.exp3(start[3:])
        self.spring = va.SpringDamper(self.tool.axes, STIFFNESS, DAMPING, setpoint=start)
        self.controller.add("tool", self.tool, [self.spring])
        self.gravity = va.GravityCompensation(robot)

    def target(self, time: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Target position [m], velocity [m/s], rotation, angular velocity [rad/s] at ``time``."""
        omega = 2.0 * math.pi * FREQUENCY
        c, s = math.cos(omega * time), math.sin(omega * time)
        position = self.center + RADIUS * np.array((c, s, 0.0))
        velocity = RADIUS * omega * np.array((-s, c, 0.0))
        if not self.turn:
            return position, velocity, self.rotation0, np.zeros(3)
        yaw, roll = 0.3 * s, 0.2 * s  # [rad]
        rotation_z, rotation_x = (
            pin.exp3(np.array((0.0, 0.0, yaw))),
            pin.exp3(np.array((roll, 0.0, 0.0))),
        )
        rotation = rotation_z @ rotation_x @ self.rotation0
        # world angular velocity of Rz(yaw) Rx(roll) R0: yaw' z + Rz(yaw) roll' x
        angular = np.array((0.0, 0.0, 0.3 * omega * c)) + rotation_z @ np.array(
            (0.2 * omega * c, 0.0, 0.0)
        )
        return position, velocity, rotation, angular

    def compute(self, q: np.ndarray, v: np.ndarray, time: float) -> np.ndarray:
        position, velocity, rotation, angular = self.target(time)
        self.spring.setpoint = np.concatenate((position, pin.log3(rotation)))
        self.spring.velocity_setpoint = np.concatenate((velocity, angular))
        return self.controller.compute(q, v, time).tau + self.gravity.torques(q)


def track(name: str, duration: float, turn: bool) -> dict[str, float]:
    """Run one arm through ``va.run``; errors measured with Pinocchio at every tick."""
    robot = va.load_robot(name)
    frame_id = robot.model.getFrameId(ARMS[name])
    q0 = start_pose(robot)
    simulator = Simulator(robot)
    simulator.reset(q0)
    hardware = MujocoHardware(simulator)
    tracker = ToolTracker(robot, ARMS[name], q0, turn)
    data = robot.model.createData()
    position_errors, orientation_errors = [], []

    def read_state() -> tuple[np.ndarray, np.ndarray, float]:
        q, v, time = hardware.read_state()
        pin.framesForwardKinematics(robot.model, data, q)
        placement = data.oMf[frame_id]
        position, _, rotation, _ = tracker.target(time)
        position_errors.append(np.linalg.norm(placement.translation - position))
        orientation_errors.append(np.linalg.norm(pin.log3(placement.rotation @ rotation.T)))
        return q, v, time

    stats = va.run(
        tracker,
        read_state,
        hardware.write_effort,
        robot=robot,
        rate_hz=1000.0,
        realtime=False,
        should_stop=lambda: simulator.time >= duration - 1e-9,
    )
    position_errors, orientation_errors = np.array(position_errors), np.array(orientation_errors)
    return {
        "position_rms_mm": 1e3 * float(np.sqrt(np.mean(position_errors**2))),
        "position_max_mm": 1e3 * float(position_errors.max()),
        "orientation_rms_rad": float(np.sqrt(np.mean(orientation_errors**2))),
        "orientation_max_rad": float(orientation_errors.max()),
        "zero_ticks": stats.zero_ticks,
        "ticks": stats.ticks,
        "wall_time_s": stats.wall_time,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=8.0, help="simulated seconds")
    parser.add_argument("--json", help="write the figures to this file")
    args = parser.parse_args()
    results = {}
    print(f"{'case':<12}{'pos rms':>10}{'pos max':>10}{'rot rms':>10}{'rot max':>10}  [mm, rad]")
    for name in ARMS:
        for case in ("hold", "turn"):
            figures = track(name, args.duration, turn=case == "turn")
            results[f"{name}-{case}"] = figures
            print(
                f"{name + '-' + case:<12}{figures['position_rms_mm']:>10.2f}"
                f"{figures['position_max_mm']:>10.2f}{figures['orientation_rms_rad']:>10.4f}"
                f"{figures['orientation_max_rad']:>10.4f}  ({figures['zero_ticks']} zero ticks,"
                f" {figures['wall_time_s']:.1f} s)",
                flush=True,
            )
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=2, sort_keys=True))


if __name__ == "__main__":
    main()
