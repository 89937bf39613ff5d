"""Simulate a loaded robot with MuJoCo: torques in, Pinocchio-convention state out.

[`Simulator`][] steps one control period at a time with the efforts held; contacts are queried by
Pinocchio frame name. [`MujocoHardware`][] puts it behind a hardware loop's two callbacks.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from time import perf_counter

import mujoco
import numpy as np

from virtual_actuators.core import kernel
from virtual_actuators.estimation.reading import SensorReading
from virtual_actuators.exceptions import InvalidInputError
from virtual_actuators.models.robot import Robot
from virtual_actuators.simulation.contact_queries import ContactQueries
from virtual_actuators.simulation.conversions import (
    configuration_from_mujoco,
    configuration_to_mujoco,
    ctrl_writer,
    finite_vector,
    gathers,
    state_velocity,
    torques_to_ctrl,
    velocity_to_mujoco,
)
from virtual_actuators.simulation.model import (
    Collisions,
    ContactParameters,
    MujocoModel,
    build_mujoco_model,
)
from virtual_actuators.simulation.sensors import SensorModel, Sensors
from virtual_actuators.simulation.terrain import Terrain
from virtual_actuators.vocabulary.arguments import check_number

#: Farthest distance between the robot and the terrain that `Simulator.on_ground` measures [m].
CLEARANCE_RANGE = 100.0

#: ``v`` of MuJoCo's state with a free joint: the core's one call (None: `state_velocity`).
_STATE_VELOCITY = kernel("state_velocity", None)


def _substeps(control_rate: float, timestep: float) -> int:
    """The number of physics steps in one control period (checked to be whole)."""
    control_rate = check_number(control_rate, "control_rate [Hz]", positive=True)
    timestep = check_number(timestep, "timestep [s]", positive=True)
    period = 1.0 / control_rate
    ratio = period / timestep
    substeps = round(ratio)
    if substeps < 1 or abs(ratio - substeps) > 1e-9 * max(1.0, ratio):
        raise InvalidInputError(
            f"The control period 1/{control_rate:g} Hz = {period:g} s is not a whole number "
            f"of physics steps of {timestep:g} s ({ratio:.6g} steps); choose a control rate "
            "that divides 1/timestep."
        )
    return int(substeps)


@dataclass
class _Push:
    """An external force held on a body for a time window."""

    body: int
    site: int
    force: np.ndarray  # N, world frame
    end: float  # s, simulation time at which it stops


class Simulator(ContactQueries):
    """A MuJoCo simulation of a robot on a terrain, driven by joint torques.

    Attributes:
        robot: The simulated robot.
        terrain: The ground.
        mujoco_model: The [`MujocoModel`][] (MuJoCo model plus the Pinocchio index maps).
        model: The MuJoCo ``MjModel``.
        data: The MuJoCo ``MjData`` (contact queries are cached per ``(data.time,
            data.ncon)``: after writing the state by hand, call [`reset`][] or step).
        control_period: Duration of one [`step`][] [s].
        substeps: Physics steps per control period.

    Example:
        >>> import numpy as np
        >>> import virtual_actuators as va
        >>> from virtual_actuators.simulation import Simulator, Terrain
        >>> sim = Simulator(va.load_robot("spring_turkey"), Terrain.builtin("profile-one"))
        >>> sim.step(np.zeros(sim.robot.model.nv))  # one control period, no torque
        >>> sim.in_contact("left_foot"), round(sim.time, 6)
        (True, 0.001)
    """

    def __init__(
        self,
        robot: Robot,
        terrain: Terrain | None = None,
        *,
        timestep: float = 5e-4,
        control_rate: float = 1000.0,
        actuated: Iterable[str] | None = None,
        contact: ContactParameters | None = None,
        collisions: Collisions = "collision",
        sensors: SensorModel | None = None,
    ) -> None:
        """Build the MuJoCo model and reset to the robot's standing pose at rest.

        Args:
            robot: The robot to simulate.
            terrain: The ground; level ground at height 0 when None.
            timestep: Physics time step [s].
            control_rate: Control frequency [Hz]; ``1 / control_rate`` must be a whole number
                of physics steps.
            actuated: Joints driven by motors (default: every 1-DoF joint not in
                ``robot.passive_joints``; see [`build_mujoco_model`][]).
            contact: Contact parameters (defaults in [`ContactParameters`][]).
            collisions: Which robot geometry collides (see ``build_mujoco_model``).
            sensors: What `read_sensors` reads and its noise; None: `SensorModel()` (a MEMS
                IMU on the floating base, encoders, no contact switches).

        Raises:
            InvalidInputError: If ``control_rate`` is not positive or its period is not a whole
                number of time steps, or an argument of ``build_mujoco_model`` is invalid.
            RobotDescriptionError: If the robot cannot be turned into a MuJoCo model.
            JointNotFoundError: If ``actuated`` names an unknown joint.
            FrameNotFoundError: If ``sensors`` names an unknown IMU or contact frame.
        """
        substeps = _substeps(control_rate, timestep)
        self.mujoco_model: MujocoModel = build_mujoco_model(
            robot, terrain, timestep=timestep, actuated=actuated, contact=contact,
            collisions=collisions,
        )  # fmt: skip
        self.robot = robot
        self.terrain = self.mujoco_model.terrain
        self.model: mujoco.MjModel = self.mujoco_model.model
        self.data = mujoco.MjData(self.model)
        self.control_period = 1.0 / float(control_rate)
        self.substeps = substeps
        self._pushes: list[_Push] = []
        self._applied = np.zeros((self.model.nbody, 6))  # our share of xfrc_applied
        self._init_contact_queries()
        # the state read every tick: MuJoCo's arrays (views) and the gathers that convert them
        self._qpos, self._qvel, self._ctrl = self.data.qpos, self.data.qvel, self.data.ctrl
        maps = gathers(self.mujoco_model)
        self._direct_q, self._direct_v = maps.direct_q, maps.direct_v
        self._write_ctrl = ctrl_writer(self.mujoco_model, self._ctrl)  # None: the general path
        self._free_v = None  # (gather, free joints' rows) of the core's read of v, or None
        if _STATE_VELOCITY is not None and self._direct_v is None:
            rows = [(j.qpos_adr, j.dof_adr, j.idx_v) for j in maps.free]
            self._free_v = (maps.gather_v.astype(np.int64), np.array(rows, np.int64).reshape(-1, 3))
        self.sensors = Sensors(SensorModel() if sensors is None else sensors, self)
        self.reset()

    @property
    def time(self) -> float:
        """Simulation time [s]."""
        return float(self.data.time)

    @property
    def q(self) -> np.ndarray:
        """Configuration in Pinocchio's convention (a fresh array of size ``model.nq``)."""
        if self._direct_q is not None:  # MuJoCo keeps its state finite (it resets a diverged one)
            return self._qpos[self._direct_q]
        return configuration_from_mujoco(self.mujoco_model, self._qpos)

    @property
    def v(self) -> np.ndarray:
        """Velocity in Pinocchio's convention (a fresh array of size ``model.nv``).

        The free-flyer's linear and angular velocities are in its body frame.
        """
        if self._direct_v is not None:  # no free joint: one gather
            return self._qvel[self._direct_v]
        if self._free_v is not None:  # free joints: the core's one call
            return _STATE_VELOCITY(self._qpos, self._qvel, *self._free_v)
        return state_velocity(self.mujoco_model, self._qpos, self._qvel)

    def reset(self, q: np.ndarray | None = None, v: np.ndarray | None = None) -> None:
        """Restart at time 0 from a state given in Pinocchio's conventions.

        Args:
            q: Configuration ``(nq,)``; None: ``robot.neutral()``, a floating base set on the
                terrain ([`on_ground`][]).
            v: Velocity ``(nv,)``; zero when None.

        Raises:
            InvalidInputError: If ``q`` or ``v`` has the wrong size or non-finite entries.
        """
        if q is None:
            q = self.robot.neutral()
            if self.robot.floating_base and self.mujoco_model.geom_frames:
                q = self.on_ground(q)
        v = np.zeros(self.robot.model.nv) if v is None else v
        qpos = configuration_to_mujoco(self.mujoco_model, q)
        qvel = velocity_to_mujoco(self.mujoco_model, q, v)
        mujoco.mj_resetData(self.model, self.data)
        self.data.qpos[:] = qpos
        self.data.qvel[:] = qvel
        self._pushes.clear()
        self._applied[:] = 0.0
        mujoco.mj_forward(self.model, self.data)
        self._contacts_time = None  # ContactQueries scans again
        self.sensors.reset()

    def read_sensors(self) -> SensorReading:
        """What the robot's sensors read now (the `SensorModel`'s IMU, encoders, switches)."""
        return self.sensors.read()

    def on_ground(self, q: np.ndarray) -> np.ndarray:
        """``q`` with the floating base moved vertically so the lowest geometry touches the terrain.

        MuJoCo's signed distances of the collision geoms; the simulation's state is left alone.

        Args:
            q: Configuration of a floating-base robot ``(nq,)``.

        Returns:
            A copy of ``q`` with its base height changed.

        Raises:
            InvalidInputError: A fixed-base robot, a robot without collision geometry, or a bad
                ``q``.
        """
        if not self.robot.floating_base or not self.mujoco_model.geom_frames:
            raise InvalidInputError(
                f"on_ground: robot {self.robot.name!r} needs a floating base and collision "
                "geometry to be set on the ground."
            )
        mm = self.mujoco_model
        scratch = mujoco.MjData(self.model)
        scratch.qpos[:] = configuration_to_mujoco(mm, q)
        mujoco.mj_kinematics(self.model, scratch)
        distances = (  # < 0: inside; beyond CLEARANCE_RANGE counts as it
            mujoco.mj_geomDistance(self.model, scratch, geom, ground, CLEARANCE_RANGE, None)
            for geom in mm.geom_frames
            for ground in mm.terrain_geoms
        )
        placed = np.array(q, dtype=float)
        placed[2] -= min((CLEARANCE_RANGE, *distances))
        return placed

    def step(self, tau: np.ndarray, *, ignore_unactuated: bool = False) -> None:
        """Advance one control period with the joint efforts ``tau`` held.

        MuJoCo clips each effort to its actuator's ``ctrlrange`` (``+-effortLimit``).

        Args:
            tau: Joint efforts ``(nv,)`` [N m or N] in Pinocchio's velocity order.
            ignore_unactuated: Drop efforts on unactuated degrees of freedom instead of raising.

        Raises:
            InvalidInputError: If ``tau`` has the wrong size or non-finite entries, or asks for
                an effort on an unactuated degree of freedom (the message names the joint).
        """
        write = self._write_ctrl
        if write is None or not write(tau, ignore_unactuated):  # the general path says why
            ctrl = torques_to_ctrl(self.mujoco_model, tau, ignore_unactuated=ignore_unactuated)
            self._ctrl[:] = ctrl
        self.sensors.applied(tau)  # checked above
        if not self._pushes:  # then _applied is zero
            mujoco.mj_step(self.model, self.data, nstep=self.substeps)
            return
        for _ in range(self.substeps):
            self._apply_pushes()
            mujoco.mj_step(self.model, self.data)
        self._apply_pushes()

    def push(self, force_world: np.ndarray, frame: str, duration: float = 0.1) -> None:
        """Push the robot: hold a world-frame force at a frame's origin for a while, from now.

        Through ``xfrc_applied`` on the frame's body, with the moment that puts it at the frame
        origin (updated every physics step). Pushes add up.

        Args:
            force_world: Force [N] in world axes, 3 values.
            frame: Pinocchio frame whose origin the force acts at.
            duration: How long the force lasts [s] (> 0).

        Raises:
            FrameNotFoundError: If the robot has no such frame (with the closest names).
            InvalidInputError: If the force is not 3 finite numbers, ``duration`` is not
                positive, or the frame is fixed to the world.
        """
        mm = self.mujoco_model
        body = mm.frame_body(frame)
        force = finite_vector(force_world, 3, "force_world [N]").copy()  # the caller's is free
        duration = check_number(duration, "duration [s]", positive=True)
        if body == 0:
            raise InvalidInputError(f"Frame {frame!r} is fixed to the world: it cannot be pushed.")
        end = self.time + duration - 0.5 * self.model.opt.timestep
        self._pushes.append(_Push(body, mm.frame_sites[frame], force, end))
        self._apply_pushes()

    def _apply_pushes(self) -> None:
        """Write the active pushes into ``xfrc_applied`` (removing the ones that ended)."""
        data, applied = self.data, self._applied
        if self._pushes:  # else our share is zero already
            data.xfrc_applied[:] -= applied
            applied[:] = 0.0
        now = float(data.time)
        pushes = self._pushes = [push for push in self._pushes if now < push.end]
        for push in pushes:
            lever = data.site_xpos[push.site] - data.xipos[push.body]  # [m]
            applied[push.body, :3] += push.force
            applied[push.body, 3:] += np.cross(lever, push.force)
        if pushes:
            data.xfrc_applied[:] += applied

    def __repr__(self) -> str:
        return (
            f"Simulator({self.robot.name!r}, terrain={self.terrain!r}, t={self.time:.4f} s, "
            f"dt={self.model.opt.timestep:g} s x {self.substeps} per control period, "
            f"{self.model.nu} actuators)"
        )


class MujocoHardware:
    """A [`Simulator`][] behind the two callbacks of a hardware control loop.

    ``write_effort`` holds the efforts for one control period and steps the physics; ``va.run``'s
    final zero steps once more unless ``write_final=hardware.hold_effort`` takes it.

    Args:
        simulator: The simulation that plays the robot.
        ignore_unactuated: Drop efforts on degrees of freedom no actuator drives (False: an
            error of `write_effort`, as [`Simulator.step`][] raises it).

    Attributes:
        simulator: As given.
        ignore_unactuated: As given.
        efforts_written: Calls of `write_effort` and `hold_effort` (the final zero included).
        physics_time: Wall-clock time spent in the physics steps [s].
    """

    def __init__(self, simulator: Simulator, *, ignore_unactuated: bool = True) -> None:
        self.simulator = simulator
        self.ignore_unactuated = bool(ignore_unactuated)
        self.efforts_written = 0
        self.physics_time = 0.0
        self._data = simulator.data

    def read_state(self) -> tuple[np.ndarray, np.ndarray, float]:
        """``(q, v, time)`` of the simulation (Pinocchio conventions, seconds)."""
        return self.simulator.q, self.simulator.v, float(self._data.time)

    def read_sensors(self) -> SensorReading:
        """What the simulated robot's sensors read (`Simulator.read_sensors`)."""
        return self.simulator.read_sensors()

    def write_effort(self, tau: np.ndarray) -> None:
        """Hold ``tau`` for one control period (see ``ignore_unactuated``).

        Raises:
            InvalidInputError: ``tau`` of the wrong size or with non-finite entries; an effort
                on an unactuated degree of freedom without ``ignore_unactuated``.
        """
        start = perf_counter()
        self.simulator.step(tau, ignore_unactuated=self.ignore_unactuated)
        self.physics_time += perf_counter() - start
        self.efforts_written += 1

    def hold_effort(self, tau: np.ndarray) -> None:
        """Set the efforts MuJoCo holds (its controls) without stepping: a loop's final zero.

        Raises:
            InvalidInputError: ``tau`` of the wrong size or with non-finite entries; an effort
                on an unactuated degree of freedom without ``ignore_unactuated``.
        """
        model = self.simulator.mujoco_model
        self._data.ctrl[:] = torques_to_ctrl(model, tau, ignore_unactuated=self.ignore_unactuated)
        self.efforts_written += 1

    def __repr__(self) -> str:
        return f"MujocoHardware({self.simulator!r})"
