"""Simulate a loaded robot with MuJoCo: torques in, Pinocchio-convention state out.

:class:`Simulator` builds the MuJoCo model of a robot on a terrain
(:func:`~virtual_actuators.simulation.model.build_mujoco_model`) and steps it one control period
at a time with the joint torques held, which is how a controller running at ``control_rate``
drives a robot. States are read and written in Pinocchio's conventions (``q``, ``v``), contacts
are queried by Pinocchio frame name.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import mujoco
import numpy as np

from virtual_actuators.exceptions import InvalidInputError
from virtual_actuators.models.robot import Robot
from virtual_actuators.simulation.conversions import (
    configuration_from_mujoco,
    configuration_to_mujoco,
    direct_gathers,
    torques_to_ctrl,
    velocity_from_mujoco,
    velocity_to_mujoco,
)
from virtual_actuators.simulation.model import (
    Collisions,
    ContactParameters,
    MujocoModel,
    build_mujoco_model,
)
from virtual_actuators.simulation.terrain import Terrain

__all__ = ["Simulator"]


@dataclass
class _Push:
    """An external force held on a body for a time window."""

    body: int
    site: int
    force: np.ndarray  # N, world frame
    end: float  # s, simulation time at which it stops


class Simulator:
    """A MuJoCo simulation of a robot on a terrain, driven by joint torques.

    Attributes:
        robot: The simulated robot.
        terrain: The ground.
        mujoco_model: The :class:`~virtual_actuators.simulation.model.MujocoModel` (MuJoCo model
            plus the Pinocchio index maps).
        model: The MuJoCo ``MjModel``.
        data: The MuJoCo ``MjData`` (read it freely; write it only if you know MuJoCo: contact
            queries are cached per ``(data.time, data.ncon)``, so after changing the state by
            hand, call :meth:`reset` or step).
        control_period: Duration of one :meth:`step` [s].
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
    ) -> None:
        """Build the MuJoCo model and reset to the robot's standing pose at rest.

        Args:
            robot: The robot to simulate.
            terrain: The ground; level ground at height 0 when None.
            timestep: Physics time step [s].
            control_rate: Control frequency [Hz]; ``1 / control_rate`` must be a whole number
                of physics steps.
            actuated: Joints driven by motors (see
                :func:`~virtual_actuators.simulation.model.build_mujoco_model`); by default
                every 1-DoF joint not in ``robot.passive_joints``.
            contact: Contact parameters (defaults documented in
                :class:`~virtual_actuators.simulation.model.ContactParameters`).
            collisions: Which robot geometry collides (see ``build_mujoco_model``).

        Raises:
            InvalidInputError: If ``control_rate`` is not positive or its period is not a whole
                number of time steps, or an argument of ``build_mujoco_model`` is invalid.
            RobotDescriptionError: If the robot cannot be turned into a MuJoCo model.
            JointNotFoundError: If ``actuated`` names an unknown joint.

        """
        if not (
            isinstance(control_rate, (int, float))
            and math.isfinite(control_rate)
            and control_rate > 0
        ):
            raise InvalidInputError(
                f"control_rate must be a positive number of Hz: {control_rate!r}."
            )
        if not (isinstance(timestep, (int, float)) and math.isfinite(timestep) and timestep > 0):
            raise InvalidInputError(f"timestep must be a positive number of seconds: {timestep!r}.")
        period = 1.0 / float(control_rate)
        ratio = period / float(timestep)
        substeps = round(ratio)
        if substeps < 1 or abs(ratio - substeps) > 1e-9 * max(1.0, ratio):
            raise InvalidInputError(
                f"The control period 1/{control_rate:g} Hz = {period:g} s is not a whole number "
                f"of physics steps of {timestep:g} s ({ratio:.6g} steps); choose a control rate "
                "that divides 1/timestep."
            )
        self.mujoco_model: MujocoModel = build_mujoco_model(
            robot,
            terrain,
            timestep=timestep,
            actuated=actuated,
            contact=contact,
            collisions=collisions,
        )
        self.robot = robot
        self.terrain = self.mujoco_model.terrain
        self.model: mujoco.MjModel = self.mujoco_model.model
        self.data = mujoco.MjData(self.model)
        self.control_period = period
        self.substeps = int(substeps)
        self._pushes: list[_Push] = []
        self._applied = np.zeros((self.model.nbody, 6))  # our share of xfrc_applied
        self._pushing = False  # whether _applied holds anything
        self._force = np.zeros(6)
        self._owned_geoms: dict[str, frozenset[int]] = {}
        self._force_rows: dict[tuple[str, ...], dict[int, list[int]]] = {}  # contact_forces
        self._contacts: list[tuple[int, int, float]] = []
        self._contacts_time: tuple[float, int] | None = None  # (time, ncon) of _contacts
        self._switches: dict[str, bool] = {}  # in_contact answers at _contacts_time
        self._switch_geoms: dict[tuple[str, ...], tuple[tuple[str, frozenset[int]], ...]] = {}
        self._touching: frozenset[str] | None = None  # touching_terrain at _contacts_time
        self._touching_sets: dict[tuple[int, ...], frozenset[str]] = {}  # by touching geoms
        self._switch_answers: dict[tuple, dict[str, bool]] = {}  # by frames and geoms
        self._touched: tuple[int, ...] = ()
        # the state read every tick: MuJoCo's arrays (views, allocated once with the data) and,
        # for hinge-and-slide robots, the one gather that converts them
        self._qpos, self._qvel, self._ctrl = self.data.qpos, self.data.qvel, self.data.ctrl
        self._direct_q, self._direct_v = direct_gathers(self.mujoco_model)
        self.reset()

    # -- state -----------------------------------------------------------------------------------

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
        return velocity_from_mujoco(self.mujoco_model, self._qpos, self._qvel)

    def reset(self, q: np.ndarray | None = None, v: np.ndarray | None = None) -> None:
        """Restart at time 0 from a state given in Pinocchio's conventions.

        Args:
            q: Configuration, size ``model.nq``; ``robot.neutral()`` (the standing pose when the
                robot has one) when None.
            v: Velocity, size ``model.nv``; zero when None.

        Raises:
            InvalidInputError: If ``q`` or ``v`` has the wrong size or non-finite entries.

        """
        pin_model = self.robot.model
        q = self.robot.neutral() if q is None else q
        v = np.zeros(pin_model.nv) if v is None else v
        qpos = configuration_to_mujoco(self.mujoco_model, q)
        qvel = velocity_to_mujoco(self.mujoco_model, q, v)
        mujoco.mj_resetData(self.model, self.data)
        self.data.qpos[:] = qpos
        self.data.qvel[:] = qvel
        self._pushes.clear()
        self._applied[:] = 0.0
        self._pushing = False
        mujoco.mj_forward(self.model, self.data)
        self._contacts_time = None

    # -- stepping --------------------------------------------------------------------------------

    def step(self, tau: np.ndarray, *, ignore_unactuated: bool = False) -> None:
        """Advance one control period with the joint efforts ``tau`` held.

        MuJoCo clips each effort to its actuator's ``ctrlrange`` (``+-effortLimit``).

        Args:
            tau: Joint efforts [N m or N] in Pinocchio's velocity order, size ``model.nv``.
            ignore_unactuated: Drop efforts on degrees of freedom no actuator drives instead of
                raising.

        Raises:
            InvalidInputError: If ``tau`` has the wrong size or non-finite entries, or asks for
                an effort on an unactuated degree of freedom (the message names the joint).

        """
        ctrl = torques_to_ctrl(self.mujoco_model, tau, ignore_unactuated=ignore_unactuated)
        self._ctrl[:] = ctrl
        if not self._pushes and not self._pushing:
            mujoco.mj_step(self.model, self.data, nstep=self.substeps)
            return
        for _ in range(self.substeps):
            self._apply_pushes()
            mujoco.mj_step(self.model, self.data)
        self._apply_pushes()

    def push(self, force_world: np.ndarray, frame: str, duration: float = 0.1) -> None:
        """Push the robot: hold a world-frame force at a frame's origin for a while, from now.

        The force is applied through ``xfrc_applied`` on the frame's body, with the moment that
        puts it at the frame origin (updated every physics step). Pushes add up.

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
        force = np.array(force_world, dtype=float).reshape(-1)
        if force.shape != (3,) or not np.all(np.isfinite(force)):
            raise InvalidInputError(
                f"force_world must be 3 finite numbers [N], got {force_world!r}."
            )
        if not (isinstance(duration, (int, float)) and math.isfinite(duration) and duration > 0):
            raise InvalidInputError(f"duration must be a positive number of seconds: {duration!r}.")
        if body == 0:
            raise InvalidInputError(f"Frame {frame!r} is fixed to the world: it cannot be pushed.")
        end = self.time + float(duration) - 0.5 * self.model.opt.timestep
        self._pushes.append(_Push(body, mm.frame_sites[frame], force, end))
        self._apply_pushes()

    def _apply_pushes(self) -> None:
        """Write the active pushes into ``xfrc_applied`` (removing the ones that ended)."""
        data, applied = self.data, self._applied
        if self._pushing:  # else our share is zero already
            data.xfrc_applied[:] -= applied
            applied[:] = 0.0
        now = float(data.time)
        pushes = self._pushes = [push for push in self._pushes if now < push.end]
        for push in pushes:
            x, y, z = (data.site_xpos[push.site] - data.xipos[push.body]).tolist()  # lever [m]
            fx, fy, fz = push.force.tolist()  # [N]
            applied[push.body, :3] += push.force
            applied[push.body, 3:] += (y * fz - z * fy, z * fx - x * fz, x * fy - y * fx)
        if pushes:
            data.xfrc_applied[:] += applied
        self._pushing = bool(pushes)

    # -- contacts --------------------------------------------------------------------------------

    def _frame_geoms(self, frame: str) -> frozenset[int]:
        """The robot geoms owned by ``frame`` (checked and cached on first use).

        Raises:
            FrameNotFoundError: If the robot has no such frame (with the closest names).
        """
        geoms = self._owned_geoms.get(frame) if frame.__class__ is str else None
        if geoms is None:
            mm = self.mujoco_model
            mm.check_frame(frame)
            geoms = self._owned_geoms[frame] = frozenset(mm.frame_geoms.get(frame, ()))
        return geoms

    def terrain_contacts(self) -> list[tuple[int, int, float]]:
        """The active robot-terrain contacts, scanned once per physics state (do not modify).

        Returns:
            ``(index in data.contact, robot geom id, sign)`` per contact; ``sign`` is +1 when
            the robot geom is the contact's second geom (MuJoCo's contact force acts on the
            second geom along the normal), -1 otherwise.

        """
        return self._terrain_contacts()

    def _terrain_contacts(self, frame: str | None = None) -> list[tuple[int, int, float]]:
        """``(contact index, robot geom, sign)`` of the active robot-terrain contacts.

        ``sign`` is +1 when the robot geom is the contact's second geom (MuJoCo's contact force
        acts on the second geom along the normal) and -1 otherwise. The list of all of them is
        built once per physics state.
        """
        key = (self.data.time, self.data.ncon)
        if self._contacts_time != key:
            self._contacts = self._scan_contacts()
            self._touched = tuple([hit[1] for hit in self._contacts])  # robot geoms touching
            self._contacts_time = key
            self._switches = {}
            self._touching = None
        if frame is None:
            return self._contacts
        geoms = self._frame_geoms(frame)
        return [hit for hit in self._contacts if hit[1] in geoms]

    def _scan_contacts(self) -> list[tuple[int, int, float]]:
        """Scan MuJoCo's contact list for robot-terrain contacts."""
        mm = self.mujoco_model
        terrain, owned = mm.terrain_geoms, mm.geom_frames
        contacts = self.data.contact
        hits = []
        rows = zip(contacts.geom.tolist(), contacts.exclude.tolist(), strict=True)
        for i, ((g1, g2), exclude) in enumerate(rows):
            if exclude != 0:
                continue
            if g1 in terrain and g2 not in terrain:
                robot_geom, sign = g2, 1.0
            elif g2 in terrain and g1 not in terrain:
                robot_geom, sign = g1, -1.0
            else:
                continue
            if robot_geom in owned:
                hits.append((i, robot_geom, sign))
        return hits

    def in_contact(self, frame: str) -> bool:
        """Whether a geom of a frame touches the terrain.

        A frame's geoms are those attached to it plus those its origin lies on (a heel frame
        on a heel sphere); see :attr:`MujocoModel.frame_geoms`.

        Args:
            frame: Pinocchio frame name.

        Returns:
            True if any of its geoms is in contact with a terrain geom.

        Raises:
            FrameNotFoundError: If the robot has no such frame (with the closest names).

        """
        data = self.data
        if frame.__class__ is str and self._contacts_time == (data.time, data.ncon):  # cached
            switch = self._switches.get(frame)
            if switch is not None:
                return switch
        switch = bool(self._terrain_contacts(frame))
        self._switches[frame] = switch  # a known frame (unknown ones raised above)
        return switch

    def contact_switches(self, frames: Sequence[str]) -> dict[str, bool]:
        """Whether each of several frames touches the terrain, in one pass over the contacts.

        The same answers as :meth:`in_contact` for each frame (cheaper for several frames).

        Args:
            frames: Pinocchio frame names.

        Returns:
            ``{frame: in contact}`` in the order of ``frames``.

        Raises:
            FrameNotFoundError: If a frame is not the robot's (with the closest names).

        """
        pairs = None
        if frames.__class__ is tuple:
            try:
                pairs = self._switch_geoms.get(frames)
            except TypeError:  # an unhashable entry: _frame_geoms names it below
                pass
        if pairs is None:  # checked (unknown frames raise) and cached per tuple of names
            pairs = tuple((frame, self._frame_geoms(frame)) for frame in frames)
            if frames.__class__ is tuple and all(frame.__class__ is str for frame in frames):
                if len(self._switch_geoms) >= 64:
                    self._switch_geoms.clear()
                self._switch_geoms[frames] = pairs
        self._terrain_contacts()
        key = (pairs, self._touched)
        out = self._switch_answers.get(key)  # the same geoms touching: the same answers
        if out is None:
            touched = set(self._touched)
            out = {frame: not geoms.isdisjoint(touched) for frame, geoms in pairs}
            if len(self._switch_answers) >= 256:
                self._switch_answers.clear()
            self._switch_answers[key] = out
        self._switches.update(out)  # in_contact's cache (reset by _terrain_contacts)
        return dict(out)

    def contact_force(self, frame: str) -> np.ndarray:
        """Total force of the terrain on a frame's geoms, in world axes [N].

        Args:
            frame: Pinocchio frame name.

        Returns:
            The force, shape ``(3,)`` (zero without contact).

        Raises:
            FrameNotFoundError: If the robot has no such frame (with the closest names).

        """
        total = np.zeros(3)
        for i, _, sign in self._terrain_contacts(frame):
            mujoco.mj_contactForce(self.model, self.data, i, self._force)
            axes = self.data.contact.frame[i].reshape(3, 3)  # rows: normal, tangent 1, tangent 2
            total += sign * (axes.T @ self._force[:3])
        return total

    def contact_forces(self, frames: Sequence[str]) -> np.ndarray:
        """Total terrain force on each of several frames' geoms, in world axes [N].

        One pass over the contacts for all of them (cheaper than :meth:`contact_force` per
        frame when a foot is made of several frames).

        Args:
            frames: Pinocchio frame names.

        Returns:
            ``(len(frames), 3)`` forces (zero rows without contact).

        Raises:
            FrameNotFoundError: If the robot has no such frame (with the closest names).

        """
        key = tuple(frames)
        try:
            rows_of = self._force_rows.get(key)
        except TypeError:  # an unhashable entry: _frame_geoms names it below
            rows_of = None
        if rows_of is None:  # geom -> the rows of the frames that own it, once per frame list
            rows_of = {}
            for k, frame in enumerate(key):
                for geom in self._frame_geoms(frame):
                    rows_of.setdefault(geom, []).append(k)
            self._force_rows[key] = rows_of  # every entry a known frame name: hashable
        out = np.zeros((len(key), 3))
        contacts = self._terrain_contacts()
        if not contacts:
            return out
        data, force = self.data, self._force
        axes_all = data.contact.frame  # (ncon, 9): normal, tangent 1, tangent 2 (rows)
        for i, geom, sign in contacts:
            rows = rows_of.get(geom)
            if rows:
                mujoco.mj_contactForce(self.model, data, i, force)
                world = (force[:3] @ axes_all[i].reshape(3, 3)) * sign  # axes^T f
                for k in rows:
                    out[k] += world
        return out

    def touching_terrain(self) -> set[str]:
        """Names of the frames whose geoms touch the terrain (e.g. to detect a fall).

        Returns:
            Frame names (a geom counts for its parent frame and every frame that owns it).

        """
        return set(self.touching_frames())

    def touching_frames(self) -> frozenset[str]:
        """:meth:`touching_terrain` as a frozenset, built once per physics state (not copied).

        Returns:
            Frame names (a geom counts for its parent frame and every frame that owns it).

        """
        self._terrain_contacts()
        touching = self._touching
        if touching is None:  # once per physics state; the same geoms give the same set object
            geoms = self._touched
            touching = self._touching_sets.get(geoms)
            if touching is None:
                owners = self.mujoco_model.geom_frames
                touching = frozenset(name for geom in geoms for name in owners[geom])
                if len(self._touching_sets) >= 256:
                    self._touching_sets.clear()
                self._touching_sets[geoms] = touching
            self._touching = touching
        return touching

    def __repr__(self) -> str:
        return (
            f"Simulator({self.robot.name!r}, terrain={self.terrain!r}, t={self.time:.4f} s, "
            f"dt={self.model.opt.timestep:g} s x {self.substeps} per control period, "
            f"{self.model.nu} actuators)"
        )
