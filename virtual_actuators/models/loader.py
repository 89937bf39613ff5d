"""Load robots by name or from any URDF file, with Pinocchio, and their SRDF's poses.

An SRDF that cannot be read is ignored.
"""

from __future__ import annotations

import importlib.util
import logging
import os
import re
import sys
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pinocchio as pin

from virtual_actuators.exceptions import (
    InvalidInputError,
    RobotDescriptionError,
    RobotNotFoundError,
    VirtualActuatorError,
)
from virtual_actuators.models import catalog
from virtual_actuators.models.catalog import ROBOTS_PATH_ENV, list_robots, robots_dir
from virtual_actuators.models.millipede import millipede
from virtual_actuators.models.robot import Robot
from virtual_actuators.models.validation import listed, parse_xml, physics_problems, validate_urdf

__all__ = ["ROBOTS_PATH_ENV", "list_robots", "load_robot", "robots_dir"]

_logger = logging.getLogger(__name__)

# The words of legs and of flying robots, which make guess_floating_base float a robot's base.
_FLOATING_WORDS = frozenset(
    "foot feet sole soles toe toes ankle ankles leg legs knee knees hip hips thigh thighs "
    "shin shins shank shanks calf calves "
    "flying quadrotor quadcopter multirotor hexarotor hexacopter octocopter drone uav "
    "rotor rotors propeller propellers".split()
)
_WORD = re.compile(r"[A-Z]+(?=[A-Z][a-z])|[A-Z]?[a-z]+|[A-Z]+")


def load_robot(name_or_path: str | os.PathLike[str], floating_base: bool | None = None) -> Robot:
    """Load a robot by name or from a URDF file.

    Args:
        name_or_path: A path to a URDF file (a `os.PathLike`, or a string that contains a
            path separator, starts with ``~`` or ends in ``.urdf`` / ``.xml``; or a folder
            holding one URDF), or a name of [`list_robots`][] (``include_aliases=True``).
        floating_base: True for a free-flyer root joint (``q`` starts with ``x y z qx qy qz
            qw``), False for a base welded to the world, None to guess
            (`guess_floating_base`).

    Returns:
        The robot with its Pinocchio model and data, its URDF text and its SRDF poses, named
        as asked (``load_robot("talos").name`` is ``"talos"``), or the file stem for a path.

    Raises:
        RobotNotFoundError: If the file does not exist or the file system refuses to look it up,
            or no robot has this name (the message lists the closest names and aliases).
        RobotDescriptionError: If the URDF is not well-formed XML, is not a valid URDF,
            describes an impossible robot (see `physics_problems`; the message names each
            offending link or joint, its value and what is valid), or Pinocchio cannot build a
            model from it.
        InvalidInputError: If ``name_or_path`` is neither a string nor a path, or is empty, or
            ``floating_base`` is not True, False or None.
    """
    if floating_base is not None and not isinstance(floating_base, bool):
        raise InvalidInputError(
            f"floating_base must be True, False or None, got {floating_base!r}."
        )
    path = catalog.as_path(name_or_path)
    if path is not None:
        return _load_path(path, floating_base)

    name = str(name_or_path).strip()
    if name == "millipede":
        return millipede(100, floating_base=True if floating_base is None else floating_base)

    for folder in catalog.local_dirs():
        found = catalog.find_local(folder, name)
        if found is not None and found.name == "__init__.py":
            return _load_module_robot(name, found, floating_base)
        if found is not None:
            found = found.resolve()
            return _load_urdf(
                name, found, floating_base, catalog.package_dirs_for(found), validate=False
            )

    index = catalog.example_robot_data()
    if name in index.broken:
        raise RobotDescriptionError(
            f"example-robot-data ships {name}.urdf but it cannot be loaded: {index.broken[name]}."
        )
    stem = name if name in index.robots else catalog.aliases().get(name)
    if stem is not None:
        share = [str(index.share)] if index.share is not None else []
        return _load_urdf(name, index.robots[stem], floating_base, share, validate=False)
    raise RobotNotFoundError(
        f"No robot named {catalog.shown_name(name)}. {catalog.suggest_robots(name)} Pass a path "
        "to load any other URDF file."
    )


def _load_path(path: Path, floating_base: bool | None) -> Robot:
    """Load a URDF given by path, validating it first."""
    try:
        if not path.exists():
            where = "" if path.is_absolute() else f" (absolute path {path.absolute()})"
            raise RobotNotFoundError(f"No URDF file at {path}{where}.")
        if path.is_dir():
            path = catalog.urdf_in_folder(path)
    except OSError as exc:  # a name too long for the file system, a folder that cannot be read
        raise RobotNotFoundError(
            f"load_robot(name_or_path={catalog.shown_name(path)}): no URDF file can be read "
            f"there ({exc.strerror or exc})."
        ) from None
    if path.suffix.lower() == ".xacro":
        raise RobotDescriptionError(
            f"{path} is a xacro file: expand it into a URDF first (xacro {path.name} > robot.urdf)."
        )
    return _load_urdf(
        path.stem, path, floating_base, catalog.package_dirs_for(path.resolve()), validate=True
    )


def _load_urdf(
    name: str, path: Path, floating_base: bool | None, package_dirs: list[str], validate: bool
) -> Robot:
    """Build the robot of one URDF file (`validate_urdf` first, or to explain a rejection)."""
    path = path.resolve()
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise RobotDescriptionError(f"Cannot read the URDF file {path}: {exc}") from exc
    root = parse_xml(path, text)  # the physics checks always; strict but on curated files
    problems, tolerated = physics_problems(root, strict=not catalog.is_curated(path))
    if problems:
        raise RobotDescriptionError(f"{path} describes an impossible robot:{listed(problems)}")
    for problem in tolerated:
        _logger.debug("%s (tolerated in a curated example-robot-data file): %s", path, problem)
    if validate:
        validate_urdf(path, root)
    if floating_base is None:
        floating_base = guess_floating_base(root, path.stem)

    try:
        root_joint = (pin.JointModelFreeFlyer(),) if floating_base else ()
        model = pin.buildModelFromUrdf(str(path), *root_joint)
    except Exception as exc:  # Pinocchio raises ValueError or RuntimeError on URDFs it rejects
        if not validate:
            validate_urdf(path, root)  # raises with a precise message when it finds the problem
        raise RobotDescriptionError(
            f"Pinocchio could not build a model from {path}: {exc}"
        ) from exc

    model.name = name  # messages name the robot as the user did ("solo12"), not the URDF ("solo")
    srdf = find_srdf(path)
    configurations = reference_configurations(model, srdf)
    return Robot(
        name=name,
        model=model,
        urdf_path=path,
        urdf_string=text,
        package_dirs=package_dirs,
        floating_base=floating_base,
        reference_configurations=configurations,
        default_pose=default_pose(configurations),
        passive_joints=passive_joints(model, srdf),
    )


def _load_module_robot(name: str, init: Path, floating_base: bool | None) -> Robot:
    """Build a robot from a ``robots/NAME/__init__.py`` hook that defines ``build_robot``."""
    module_name = f"virtual_actuators._robot_hooks.{name}"
    spec = importlib.util.spec_from_file_location(
        module_name, init, submodule_search_locations=[str(init.parent)]
    )
    if spec is None or spec.loader is None:
        raise RobotDescriptionError(f"Cannot import the robot module {init}.")
    module = importlib.util.module_from_spec(spec)
    sys.modules[module_name] = module
    try:
        spec.loader.exec_module(module)
        build = getattr(module, "build_robot", None)
        if not callable(build):
            raise RobotDescriptionError(
                f"{init} defines no build_robot(floating_base=None) function and the folder "
                f"has no {name}.urdf."
            )
        robot = build(floating_base=floating_base)
    except VirtualActuatorError:
        raise
    except Exception as exc:
        raise RobotDescriptionError(
            f"Building robot {name!r} with {init} failed: {type(exc).__name__}: {exc}"
        ) from exc
    finally:
        sys.modules.pop(module_name, None)
    if not isinstance(robot, Robot):
        raise RobotDescriptionError(
            f"{init}: build_robot() returned {type(robot).__name__}, not a Robot."
        )
    return robot


def guess_floating_base(root: ET.Element, stem: str) -> bool:
    """Guess whether a URDF describes a legged or flying robot (``floating_base=None``).

    The base floats when a word of a link or joint name of ``root`` (the ``<robot>`` element),
    the robot's name or the file stem ``stem`` is a leg or flying word (`_FLOATING_WORDS`);
    names split into words at ``_``, digits and camel-case humps. A URDF whose root link is
    ``world`` is fixed.
    """
    links = [link.get("name", "") for link in root.iter("link")]
    joints = root.findall("joint")
    children = {child.get("link") for joint in joints for child in joint.iter("child")}
    roots = [link for link in links if link not in children]
    if roots == ["world"]:
        return False
    names = [*links, *(joint.get("name", "") for joint in joints), root.get("name", ""), stem]
    words = {word.lower() for name in names for word in _WORD.findall(name)}
    return bool(words & _FLOATING_WORDS)


#: Group states of the SRDF that [`Robot.neutral`][] prefers, best first.
DEFAULT_POSE_NAMES = ("standing", "half_sitting", "straight_standing", "default", "home", "neutral")


def find_srdf(urdf: Path) -> Path | None:
    """The SRDF of a URDF (same stem, else the longest stem prefix), or None."""
    near = (urdf.parent, urdf.parent / "srdf", urdf.parent.parent / "srdf")
    folders = [folder for folder in near if folder.is_dir()]
    for folder in folders:
        exact = folder / f"{urdf.stem}.srdf"
        if exact.is_file():
            return exact
    prefixes = [
        candidate
        for folder in folders
        for candidate in sorted(folder.glob("*.srdf"))
        if urdf.stem.startswith(candidate.stem)
    ]
    return max(prefixes, key=lambda candidate: len(candidate.stem), default=None)


def reference_configurations(model: pin.Model, srdf: Path | None) -> dict[str, np.ndarray]:
    """Read the SRDF's group states into the model; return them (empty if it cannot be read)."""
    if srdf is None:
        return {}
    try:
        pin.loadReferenceConfigurations(model, str(srdf), False)
        entries = [
            (entry.key(), np.array(entry.data(), dtype=float))
            for entry in model.referenceConfigurations
        ]
    except Exception as exc:  # a broken SRDF must never stop the robot from loading
        _logger.debug("Ignoring the SRDF %s: %s", srdf, exc)
        return {}
    return {key: q for key, q in entries if q.shape == (model.nq,) and np.all(np.isfinite(q))}


def passive_joints(model: pin.Model, srdf: Path | None) -> tuple[str, ...]:
    """The SRDF's ``<passive_joint name="..."/>`` entries that are joints of the model, in order."""
    if srdf is None:
        return ()
    try:
        root = ET.parse(srdf).getroot()
    except (ET.ParseError, OSError) as exc:
        _logger.debug("Ignoring the SRDF %s: %s", srdf, exc)
        return ()
    declared = {element.get("name", "") for element in root.iter("passive_joint")}
    joints = list(model.names)[1:]
    for name in sorted(declared - set(joints)):
        _logger.debug("%s: passive joint %r is not a joint of the model; ignored", srdf, name)
    return tuple(name for name in joints if name in declared)


def default_pose(configurations: Mapping[str, np.ndarray]) -> str | None:
    """Pick the pose that [`Robot.neutral`][] returns."""
    preferred = (name for name in DEFAULT_POSE_NAMES if name in configurations)
    return next(preferred, next(iter(configurations), None))
