"""The robots that load by name, described: kind, degrees of freedom, legs and feet, aliases.

An example-robot-data robot's kind comes from its description folder (`KINDS`), any other's
from its model; degrees of freedom are ``nv`` without a free-flyer's 6 and the passive joints.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

from virtual_actuators.exceptions import FrameNotFoundError
from virtual_actuators.models.catalog import aliases, example_robot_data, list_robots
from virtual_actuators.models.feet import find_feet
from virtual_actuators.models.loader import load_robot

#: Kind and maker of the robots in each example-robot-data description folder.
KINDS: dict[str, tuple[str, str]] = {
    "a1_description": ("quadruped", "Unitree A1"),
    "alex_description": ("humanoid upper body", "IHMC / Boardwalk Robotics Alex"),
    "alexander_description": ("biped", "IHMC Alexander, lower body"),
    "allegro_hand_description": ("hand", "Wonik Allegro hand"),
    "anymal_b_simple_description": ("quadruped", "ANYbotics ANYmal B"),
    "anymal_c_simple_description": ("quadruped", "ANYbotics ANYmal C"),
    "asr_twodof_description": ("arm", "two-joint planar arm"),
    "b1_description": ("quadruped", "Unitree B1"),
    "baxter_description": ("dual arm", "Rethink Robotics Baxter"),
    "bolt_description": ("biped", "ODRI Bolt"),
    "borinot_description": ("aerial manipulator", "Borinot flying arm"),
    "centauro_description": ("centaur", "IIT Centauro: four wheeled legs, two arms"),
    "double_pendulum_description": ("pendulum", "double pendulum"),
    "finger_edu_description": ("finger", "ODRI / TriFinger finger"),
    "g1_description": ("humanoid", "Unitree G1"),
    "go1_description": ("quadruped", "Unitree Go1"),
    "go2_description": ("quadruped", "Unitree Go2"),
    "hector_description": ("aerial", "Hector quadrotor"),
    "hextilt_description": ("aerial manipulator", "tilted hexarotor with an arm"),
    "human_description": ("humanoid", "human body model"),
    "hyq_description": ("quadruped", "IIT HyQ"),
    "icub_description": ("humanoid", "IIT iCub"),
    "iris_description": ("aerial", "3DR Iris quadrotor"),
    "kinova_description": ("arm", "Kinova arm"),
    "laikago_description": ("quadruped", "Unitree Laikago"),
    "panda_description": ("arm", "Franka Emika Panda"),
    "pr2_description": ("mobile manipulator", "Willow Garage PR2"),
    "quadruped_description": ("quadruped", "generic quadruped"),
    "romeo_description": ("humanoid", "Aldebaran Romeo"),
    "simple_humanoid_description": ("humanoid", "simple humanoid"),
    "so_arm_description": ("arm", "SO-ARM (LeRobot)"),
    "solo_description": ("quadruped", "ODRI Solo"),
    "talos_data": ("humanoid", "PAL Robotics TALOS"),
    "tiago_description": ("mobile manipulator", "PAL Robotics TIAGo"),
    "tiago_pro_description": ("mobile manipulator", "PAL Robotics TIAGo Pro"),
    "ur_description": ("arm", "Universal Robots"),
    "xarm_description": ("arm", "UFactory xArm 7"),
    "z1_description": ("arm", "Unitree Z1"),
}

#: Robots whose kind differs from their folder's.
_STEM_KINDS = {
    "anymal-kinova": "legged manipulator",
    "b1-z1": "legged manipulator",
    "talos_left_arm": "arm",
}

_LEGS = {"quadruped": 4, "legged manipulator": 4, "centaur": 4, "biped": 2, "humanoid": 2}


@dataclass(frozen=True)
class RobotInfo:
    """One robot that loads by name.

    Attributes:
        name: The name [`load_robot`][] takes.
        aliases: Its common names (`ALIASES`).
        kind: ``quadruped``, ``biped``, ``humanoid``, ``arm``, ``hand``, ``aerial``...
        maker: Maker and model, when known (example-robot-data robots), else ``""``.
        dof: Actuated degrees of freedom.
        floating_base: Whether it loads with a free-flyer root joint.
        legs: Number of legs (from its kind, else from its feet), or None.
        feet: Its foot frames as `find_feet` finds them (the walkers' and the balancer's), or none.
        source: ``example-robot-data``, ``generated`` or the folder it comes from.
    """

    name: str
    aliases: tuple[str, ...]
    kind: str
    maker: str
    dof: int
    floating_base: bool
    legs: int | None
    feet: tuple[str, ...]
    source: str

    @property
    def description(self) -> str:
        """One line: kind, maker, degrees of freedom, legs and feet."""
        parts = [self.kind + (f" ({self.maker})" if self.maker else ""), f"{self.dof} DoF"]
        if self.floating_base:
            parts.append("floating base")
        if self.legs:
            parts.append(f"{self.legs} legs")
        if len(self.feet) > 6:
            parts.append(f"feet {' '.join(self.feet[:3])} ... {self.feet[-1]} ({len(self.feet)})")
        elif self.feet:
            parts.append("feet " + " ".join(self.feet))
        return ", ".join(parts)


def _describe(name: str) -> RobotInfo:
    """Load robot ``name`` and describe it."""
    targets = aliases()
    stem = targets.get(name, name)
    robot = load_robot(name)
    index = example_robot_data()
    urdf = index.robots.get(stem)
    kind, maker, source = "", "", "generated" if robot.urdf_path is None else ""
    if urdf is not None and index.share is not None:
        folder = urdf.relative_to(index.share / "example-robot-data" / "robots").parts[0]
        kind, maker = KINDS.get(folder, ("", ""))
        kind = _STEM_KINDS.get(stem, kind)
        source = "example-robot-data"
    elif robot.urdf_path is not None:
        source = str(robot.urdf_path.parent)
    try:  # the feet the walkers and the balancer find (`find_feet`), if it has any
        feet = find_feet(robot).feet
    except FrameNotFoundError:
        feet = ()
    model = robot.model
    dof = model.nv - (6 if robot.floating_base else 0) - len(robot.passive_joints)
    if not kind and feet:
        kind = {1: "hopper", 2: "biped", 4: "quadruped", 6: "hexapod"}.get(
            len(feet), f"{len(feet)}-legged"
        )
    elif not kind:
        kind = "floating base" if robot.floating_base else "fixed base"
    legs = _LEGS.get(kind, len(feet) or None)
    return RobotInfo(
        name=name,
        aliases=tuple(sorted(alias for alias, target in targets.items() if target == stem)),
        kind=kind,
        maker=maker,
        dof=dof,
        floating_base=robot.floating_base,
        legs=legs if kind not in ("arm", "hand", "finger") else None,
        feet=feet,
        source=source,
    )


def describe_robots(names: Iterable[str] | None = None) -> list[RobotInfo]:
    """One [`RobotInfo`][] per name (default: every name of [`list_robots`][]), in order.

    Loads each robot: about 1 s for all of example-robot-data.

    Raises:
        RobotNotFoundError: A name is not known.
        RobotDescriptionError: A robot cannot be loaded.
    """
    return [_describe(name) for name in (list_robots() if names is None else names)]


def robot_table(infos: Iterable[RobotInfo]) -> str:
    """The robots as a plain-text table (name, aliases, description), columns aligned."""
    rows = [("name", "aliases", "description")]
    rows += [(info.name, " ".join(info.aliases), info.description) for info in infos]
    widths = [max(len(row[k]) for row in rows) for k in range(2)]
    return "\n".join(
        f"{name:<{widths[0]}}  {alias:<{widths[1]}}  {text}".rstrip() for name, alias, text in rows
    )
