"""Build a MuJoCo model of any loaded [`Robot`][], in code, with MjSpec.

The model is built from the Pinocchio model (not MuJoCo's URDF importer), so both describe the
same mechanism; every index map is computed by joint name, never by assuming the same order.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import mujoco
import numpy as np
import pinocchio as pin

from virtual_actuators.exceptions import (
    FrameNotFoundError,
    InvalidInputError,
    RobotDescriptionError,
)
from virtual_actuators.models.robot import Robot, frame_id
from virtual_actuators.simulation.geoms import (
    COLLISION_CHOICES,
    Collisions,
    add_geometry,
    add_sites,
)
from virtual_actuators.simulation.ground import ContactParameters, add_terrain
from virtual_actuators.simulation.joints import (
    BOUND_INERTIA,
    BOUND_MASS,
    actuated_joints,
    add_actuators,
    add_bodies,
    balance_inertias,
    joint_kind,
)
from virtual_actuators.simulation.terrain import Terrain
from virtual_actuators.vocabulary.arguments import check_number

__all__ = ["ContactParameters", "JointMap", "MujocoModel", "build_mujoco_model"]


@dataclass(frozen=True)
class JointMap:
    """Where one Pinocchio joint lives in both models.

    Attributes:
        name: Joint name (the same in Pinocchio and MuJoCo).
        kind: ``"free"``, ``"ball"``, ``"hinge"``, ``"continuous"`` (a hinge whose Pinocchio
            ``q`` is ``(cos, sin)``) or ``"slide"``.
        idx_q: First index in Pinocchio's ``q``.
        nq: Entries in Pinocchio's ``q``.
        idx_v: First index in Pinocchio's ``v``.
        nv: Entries in ``v`` (degrees of freedom).
        qpos_adr: First index in MuJoCo's ``qpos``.
        dof_adr: First index in MuJoCo's ``qvel``.
        actuator: MuJoCo actuator id, or None for an unactuated joint.
        placement: Pinocchio joint placement in its parent joint.
    """

    name: str
    kind: str
    idx_q: int
    nq: int
    idx_v: int
    nv: int
    qpos_adr: int
    dof_adr: int
    actuator: int | None
    placement: pin.SE3


@dataclass(frozen=True, eq=False)
class MujocoModel:
    """A compiled MuJoCo model of a robot on a terrain, with the maps back to Pinocchio.

    Attributes:
        robot: The robot it was built from.
        terrain: The terrain.
        model: The compiled MuJoCo model.
        contact: The contact parameters used.
        joints: One `JointMap` per Pinocchio joint (universe excluded), Pinocchio order.
        actuated: Names of the actuated joints, Pinocchio order.
        geom_frames: For each robot geom id, the frames that own it: its parent frame, then every
            frame on the same joint whose origin lies on or inside it.
        frame_geoms: For each frame name, the ids of the robot geoms it owns.
        frame_sites: MuJoCo site id of each frame name.
        terrain_geoms: Ids of the terrain geoms.
        skipped_geometries: Names of the geometries MuJoCo cannot use (no counterpart and no
            finite bounding box).
        approximated_geometries: Names of the meshes simulated as their bounding boxes.
    """

    robot: Robot
    terrain: Terrain
    model: mujoco.MjModel
    contact: ContactParameters
    joints: tuple[JointMap, ...]
    actuated: tuple[str, ...]
    geom_frames: Mapping[int, tuple[str, ...]]
    frame_geoms: Mapping[str, tuple[int, ...]]
    frame_sites: Mapping[str, int]
    terrain_geoms: frozenset[int]
    skipped_geometries: tuple[str, ...] = field(default=())
    approximated_geometries: tuple[str, ...] = field(default=())

    def check_frame(self, frame: str) -> None:
        """Check that ``frame`` names a frame of the robot.

        Raises:
            FrameNotFoundError: If it does not (with the closest frame names).
        """
        if not isinstance(frame, str):
            raise FrameNotFoundError(
                f"A frame is named by a str, got {frame!r} ({type(frame).__name__}); robot "
                f"{self.robot.name!r} has frames such as {self.robot.frame_names[:4]}."
            )
        if frame not in self.frame_sites:  # every frame name has a site
            frame_id(self.robot, frame)  # raises the FrameNotFoundError with the closest names

    def frame_body(self, frame: str) -> int:
        """MuJoCo body id that carries the frame ``frame``.

        Raises:
            FrameNotFoundError: If the robot has no such frame.
        """
        self.check_frame(frame)
        return int(self.model.site_bodyid[self.frame_sites[frame]])

    def __repr__(self) -> str:
        m = self.model
        return (
            f"MujocoModel({self.robot.name!r}, nq={m.nq}, nv={m.nv}, nu={m.nu}, "
            f"{m.ngeom - len(self.terrain_geoms)} robot geoms, terrain={self.terrain!r})"
        )


def build_mujoco_model(
    robot: Robot,
    terrain: Terrain | None = None,
    *,
    timestep: float = 5e-4,
    actuated: Iterable[str] | None = None,
    contact: ContactParameters | None = None,
    collisions: Collisions = "collision",
) -> MujocoModel:
    """Build and compile the MuJoCo model of ``robot`` standing on ``terrain``.

    Args:
        robot: A loaded robot (its URDF is read again for the geometry).
        terrain: The ground; level ground at height 0 when None.
        timestep: Physics time step [s].
        actuated: Joints driven by a motor; by default every 1-DoF joint not in
            ``robot.passive_joints``.
        contact: Contact parameters; [`ContactParameters`][] defaults when None.
        collisions: Which geometry collides: ``"collision"`` (the URDF's collision shapes; an
            unread mesh is its bounding box, with a notice), ``"primitives"`` (the same without
            meshes), ``"visual"`` (the visual shapes) or ``"none"``.

    Returns:
        The compiled model with its index maps.

    Raises:
        RobotDescriptionError: If a joint type has no MuJoCo counterpart, a free-flyer is not the
            root joint, or MuJoCo rejects the model.
        JointNotFoundError: If ``actuated`` names a joint the robot does not have.
        InvalidInputError: If ``actuated`` names a joint with other than one degree of freedom,
            or ``timestep`` or ``collisions`` is invalid.
    """
    terrain = _checked_options(timestep, collisions, terrain)
    contact = ContactParameters() if contact is None else contact
    model = robot.model
    kinds = [joint_kind(model, j) for j in range(1, model.njoints)]
    actuated_names = actuated_joints(robot, kinds, actuated)
    spec = _new_spec(robot, timestep, contact)
    bodies = add_bodies(spec, robot, kinds)
    balance_inertias(spec, robot)
    add_actuators(spec, model, actuated_names)
    geometry = add_geometry(spec, robot, bodies, contact, collisions)
    sites = add_sites(spec, robot, bodies)
    terrain_names = add_terrain(spec, terrain, contact)

    try:
        compiled = spec.compile()
    except Exception as exc:  # MuJoCo raises ValueError with its compiler message
        raise RobotDescriptionError(
            f"MuJoCo cannot compile the model of robot {robot.name!r}: {exc}"
        ) from exc

    geom_frames, frame_geoms = _geom_maps(compiled, geometry.owners)
    return MujocoModel(
        robot=robot,
        terrain=terrain,
        model=compiled,
        contact=contact,
        joints=_joint_maps(compiled, model, kinds, actuated_names),
        actuated=tuple(actuated_names),
        geom_frames=MappingProxyType(geom_frames),
        frame_geoms=MappingProxyType(frame_geoms),
        frame_sites=MappingProxyType(
            {frame: compiled.site(site).id for frame, site in sites.items()}
        ),
        terrain_geoms=frozenset(compiled.geom(name).id for name in terrain_names),
        skipped_geometries=tuple(geometry.skipped),
        approximated_geometries=tuple(geometry.approximated),
    )


def _checked_options(timestep: float, collisions: str, terrain: Terrain | None) -> Terrain:
    """The terrain (level ground when None), after checking the options."""
    check_number(timestep, "timestep [s]", positive=True)
    if collisions not in COLLISION_CHOICES:
        raise InvalidInputError(
            f"collisions must be one of {', '.join(map(repr, COLLISION_CHOICES))}, "
            f"got {collisions!r}."
        )
    terrain = Terrain.flat() if terrain is None else terrain
    if not isinstance(terrain, Terrain):
        raise InvalidInputError(f"terrain must be a Terrain, got {type(terrain).__name__}.")
    return terrain


def _new_spec(robot: Robot, timestep: float, contact: ContactParameters) -> mujoco.MjSpec:
    """An empty MjSpec with the compiler settings and the options (step, gravity, cone)."""
    spec = mujoco.MjSpec()
    spec.modelname = robot.name
    spec.compiler.degree = False
    spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE
    spec.compiler.boundmass = BOUND_MASS
    spec.compiler.boundinertia = BOUND_INERTIA
    spec.option.timestep = float(timestep)
    spec.option.gravity = np.array(robot.model.gravity.linear, dtype=float)
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.cone = getattr(mujoco.mjtCone, f"mjCONE_{contact.cone.upper()}")  # checked name
    return spec


def _joint_maps(
    compiled: mujoco.MjModel, model: pin.Model, kinds: list[str], actuated: list[str]
) -> tuple[JointMap, ...]:
    """The index maps of every Pinocchio joint but the universe, by name."""
    joints = []
    for j, kind in enumerate(kinds, start=1):
        name = model.names[j]
        joint, mj_joint = model.joints[j], compiled.joint(name)
        joints.append(
            JointMap(
                name=name,
                kind=kind,
                idx_q=joint.idx_q,
                nq=joint.nq,
                idx_v=joint.idx_v,
                nv=joint.nv,
                qpos_adr=int(mj_joint.qposadr[0]),
                dof_adr=int(mj_joint.dofadr[0]),
                actuator=compiled.actuator(name).id if name in actuated else None,
                placement=model.jointPlacements[j].copy(),
            )
        )
    return tuple(joints)


def _geom_maps(
    compiled: mujoco.MjModel, geom_parents: dict[str, tuple[str, ...]]
) -> tuple[dict[int, tuple[str, ...]], dict[str, tuple[int, ...]]]:
    """Geom id -> owning frames, and frame -> its geom ids."""
    geom_frames = {compiled.geom(name).id: owners for name, owners in geom_parents.items()}
    frame_geoms: dict[str, list[int]] = {}
    for gid, owners in geom_frames.items():
        for owner in owners:
            frame_geoms.setdefault(owner, []).append(gid)
    return geom_frames, {k: tuple(v) for k, v in frame_geoms.items()}
