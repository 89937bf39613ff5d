"""Build a MuJoCo model of any loaded :class:`~virtual_actuators.Robot`, in code, with MjSpec.

The model is built from the robot's Pinocchio model (not with MuJoCo's URDF importer), so both
describe exactly the same mechanism:

* one MuJoCo body per Pinocchio joint, placed at ``model.jointPlacements`` relative to its parent
  joint's body, carrying the joint's inertia ``model.inertias`` (mass, centre of mass, and the
  rotational inertia as principal moments and axes; links welded by fixed joints are already
  merged by Pinocchio);
* the joint itself at the body origin, with Pinocchio's name: a revolute joint about any axis
  (``RX``, ``RY``, ``RZ``, unaligned) is a hinge, a continuous one (``RUBX``... whose ``q`` is
  ``(cos, sin)``) an unlimited hinge, a prismatic joint a slide, a free-flyer a free joint and a
  spherical joint a ball joint; any other joint type raises
  :class:`~virtual_actuators.exceptions.RobotDescriptionError`;
* joint ranges from ``lowerPositionLimit`` / ``upperPositionLimit`` when they are finite and
  different (never for continuous or ball joints), ``model.damping`` as joint damping,
  ``model.friction`` as dry friction (``frictionloss``), ``model.armature`` as armature;
* one ``motor`` actuator (gear 1, named after its joint) per actuated joint, its control range
  ``+-effortLimit`` when the limit is finite and positive. By default every 1-DoF joint not in
  :attr:`Robot.passive_joints` is actuated; a free-flyer never is;
* the collision geometry of the URDF read by Pinocchio (``pin.buildGeomFromUrdf``): boxes,
  spheres, cylinders, capsules and ellipsoids as MuJoCo primitives, binary STL and OBJ meshes as
  meshes (MuJoCo collides with their convex hull); other meshes (DAE, ASCII STL...) are skipped
  with a warning naming them;
* one site per Pinocchio frame, named after the frame, to read frame placements and to push;
* the :class:`~virtual_actuators.simulation.terrain.Terrain`, gravity from the Pinocchio model
  (``-9.81 z`` by default).

Contact model (:class:`ContactParameters`): MuJoCo soft contacts with friction 1.0, ``condim 3``
(no torsional or rolling friction), ``solref = (0.005 s, 1.0)`` (time constant and critical
damping; the time constant must stay above two physics steps, here 10 steps of 0.5 ms) and the
default ``solimp = (0.9, 0.95, 1 mm, 0.5, 2)``. This is stiff enough for walking robots: at
0.5 ms steps the 10 kg Spring Turkey standing on its two 2 cm foot spheres sinks less than
0.1 mm into the ground (the tests require < 3 mm). MuJoCo's default ``solref = (0.02, 1)`` has
a four times longer time constant (16 times lower stiffness) and suits larger steps. The
``implicitfast`` integrator keeps large joint damping stable. Robot geometries collide with the
terrain only; pass ``ContactParameters(self_collisions=True)`` to let non-adjacent robot bodies
collide as well.

Every index map (Pinocchio ``q`` / ``v`` indices, MuJoCo ``qpos`` / ``qvel`` addresses, actuator
ids) is computed by joint *name*, never by assuming the same ordering.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Literal

import mujoco
import numpy as np
import pinocchio as pin

from virtual_actuators.exceptions import (
    FrameNotFoundError,
    InvalidInputError,
    JointNotFoundError,
    RobotDescriptionError,
    suggestion,
)
from virtual_actuators.robots.robot import Robot
from virtual_actuators.simulation.terrain import Terrain

__all__ = [
    "ContactParameters",
    "JointMap",
    "MujocoModel",
    "build_mujoco_model",
]

#: Mesh formats MuJoCo reads (STL in binary form only).
MESH_FORMATS = (".stl", ".obj")

#: Most faces MuJoCo reads from an STL file.
MAX_STL_FACES = 200_000

#: Lower bounds that let massless moving bodies compile [kg] and [kg m^2]; real links are far
#: heavier, so these change nothing for them.
BOUND_MASS = 1e-6
BOUND_INERTIA = 1e-10

#: Thickness of the terrain boxes, perpendicular to the surface [m].
TERRAIN_THICKNESS = 0.2

#: Length of the level terrain boxes before the first and after the last profile point [m].
TERRAIN_RUN = 50.0

#: Prefix of the names of the terrain geoms.
TERRAIN_PREFIX = "terrain_"

#: Geom groups (MuJoCo's visualiser shows groups 0-2 by default).
TERRAIN_GROUP = 0
ROBOT_GROUP = 3
SITE_GROUP = 4

# Collision bits: robot geoms (contype 2, conaffinity 1) touch the terrain (contype 1,
# conaffinity 2) but not each other unless self-collisions are enabled (both 3).
_TERRAIN_BITS = (1, 2)
_ROBOT_BITS = (2, 1)
_ROBOT_SELF_BITS = (3, 3)

Collisions = Literal["collision", "primitives", "visual", "none"]
_COLLISION_CHOICES = ("collision", "primitives", "visual", "none")


@dataclass(frozen=True)
class ContactParameters:
    """Contact settings shared by every robot and terrain geom.

    Attributes:
        friction: Sliding friction coefficient (MuJoCo takes the largest of the two geoms').
        torsional_friction: Torsional friction [m] (used only with ``condim`` 4 or 6).
        rolling_friction: Rolling friction [m] (used only with ``condim`` 6).
        condim: 1 (frictionless), 3 (sliding friction), 4 (+ torsional) or 6 (+ rolling).
        solref: ``(time constant [s], damping ratio)`` of the soft contact; the time constant
            should be at least twice the physics time step.
        solimp: MuJoCo's impedance ``(dmin, dmax, width [m], midpoint, power)``.
        margin: Distance [m] at which contacts become active (0: on touching).
        cone: Friction cone, ``"pyramidal"`` (MuJoCo's default) or ``"elliptic"``.
        self_collisions: Whether robot geoms collide with each other (bodies joined by a joint
            never do).

    """

    friction: float = 1.0
    torsional_friction: float = 0.005
    rolling_friction: float = 0.0001
    condim: int = 3
    solref: tuple[float, float] = (0.005, 1.0)
    solimp: tuple[float, float, float, float, float] = (0.9, 0.95, 0.001, 0.5, 2.0)
    margin: float = 0.0
    cone: Literal["pyramidal", "elliptic"] = "pyramidal"
    self_collisions: bool = False

    def __post_init__(self) -> None:
        if self.condim not in (1, 3, 4, 6):
            raise InvalidInputError(f"condim must be 1, 3, 4 or 6, got {self.condim!r}.")
        if self.cone not in ("pyramidal", "elliptic"):
            raise InvalidInputError(f"cone must be 'pyramidal' or 'elliptic', got {self.cone!r}.")
        values = (self.friction, self.torsional_friction, self.rolling_friction, self.margin)
        if not all(math.isfinite(v) and v >= 0.0 for v in values):
            raise InvalidInputError(
                "friction, torsional_friction, rolling_friction and margin must be finite and "
                f">= 0, got {values}."
            )
        if len(self.solref) != 2 or len(self.solimp) != 5:
            raise InvalidInputError("solref needs 2 values and solimp 5 values.")


@dataclass(frozen=True)
class JointMap:
    """Where one Pinocchio joint lives in both models.

    Attributes:
        name: Joint name (the same in Pinocchio and MuJoCo).
        kind: ``"free"``, ``"ball"``, ``"hinge"``, ``"continuous"`` (a hinge whose Pinocchio
            ``q`` is ``(cos, sin)``) or ``"slide"``.
        pin_id: Pinocchio joint index.
        idx_q: First index in Pinocchio's ``q``.
        nq: Entries in Pinocchio's ``q``.
        idx_v: First index in Pinocchio's ``v``.
        nv: Entries in ``v`` (degrees of freedom).
        mj_id: MuJoCo joint id.
        qpos_adr: First index in MuJoCo's ``qpos``.
        dof_adr: First index in MuJoCo's ``qvel``.
        actuator: MuJoCo actuator id, or None for an unactuated joint.
        placement: Pinocchio joint placement in its parent joint (used for a free-flyer, whose
            MuJoCo ``qpos`` is the body pose in the world).

    """

    name: str
    kind: str
    pin_id: int
    idx_q: int
    nq: int
    idx_v: int
    nv: int
    mj_id: int
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
        spec: The MjSpec it was compiled from.
        model: The compiled MuJoCo model.
        contact: The contact parameters used.
        joints: One :class:`JointMap` per Pinocchio joint (universe excluded), Pinocchio order.
        actuated: Names of the actuated joints, Pinocchio order.
        joint_bodies: MuJoCo body id of each Pinocchio joint index (index 0, the universe, is
            the world body).
        geom_frames: For each robot geom id, the Pinocchio frames it belongs to: its parent
            frame first, then every frame on the same joint whose origin lies on or inside it
            (so a heel frame on the surface of a heel sphere owns that sphere).
        frame_geoms: For each frame name, the ids of the robot geoms it owns (frames without
            geometry are absent).
        frame_sites: MuJoCo site id of each frame name (the first frame of that name).
        terrain_geoms: Ids of the terrain geoms.
        skipped_geometries: Names of the Pinocchio geometries left out because MuJoCo cannot
            use them (unsupported shapes or mesh formats; not the meshes that
            ``collisions="primitives"`` leaves out on purpose).

    """

    robot: Robot
    terrain: Terrain
    spec: mujoco.MjSpec
    model: mujoco.MjModel
    contact: ContactParameters
    joints: tuple[JointMap, ...]
    actuated: tuple[str, ...]
    joint_bodies: tuple[int, ...]
    geom_frames: Mapping[int, tuple[str, ...]]
    frame_geoms: Mapping[str, tuple[int, ...]]
    frame_sites: Mapping[str, int]
    terrain_geoms: frozenset[int]
    skipped_geometries: tuple[str, ...] = field(default=())

    def joint(self, name: str) -> JointMap:
        """The map of the joint called ``name``.

        Raises:
            JointNotFoundError: If the robot has no such joint (with the closest names).

        """
        for entry in self.joints:
            if entry.name == name:
                return entry
        raise JointNotFoundError(
            f"Robot {self.robot.name!r} has no joint {name!r}. "
            + suggestion(name, [j.name for j in self.joints], "joints")
        )

    def check_frame(self, frame: str) -> None:
        """Check that ``frame`` names a frame of the robot.

        Raises:
            FrameNotFoundError: If it does not (with the closest frame names).

        """
        if frame not in self.frame_sites:
            raise FrameNotFoundError(
                f"Robot {self.robot.name!r} has no frame {frame!r}. "
                + suggestion(str(frame), self.robot.frame_names, "frames")
            )

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
        robot: A loaded robot (its URDF path or text is read again for the geometry).
        terrain: The ground; level ground at height 0 when None.
        timestep: Physics time step [s].
        actuated: Names of the joints driven by a motor; by default every 1-DoF joint not in
            ``robot.passive_joints``.
        contact: Contact parameters; :class:`ContactParameters` defaults when None.
        collisions: Which robot geometry collides: ``"collision"`` (the URDF's collision
            shapes, readable meshes included; others are skipped with a warning naming them),
            ``"primitives"`` (the same without any mesh, silently),
            ``"visual"`` (the visual shapes, e.g. for robots whose collision shapes are only
            feet), or ``"none"``.

    Returns:
        The compiled model with its index maps.

    Raises:
        RobotDescriptionError: If a joint type has no MuJoCo counterpart (the message names
            the joint), a free-flyer is not the root joint, or MuJoCo rejects the model.
        JointNotFoundError: If ``actuated`` names a joint the robot does not have.
        InvalidInputError: If ``actuated`` names a joint with more or fewer than one degree of
            freedom, or ``timestep`` or ``collisions`` is invalid.

    """
    if not (isinstance(timestep, (int, float)) and math.isfinite(timestep) and timestep > 0):
        raise InvalidInputError(f"timestep must be a positive number of seconds: {timestep!r}.")
    if collisions not in _COLLISION_CHOICES:
        raise InvalidInputError(
            f"collisions must be one of {', '.join(map(repr, _COLLISION_CHOICES))}, "
            f"got {collisions!r}."
        )
    terrain = Terrain.flat() if terrain is None else terrain
    if not isinstance(terrain, Terrain):
        raise InvalidInputError(f"terrain must be a Terrain, got {type(terrain).__name__}.")
    contact = ContactParameters() if contact is None else contact
    model = robot.model
    kinds = [_joint_kind(model, j) for j in range(1, model.njoints)]
    actuated_names = _actuated_joints(robot, kinds, actuated)

    spec = mujoco.MjSpec()
    spec.modelname = robot.name
    spec.compiler.degree = False
    spec.compiler.autolimits = False
    spec.compiler.fusestatic = False
    spec.compiler.inertiafromgeom = mujoco.mjtInertiaFromGeom.mjINERTIAFROMGEOM_FALSE
    spec.compiler.boundmass = BOUND_MASS
    spec.compiler.boundinertia = BOUND_INERTIA
    spec.option.timestep = float(timestep)
    spec.option.gravity = np.array(model.gravity.linear, dtype=float)
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.option.cone = (
        mujoco.mjtCone.mjCONE_ELLIPTIC
        if contact.cone == "elliptic"
        else mujoco.mjtCone.mjCONE_PYRAMIDAL
    )

    bodies = _add_bodies(spec, robot, kinds)
    _balance_inertias(spec, robot)
    for name in actuated_names:
        jid = model.getJointId(name)
        joint = model.joints[jid]
        effort = float(model.effortLimit[joint.idx_v])
        actuator = spec.add_actuator(name=name, target=name)
        actuator.trntype = mujoco.mjtTrn.mjTRN_JOINT
        actuator.gear[0] = 1.0
        actuator.gainprm[0] = 1.0
        actuator.biastype = mujoco.mjtBias.mjBIAS_NONE
        actuator.dyntype = mujoco.mjtDyn.mjDYN_NONE
        if math.isfinite(effort) and effort > 0.0:
            actuator.ctrllimited = mujoco.mjtLimited.mjLIMITED_TRUE
            actuator.ctrlrange = [-effort, effort]
        else:
            actuator.ctrllimited = mujoco.mjtLimited.mjLIMITED_FALSE

    geom_parents, skipped = _add_geometry(spec, robot, bodies, contact, collisions)
    site_names = _add_sites(spec, robot, bodies)
    terrain_names = _add_terrain(spec, terrain, contact)

    try:
        compiled = spec.compile()
    except Exception as exc:  # MuJoCo raises ValueError with its compiler message
        raise RobotDescriptionError(
            f"MuJoCo cannot compile the model of robot {robot.name!r}: {exc}"
        ) from exc

    joints = []
    for j, kind in enumerate(kinds, start=1):
        name = model.names[j]
        joint = model.joints[j]
        mj_id = mujoco.mj_name2id(compiled, mujoco.mjtObj.mjOBJ_JOINT, name)
        act = mujoco.mj_name2id(compiled, mujoco.mjtObj.mjOBJ_ACTUATOR, name)
        joints.append(
            JointMap(
                name=name,
                kind=kind,
                pin_id=j,
                idx_q=joint.idx_q,
                nq=joint.nq,
                idx_v=joint.idx_v,
                nv=joint.nv,
                mj_id=mj_id,
                qpos_adr=int(compiled.jnt_qposadr[mj_id]),
                dof_adr=int(compiled.jnt_dofadr[mj_id]),
                actuator=act if name in actuated_names else None,
                placement=model.jointPlacements[j].copy(),
            )
        )
    joint_bodies = tuple(
        0 if j == 0 else mujoco.mj_name2id(compiled, mujoco.mjtObj.mjOBJ_BODY, bodies[j].name)
        for j in range(model.njoints)
    )
    geom_frames: dict[int, tuple[str, ...]] = {}
    frame_geoms: dict[str, list[int]] = {}
    for geom_name, owners in geom_parents.items():
        gid = mujoco.mj_name2id(compiled, mujoco.mjtObj.mjOBJ_GEOM, geom_name)
        geom_frames[gid] = owners
        for owner in owners:
            frame_geoms.setdefault(owner, []).append(gid)
    frame_sites = {
        frame: mujoco.mj_name2id(compiled, mujoco.mjtObj.mjOBJ_SITE, site)
        for frame, site in site_names.items()
    }
    terrain_ids = frozenset(
        mujoco.mj_name2id(compiled, mujoco.mjtObj.mjOBJ_GEOM, name) for name in terrain_names
    )
    return MujocoModel(
        robot=robot,
        terrain=terrain,
        spec=spec,
        model=compiled,
        contact=contact,
        joints=tuple(joints),
        actuated=tuple(actuated_names),
        joint_bodies=joint_bodies,
        geom_frames=MappingProxyType(geom_frames),
        frame_geoms=MappingProxyType({k: tuple(v) for k, v in frame_geoms.items()}),
        frame_sites=MappingProxyType(frame_sites),
        terrain_geoms=terrain_ids,
        skipped_geometries=tuple(skipped),
    )


# ---------------------------------------------------------------------------------------------
# Joints and bodies


def _joint_kind(model: pin.Model, j: int) -> str:
    """Classify Pinocchio joint ``j`` as free, ball, hinge, continuous or slide.

    Raises:
        RobotDescriptionError: For a joint type MuJoCo has no single joint for.

    """
    joint = model.joints[j]
    short = joint.shortname()
    if short == "JointModelFreeFlyer":
        if model.parents[j] != 0:
            raise RobotDescriptionError(
                f"Joint {model.names[j]!r} is a free-flyer that is not the root joint; MuJoCo "
                "only allows free joints on bodies attached to the world."
            )
        return "free"
    if short == "JointModelSpherical":
        return "ball"
    if joint.nv == 1 and joint.nq in (1, 2) and "Mimic" not in short:
        axis_lin, axis_ang = _motion_axis(model, j)
        if np.linalg.norm(axis_lin) < 1e-12 and abs(np.linalg.norm(axis_ang) - 1.0) < 1e-9:
            return "continuous" if joint.nq == 2 else "hinge"
        if np.linalg.norm(axis_ang) < 1e-12 and abs(np.linalg.norm(axis_lin) - 1.0) < 1e-9:
            if joint.nq == 1:
                return "slide"
    raise RobotDescriptionError(
        f"Joint {model.names[j]!r} has type {short.removeprefix('JointModel')}, which cannot be "
        "simulated: supported joints are revolute (any axis, bounded or continuous), prismatic "
        "(any axis), spherical and a free-flyer root."
    )


def _motion_axis(model: pin.Model, j: int) -> tuple[np.ndarray, np.ndarray]:
    """Linear and angular parts of the motion subspace of 1-DoF joint ``j`` (joint frame)."""
    joint = model.joints[j]
    jdata = joint.createData()
    joint.calc(jdata, pin.neutral(model))
    s = np.asarray(jdata.S, dtype=float).reshape(6)
    return s[:3], s[3:]


def _actuated_joints(robot: Robot, kinds: list[str], actuated: Iterable[str] | None) -> list[str]:
    """Names of the actuated joints in Pinocchio order (see :func:`build_mujoco_model`)."""
    model = robot.model
    names = list(model.names)[1:]
    one_dof = {name for name, kind in zip(names, kinds, strict=True) if kind != "free"}
    one_dof = {name for name in one_dof if model.joints[model.getJointId(name)].nv == 1}
    if actuated is None:
        passive = set(robot.passive_joints)
        return [name for name in names if name in one_dof and name not in passive]
    if isinstance(actuated, str):
        actuated = [actuated]
    requested = list(actuated)
    for name in requested:
        if name not in names:
            raise JointNotFoundError(
                f"Cannot actuate {name!r}: robot {robot.name!r} has no such joint. "
                + suggestion(str(name), names, "joints")
            )
        if name not in one_dof:
            raise InvalidInputError(
                f"Cannot actuate joint {name!r}: a motor drives one degree of freedom and this "
                "joint has "
                f"{model.joints[model.getJointId(name)].nv}."
            )
    return [name for name in names if name in set(requested)]


def _body_names(robot: Robot) -> list[str]:
    """A unique MuJoCo body name per Pinocchio joint: its child link, else the joint name."""
    model = robot.model
    names = ["world"]
    used = {"world"}
    for j in range(1, model.njoints):
        link = next(
            (
                frame.name
                for frame in model.frames
                if frame.parentJoint == j and frame.type == pin.FrameType.BODY
            ),
            model.names[j],
        )
        name = link if link not in used else model.names[j]
        while name in used:
            name += "_"
        used.add(name)
        names.append(name)
    return names


def _quat_wxyz(rotation: np.ndarray) -> np.ndarray:
    """MuJoCo quaternion ``(w, x, y, z)`` of a rotation matrix."""
    quat = pin.Quaternion(np.asarray(rotation, dtype=float)).coeffs()  # (x, y, z, w)
    return np.array([quat[3], quat[0], quat[1], quat[2]])


def _add_bodies(spec: mujoco.MjSpec, robot: Robot, kinds: list[str]) -> list[mujoco.MjsBody]:
    """Add one body (with its joint and inertia) per Pinocchio joint; index 0 is the world."""
    model = robot.model
    bodies: list[mujoco.MjsBody] = [spec.worldbody]
    names = _body_names(robot)
    for j in range(1, model.njoints):
        kind = kinds[j - 1]
        joint = model.joints[j]
        placement = model.jointPlacements[j]
        body = bodies[model.parents[j]].add_body(
            name=names[j],
            pos=np.array(placement.translation, dtype=float),
            quat=_quat_wxyz(placement.rotation),
        )
        inertia = model.inertias[j]
        body.explicitinertial = True
        body.mass = float(inertia.mass)
        body.ipos = np.array(inertia.lever, dtype=float)
        moments, axes = _principal_inertia(np.asarray(inertia.inertia, dtype=float))
        body.inertia = moments
        body.iquat = _quat_wxyz(axes)
        name = model.names[j]
        if kind == "free":
            body.add_freejoint(name=name)
            bodies.append(body)
            continue
        mj_joint = body.add_joint(name=name)
        v = joint.idx_v
        _set_damping(mj_joint, float(model.damping[v]))
        mj_joint.frictionloss = float(model.friction[v])
        mj_joint.armature = float(model.armature[v])
        mj_joint.limited = mujoco.mjtLimited.mjLIMITED_FALSE
        if kind == "ball":
            mj_joint.type = mujoco.mjtJoint.mjJNT_BALL
        else:
            linear, angular = _motion_axis(model, j)
            if kind == "slide":
                mj_joint.type, axis = mujoco.mjtJoint.mjJNT_SLIDE, linear
            else:
                mj_joint.type, axis = mujoco.mjtJoint.mjJNT_HINGE, angular
            mj_joint.axis = axis
            lower = float(model.lowerPositionLimit[joint.idx_q])
            upper = float(model.upperPositionLimit[joint.idx_q])
            if kind != "continuous" and math.isfinite(lower) and math.isfinite(upper):
                if lower < upper:
                    mj_joint.limited = mujoco.mjtLimited.mjLIMITED_TRUE
                    mj_joint.range = [lower, upper]
        bodies.append(body)
    return bodies


def _set_damping(joint: mujoco.MjsJoint, damping: float) -> None:
    """Set a joint's linear damping [N m s/rad or N s/m].

    It is a scalar in MuJoCo 3 and the first polynomial coefficient in MuJoCo 4.
    """
    current = joint.damping
    if np.ndim(current) == 0:
        joint.damping = damping
    else:
        values = np.zeros(np.shape(current))
        values[0] = damping
        joint.damping = values


def _principal_inertia(inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments (negative ones clamped to 0) and axes (a rotation) of an inertia."""
    moments, axes = np.linalg.eigh((inertia + inertia.T) / 2.0)
    if np.linalg.det(axes) < 0.0:
        axes[:, 2] = -axes[:, 2]
    return np.maximum(moments, 0.0), axes


def _balance_inertias(spec: mujoco.MjSpec, robot: Robot) -> None:
    """Let MuJoCo repair physically impossible inertias, with a warning naming them.

    A rotational inertia with a negative principal moment is clamped to zero (then raised to
    :data:`BOUND_INERTIA`), and one that breaks the triangle inequality is balanced by MuJoCo's
    ``balanceinertia``.
    """
    model = robot.model
    bad = []
    for j in range(1, model.njoints):
        if model.inertias[j].mass <= 0.0:
            continue
        moments = np.sort(np.linalg.eigvalsh(np.asarray(model.inertias[j].inertia)))
        scale = max(float(moments[2]), 1e-300)
        if moments[0] < -1e-12 * scale or moments[0] + moments[1] < moments[2] - 1e-9 * scale:
            bad.append(model.names[j])
    if bad:
        spec.compiler.balanceinertia = True
        warnings.warn(
            f"Robot {robot.name!r}: the inertia of the bodies of joints {', '.join(bad)} is not "
            "physically possible (a negative principal moment, or the triangle inequality "
            "broken); MuJoCo uses a repaired one, so the simulation differs from the Pinocchio "
            "model there.",
            stacklevel=3,
        )


# ---------------------------------------------------------------------------------------------
# Geometry


def _geometry_model(robot: Robot, kind: pin.GeometryType) -> pin.GeometryModel:
    """Read the robot's collision or visual geometry with Pinocchio."""
    model = robot.model
    dirs = list(robot.package_dirs)
    try:
        if robot.urdf_path is not None:
            return pin.buildGeomFromUrdf(model, str(robot.urdf_path), kind, package_dirs=dirs)
        if robot.urdf_string is not None:
            return pin.buildGeomFromUrdfString(model, robot.urdf_string, kind, package_dirs=dirs)
    except Exception as exc:
        raise RobotDescriptionError(
            f"Pinocchio cannot read the geometry of robot {robot.name!r}: {exc}"
        ) from exc
    return pin.GeometryModel()


def _add_geometry(
    spec: mujoco.MjSpec,
    robot: Robot,
    bodies: list[mujoco.MjsBody],
    contact: ContactParameters,
    collisions: str,
) -> tuple[dict[str, tuple[str, ...]], list[str]]:
    """Add the robot's geoms; return geom name -> owning frames, and the skipped geometries."""
    if collisions == "none":
        return {}, []
    kind = pin.GeometryType.VISUAL if collisions == "visual" else pin.GeometryType.COLLISION
    geometry = _geometry_model(robot, kind)
    model = robot.model
    contype, conaffinity = _ROBOT_SELF_BITS if contact.self_collisions else _ROBOT_BITS
    placements = _frames_in_joints(model)
    owners: dict[str, tuple[str, ...]] = {}
    skipped: list[str] = []
    meshes: dict[tuple[str, tuple[float, ...]], str] = {}
    used = set()
    for obj in geometry.geometryObjects:
        shape = obj.geometry
        shape_type = type(shape).__name__
        size: list[float] | None = None
        mesh_name = None
        if shape_type == "Box":
            geom_type, size = mujoco.mjtGeom.mjGEOM_BOX, list(shape.halfSide)
        elif shape_type == "Sphere":
            geom_type, size = mujoco.mjtGeom.mjGEOM_SPHERE, [shape.radius, 0.0, 0.0]
        elif shape_type == "Cylinder":
            geom_type, size = mujoco.mjtGeom.mjGEOM_CYLINDER, [shape.radius, shape.halfLength, 0]
        elif shape_type == "Capsule":
            geom_type, size = mujoco.mjtGeom.mjGEOM_CAPSULE, [shape.radius, shape.halfLength, 0]
        elif shape_type == "Ellipsoid":
            geom_type, size = mujoco.mjtGeom.mjGEOM_ELLIPSOID, list(shape.radii)
        elif shape_type.startswith(("BVHModel", "Convex")) and collisions != "primitives":
            path = Path(obj.meshPath)
            if _readable_mesh(path):
                scale = tuple(float(s) for s in obj.meshScale)
                key = (str(path), scale)
                if key not in meshes:
                    meshes[key] = f"mesh_{len(meshes)}_{path.stem}"
                    mesh = spec.add_mesh(name=meshes[key], file=str(path), scale=list(scale))
                    # Mesh inertia is unused (inertias come from Pinocchio); a surface inertia
                    # compiles even for open or flat meshes.
                    mesh.inertia = mujoco.mjtMeshInertia.mjMESH_INERTIA_SHELL
                geom_type, mesh_name = mujoco.mjtGeom.mjGEOM_MESH, meshes[key]
            else:
                geom_type = None
        elif shape_type.startswith(("BVHModel", "Convex")):
            continue  # "primitives": meshes are left out on purpose
        else:
            geom_type = None
        if geom_type is None:
            skipped.append(obj.name)
            continue
        name = obj.name
        while name in used or name.startswith(TERRAIN_PREFIX):
            name = f"robot_{name}"
        used.add(name)
        placement = obj.placement
        geom = bodies[obj.parentJoint].add_geom(
            name=name,
            type=geom_type,
            pos=np.array(placement.translation, dtype=float),
            quat=_quat_wxyz(placement.rotation),
        )
        if size is not None:
            geom.size = np.array(size, dtype=float)
        if mesh_name is not None:
            geom.meshname = mesh_name
        _set_contact(geom, contact, contype, conaffinity)
        geom.group = ROBOT_GROUP
        geom.rgba = [0.6, 0.6, 0.65, 1.0]
        parent = model.frames[obj.parentFrame].name
        located = [
            frame
            for frame, (joint, point) in placements.items()
            if joint == obj.parentJoint
            and frame != parent
            and size is not None
            and _inside(geom_type, size, placement.actInv(point))
        ]
        owners[name] = (parent, *located)
    if skipped:
        warnings.warn(
            f"Robot {robot.name!r}: {len(skipped)} geometries cannot be simulated and are left "
            "out (unsupported shape or mesh format; MuJoCo reads OBJ and binary STL): "
            + ", ".join(skipped),
            stacklevel=3,
        )
    return owners, skipped


def _readable_mesh(path: Path) -> bool:
    """Whether MuJoCo can read a mesh file: OBJ, or binary STL with 1 to 200000 faces."""
    suffix = path.suffix.lower()
    if suffix not in MESH_FORMATS or not path.is_file():
        return False
    if suffix != ".stl":
        return True
    try:
        with path.open("rb") as stream:
            header = stream.read(84)
        size = path.stat().st_size
    except OSError:
        return False
    if len(header) < 84:
        return False
    faces = int.from_bytes(header[80:84], "little")
    return size == 84 + 50 * faces and 1 <= faces <= MAX_STL_FACES  # ASCII STL is not read


def _frames_in_joints(model: pin.Model) -> dict[str, tuple[int, np.ndarray]]:
    """Parent joint and origin (joint frame) of each frame name but movable joints' frames."""
    out: dict[str, tuple[int, np.ndarray]] = {}
    for frame in model.frames:
        if frame.name not in out and frame.type != pin.FrameType.JOINT:
            out[frame.name] = (frame.parentJoint, np.array(frame.placement.translation))
    return out


def _inside(geom_type: mujoco.mjtGeom, size: list[float], point: np.ndarray) -> bool:
    """Whether ``point`` (geom frame) lies inside or on the surface of a primitive."""
    tol = 1e-6 * max(1.0, max(abs(s) for s in size))
    x, y, z = (float(c) for c in point)
    if geom_type == mujoco.mjtGeom.mjGEOM_SPHERE:
        return math.sqrt(x * x + y * y + z * z) <= size[0] + tol
    if geom_type == mujoco.mjtGeom.mjGEOM_BOX:
        return all(abs(c) <= s + tol for c, s in zip((x, y, z), size, strict=True))
    if geom_type == mujoco.mjtGeom.mjGEOM_CYLINDER:
        return math.hypot(x, y) <= size[0] + tol and abs(z) <= size[1] + tol
    if geom_type == mujoco.mjtGeom.mjGEOM_CAPSULE:
        zc = min(max(z, -size[1]), size[1])
        return math.sqrt(x * x + y * y + (z - zc) ** 2) <= size[0] + tol
    if geom_type == mujoco.mjtGeom.mjGEOM_ELLIPSOID:
        return (x / size[0]) ** 2 + (y / size[1]) ** 2 + (z / size[2]) ** 2 <= 1.0 + tol
    return False


def _set_contact(
    geom: mujoco.MjsGeom, contact: ContactParameters, contype: int, conaffinity: int
) -> None:
    geom.contype = contype
    geom.conaffinity = conaffinity
    geom.condim = contact.condim
    geom.friction = [contact.friction, contact.torsional_friction, contact.rolling_friction]
    geom.solref = list(contact.solref)
    geom.solimp = list(contact.solimp)
    geom.margin = contact.margin


def _add_sites(spec: mujoco.MjSpec, robot: Robot, bodies: list[mujoco.MjsBody]) -> dict[str, str]:
    """Add a site per Pinocchio frame name; return frame name -> site name."""
    sites: dict[str, str] = {}
    for frame in robot.model.frames:
        if frame.name in sites:
            continue
        sites[frame.name] = frame.name
        placement = frame.placement
        site = bodies[frame.parentJoint].add_site(
            name=frame.name,
            pos=np.array(placement.translation, dtype=float),
            quat=_quat_wxyz(placement.rotation),
        )
        site.size = [0.005, 0.005, 0.005]
        site.group = SITE_GROUP
    return sites


def _add_terrain(spec: mujoco.MjSpec, terrain: Terrain, contact: ContactParameters) -> list[str]:
    """Add the terrain geoms to the world body; return their names."""
    world = spec.worldbody
    contype, conaffinity = _TERRAIN_BITS
    names = []
    if terrain.is_flat:
        height = float(terrain.points[0, 1])
        geom = world.add_geom(
            name=f"{TERRAIN_PREFIX}plane",
            type=mujoco.mjtGeom.mjGEOM_PLANE,
            pos=[0.0, 0.0, height],
            size=[0.0, 0.0, 0.05],
        )
        _set_contact(geom, contact, contype, conaffinity)
        geom.group = TERRAIN_GROUP
        geom.rgba = [0.45, 0.5, 0.45, 1.0]
        return [geom.name]
    segments = terrain.segments(TERRAIN_RUN)
    for i, ((x0, z0), (x1, z1)) in enumerate(segments):
        dx, dz = x1 - x0, z1 - z0
        length = math.hypot(dx, dz)
        angle = math.atan2(dz, dx)  # slope, uphill positive
        normal = np.array([-math.sin(angle), 0.0, math.cos(angle)])
        centre = np.array([(x0 + x1) / 2.0, 0.0, (z0 + z1) / 2.0]) - normal * (
            TERRAIN_THICKNESS / 2.0
        )
        if i == 0:
            label = "run_in"
        elif i == len(segments) - 1:
            label = "run_out"
        else:
            label = f"segment_{i - 1}"
        # A rotation by -angle about y takes the box's x axis onto the segment direction.
        quat = [math.cos(-angle / 2.0), 0.0, math.sin(-angle / 2.0), 0.0]
        geom = world.add_geom(
            name=f"{TERRAIN_PREFIX}{label}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            pos=centre,
            quat=quat,
            size=[length / 2.0, terrain.width / 2.0, TERRAIN_THICKNESS / 2.0],
        )
        _set_contact(geom, contact, contype, conaffinity)
        geom.group = TERRAIN_GROUP
        geom.rgba = [0.45, 0.5, 0.45, 1.0] if i % 2 else [0.5, 0.55, 0.5, 1.0]
        names.append(geom.name)
    return names
