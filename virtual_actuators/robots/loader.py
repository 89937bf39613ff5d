"""Load robots by name or from any URDF file, with Pinocchio.

:func:`load_robot` accepts a path to a URDF file or the name of a known robot. Names are resolved
in this order:

1. ``"millipede"``: the generated robot of :func:`~virtual_actuators.robots.millipede.millipede`
   (100 legs).
2. The folders listed in the environment variable ``VIRTUAL_ACTUATORS_ROBOTS`` (separated by
   :data:`os.pathsep`), then the repository's top-level ``robots/`` folder (:data:`robots_dir`).
   In each folder, robot ``NAME`` is ``NAME.urdf``, ``NAME/NAME.urdf``, ``NAME/urdf/NAME.urdf``
   or ``NAME/robots/NAME.urdf``, with an optional SRDF beside it (see below); or a Python package
   ``NAME/__init__.py`` (with no ``NAME.urdf``) that defines
   ``build_robot(floating_base: bool | None = None) -> Robot`` for robots generated in code.
3. The URDF files shipped by example-robot-data, by file stem (``solo12``, ``talos_reduced``,
   ``ur5_robot``, ...). Two files are called ``anymal.urdf``: ``anymal`` is ANYmal B and
   ``anymal_c`` is ANYmal C. ``ur3.urdf`` is an empty xacro stub that no URDF parser can load:
   such a stub is left out of :func:`list_robots` and its name resolves to ``<stem>_robot.urdf``
   from the same folder when that exists (``ur3`` loads ``ur3_robot.urdf``).

Floating or fixed base: ``floating_base=None`` guesses from the description. The base floats
(a free-flyer root joint) when a link or joint name, the robot's name or the file stem contains
a leg word (foot, feet, sole, toe, ankle, leg, knee, hip, thigh, shin, shank, calf) or a flying
word (flying, quadrotor, quadcopter, multirotor, hexarotor, hexacopter, octocopter, drone, uav,
rotor, propeller), and is fixed otherwise (arms, hands, grippers, pendulums, wheeled bases). Names
are split into words at ``_``, digits and camel-case humps, so ``base_footprint`` or ``allegro`` do
not count. A URDF whose root link is ``world`` is always fixed. Pass ``floating_base`` explicitly to
override the guess.

Standing pose: the SRDF of a URDF is ``STEM.srdf`` in the URDF's folder, in a ``srdf/`` folder
beside it or in the ``srdf/`` folder of its parent (the layout of example-robot-data); failing
that, the SRDF in those folders whose stem is the longest prefix of the URDF stem (``solo12`` uses
``solo.srdf``, ``talos_reduced`` uses ``talos.srdf``). Its ``group_state`` entries become
:attr:`Robot.reference_configurations`, and :meth:`Robot.neutral` returns the first of
``standing``, ``half_sitting``, ``straight_standing``, ``default``, ``home``, ``neutral`` that
exists, else the first group state, else Pinocchio's neutral configuration. An SRDF that cannot be
read is ignored. Its ``passive_joint`` entries become :attr:`Robot.passive_joints` (joints that
no actuator drives, such as the boom of a planar biped).

A URDF given by path is checked before Pinocchio sees it (XML syntax, then the URDF structure with
``yourdfpy``: names, joint types, parent and child links, limits, a single tree), so that a broken
file gives a :class:`~virtual_actuators.exceptions.RobotDescriptionError` that says what is wrong.
``yourdfpy`` is only a validator here: it never loads meshes and never computes kinematics.

Every URDF, by path or by name, is also checked for what Pinocchio would load silently but no
robot can be, on the XML itself before Pinocchio reads it (Pinocchio loads a NaN mass as 0): a
revolute, continuous, prismatic or planar joint with a zero or non-finite axis; a negative or
non-finite mass; a non-finite inertia or a negative ``ixx``, ``iyy`` or ``izz``; a joint limit
with ``lower > upper`` or a NaN bound; an inertia that is not positive semi-definite (beyond a
round-off of ``max(1e-9 kg m^2, 1e-6 * largest principal moment)``); and ``<mimic>`` joints,
which are not supported (remove the tag, or declare an
:class:`~virtual_actuators.vocabulary.constraints.EqualTorque` design constraint to share the
effort). Each gives a :class:`~virtual_actuators.exceptions.RobotDescriptionError` naming the link
or joint, the bad value and what is valid. Zero masses, fixed joints with any axis, continuous
joints without limits and ``lower == upper`` are valid. The curated example-robot-data files are
exempt from the last two checks only: several ship gripper fingers as mimic joints (loaded as
independent joints) and ``romeo_laas_small`` and the ``tiago`` family ship inertias that are not
positive semi-definite; they load as Pinocchio loads them.
"""

from __future__ import annotations

import functools
import importlib.metadata
import importlib.util
import logging
import math
import os
import re
import sys
import sysconfig
import xml.etree.ElementTree as ET
from collections import Counter
from collections.abc import Mapping
from pathlib import Path
from types import MappingProxyType
from typing import Any, NamedTuple

import numpy as np
import pinocchio as pin

from virtual_actuators.exceptions import (
    InvalidInputError,
    RobotDescriptionError,
    RobotNotFoundError,
    VirtualActuatorError,
    suggestion,
)
from virtual_actuators.robots.millipede import millipede
from virtual_actuators.robots.robot import Robot

__all__ = ["ROBOTS_PATH_ENV", "list_robots", "load_robot", "robots_dir"]

_logger = logging.getLogger(__name__)

#: The repository's top-level folder of robot descriptions.
robots_dir: Path = Path(__file__).resolve().parents[2] / "robots"

#: Environment variable with extra robot folders (separated by ``os.pathsep``), searched first.
ROBOTS_PATH_ENV = "VIRTUAL_ACTUATORS_ROBOTS"

#: Group states that :meth:`Robot.neutral` prefers, best first.
DEFAULT_POSE_NAMES = (
    "standing",
    "half_sitting",
    "straight_standing",
    "default",
    "home",
    "neutral",
)

_LEG_WORDS = frozenset(
    "foot feet sole soles toe toes ankle ankles leg legs knee knees hip hips thigh thighs "
    "shin shins shank shanks calf calves".split()
)
_FLYING_WORDS = frozenset(
    "flying quadrotor quadcopter multirotor hexarotor hexacopter octocopter drone uav "
    "rotor rotors propeller propellers".split()
)
_WORD = re.compile(r"[A-Z]+(?=[A-Z][a-z])|[A-Z]?[a-z]+|[A-Z]+")

#: Names of example-robot-data URDFs whose stem is shipped twice: (description folder, stem).
_DUPLICATE_NAMES = {
    ("anymal_b_simple_description", "anymal"): "anymal",
    ("anymal_c_simple_description", "anymal"): "anymal_c",
}

_JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
_PATH_SUFFIXES = (".urdf", ".xml", ".xacro")
_MAX_PROBLEMS = 10
_INERTIA_KEYS = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
#: Round-off allowed on moments of inertia: relative to the largest principal moment, and [kg m^2].
_INERTIA_RTOL = 1e-6
_INERTIA_ATOL = 1e-9


# ---------------------------------------------------------------------------------------------
# Public functions


def load_robot(name_or_path: str | os.PathLike[str], floating_base: bool | None = None) -> Robot:
    """Load a robot by name or from a URDF file.

    Args:
        name_or_path: A path to a URDF file (a :class:`os.PathLike`, or a string that contains a
            path separator, starts with ``~`` or ends in ``.urdf`` / ``.xml``; a folder works
            when it holds one URDF), or a name from :func:`list_robots`.
        floating_base: True for a free-flyer root joint (``q`` starts with the base position
            and quaternion ``x y z qx qy qz qw``), False for a base welded to the world, None to
            guess: legged and flying robots float, arms and hands are fixed (see the module
            documentation).

    Returns:
        The robot with its Pinocchio model and data, its URDF text and its SRDF poses;
        ``robot.name`` is the name asked for, or the file stem for a path.

    Raises:
        RobotNotFoundError: If the file does not exist, or no robot has this name (the message
            lists the closest names).
        RobotDescriptionError: If the URDF is not well-formed XML, is not a valid URDF (the
            message names the file and what is wrong), describes an impossible robot (a zero
            joint axis, a negative or NaN mass, a non-finite, negative or not positive
            semi-definite inertia, a limit with lower > upper, a mimic joint; the message names
            each offending link or joint, its value and what is valid; see the module
            documentation for the example-robot-data exemptions), or Pinocchio cannot build a
            model from it.
        InvalidInputError: If ``name_or_path`` is neither a string nor a path, or is empty, or
            ``floating_base`` is not True, False or None.

    """
    if floating_base is not None and not isinstance(floating_base, bool):
        raise InvalidInputError(
            f"floating_base must be True, False or None, got {floating_base!r}."
        )
    path = _as_path(name_or_path)
    if path is not None:
        return _load_path(path, floating_base)

    name = str(name_or_path).strip()
    if name == "millipede":
        return millipede(100, floating_base=True if floating_base is None else floating_base)

    for folder in _local_dirs():
        found = _find_local(folder, name)
        if found is not None and found.name == "__init__.py":
            return _load_module_robot(name, found, floating_base)
        if found is not None:
            found = found.resolve()
            return _load_urdf(name, found, floating_base, _package_dirs(found), validate=False)

    index = _example_robot_data()
    if name in index.robots:
        share = [str(index.share)] if index.share is not None else []
        return _load_urdf(name, index.robots[name], floating_base, share, validate=False)
    if name in index.broken:
        raise RobotDescriptionError(
            f"example-robot-data ships {name}.urdf but it cannot be loaded: {index.broken[name]}."
        )
    raise RobotNotFoundError(
        f"No robot named {name!r}. {suggestion(name, list_robots(), 'robots')} "
        "Pass a path to load any other URDF file."
    )


def list_robots() -> list[str]:
    """List the names that :func:`load_robot` accepts without a path.

    Returns:
        Sorted names: the generated ``millipede``, the robots of :data:`robots_dir` and of the
        folders in ``VIRTUAL_ACTUATORS_ROBOTS``, and every example-robot-data URDF that can be
        loaded (its empty xacro stubs are left out).

    """
    names = {"millipede", *_example_robot_data().robots}
    for folder in _local_dirs():
        names.update(_local_names(folder))
    return sorted(names)


# ---------------------------------------------------------------------------------------------
# Finding robots


class _Index(NamedTuple):
    """The URDF files shipped by example-robot-data."""

    share: Path | None
    robots: Mapping[str, Path]
    broken: Mapping[str, str]


@functools.cache
def _example_robot_data() -> _Index:
    """Scan example-robot-data's robots folder once (the models themselves are not cached)."""
    try:
        distribution = importlib.metadata.distribution("example-robot-data")
    except importlib.metadata.PackageNotFoundError:
        return _Index(None, MappingProxyType({}), MappingProxyType({}))
    folder = Path(
        str(distribution.locate_file("cmeel.prefix/share/example-robot-data/robots"))
    ).resolve()
    if not folder.is_dir():
        return _Index(None, MappingProxyType({}), MappingProxyType({}))

    robots: dict[str, Path] = {}
    broken: dict[str, str] = {}
    for urdf in sorted(folder.rglob("*.urdf")):
        description = urdf.relative_to(folder).parts[0]
        name = _DUPLICATE_NAMES.get((description, urdf.stem), urdf.stem)
        if name in robots:
            name = f"{description.removesuffix('_description')}_{urdf.stem}"
        problem = _quick_check(urdf)
        if problem is None:
            robots[name] = urdf
        else:
            broken[name] = problem
    for name in list(broken):
        replacement = robots.get(f"{name}_robot")
        if replacement is not None:
            robots[name] = replacement
            del broken[name]
    return _Index(folder.parents[1], MappingProxyType(robots), MappingProxyType(broken))


def _quick_check(urdf: Path) -> str | None:
    """Return why a URDF surely cannot be loaded (no robot name, no link), or None."""
    try:
        for _, element in ET.iterparse(urdf, events=("start",)):
            if element.tag == "robot" and not element.get("name"):
                return "its <robot> element has no name (it is an unexpanded xacro stub)"
            if element.tag == "link":
                return None
    except (ET.ParseError, OSError) as exc:
        return f"it is not readable XML ({exc})"
    return "it declares no <link>"


def _local_dirs() -> list[Path]:
    """Folders searched for robots by name.

    ``VIRTUAL_ACTUATORS_ROBOTS`` first, then the source tree's ``robots/`` (editable installs),
    then ``<prefix>/share/virtual_actuators/robots`` (where a regular install puts them).
    """
    extra = os.environ.get(ROBOTS_PATH_ENV, "")
    folders = [Path(entry).expanduser() for entry in extra.split(os.pathsep) if entry.strip()]
    installed = Path(sysconfig.get_path("data")) / "share" / "virtual_actuators" / "robots"
    return [*folders, robots_dir, installed]


def _find_local(folder: Path, name: str) -> Path | None:
    """Return the URDF (or ``__init__.py`` hook) of robot ``name`` in ``folder``, or None."""
    if not name or name.startswith((".", "_")):
        return None
    candidates = (
        folder / f"{name}.urdf",
        folder / name / f"{name}.urdf",
        folder / name / "urdf" / f"{name}.urdf",
        folder / name / "robots" / f"{name}.urdf",
        folder / name / "__init__.py",
    )
    return next((path for path in candidates if path.is_file()), None)


def _local_names(folder: Path) -> list[str]:
    """Names of the robots in one robots folder."""
    if not folder.is_dir():
        return []
    names = []
    for entry in folder.iterdir():
        if entry.is_dir():
            name = entry.name
        elif entry.suffix == ".urdf":
            name = entry.stem
        else:
            continue
        if _find_local(folder, name) is not None:
            names.append(name)
    return names


def _as_path(name_or_path: object) -> Path | None:
    """Return the path meant by ``name_or_path``, or None if it is a robot name."""
    if isinstance(name_or_path, os.PathLike):
        return Path(os.fspath(name_or_path)).expanduser()
    if not isinstance(name_or_path, str):
        raise InvalidInputError(
            f"load_robot() needs a robot name or a path to a URDF file, got {name_or_path!r}."
        )
    text = name_or_path.strip()
    if not text:
        raise InvalidInputError("load_robot() needs a robot name or a path, got an empty string.")
    separators = {"/", os.sep, os.altsep} - {None}
    if (
        any(separator in text for separator in separators)
        or text.startswith("~")
        or Path(text).suffix.lower() in _PATH_SUFFIXES
    ):
        return Path(text).expanduser()
    return None


def _package_dirs(urdf: Path) -> list[str]:
    """Folders that ``package://`` URIs of a URDF outside example-robot-data may refer to."""
    folders: list[str] = []
    for folder in (urdf.parent, *urdf.parent.parents[:2]):
        if str(folder) not in folders:
            folders.append(str(folder))
    return folders


def _urdf_in_folder(folder: Path) -> Path:
    """Return the one URDF that a folder given as a path stands for."""
    for candidate in (
        folder / f"{folder.name}.urdf",
        folder / "urdf" / f"{folder.name}.urdf",
        folder / "robots" / f"{folder.name}.urdf",
    ):
        if candidate.is_file():
            return candidate
    found = sorted(folder.glob("*.urdf")) or sorted(folder.glob("*/*.urdf"))
    if len(found) == 1:
        return found[0]
    if not found:
        raise RobotNotFoundError(f"The folder {folder} holds no URDF file.")
    listed = ", ".join(str(path.relative_to(folder)) for path in found[:10])
    raise RobotNotFoundError(
        f"The folder {folder} holds several URDF files ({listed}): pass the file's path."
    )


# ---------------------------------------------------------------------------------------------
# Loading


def _load_path(path: Path, floating_base: bool | None) -> Robot:
    """Load a URDF given by path, validating it first."""
    if not path.exists():
        where = "" if path.is_absolute() else f" (absolute path {path.absolute()})"
        raise RobotNotFoundError(f"No URDF file at {path}{where}.")
    if path.is_dir():
        path = _urdf_in_folder(path)
    if path.suffix.lower() == ".xacro":
        raise RobotDescriptionError(
            f"{path} is a xacro file: expand it into a URDF first (xacro {path.name} > robot.urdf)."
        )
    return _load_urdf(path.stem, path, floating_base, _package_dirs(path.resolve()), validate=True)


def _load_urdf(
    name: str,
    path: Path,
    floating_base: bool | None,
    package_dirs: list[str],
    validate: bool,
) -> Robot:
    """Build the robot of one URDF file.

    The physical checks of :func:`_physics_problems` always run first, on the XML (strictly,
    except for the curated example-robot-data files). ``validate`` then runs the structural
    checks of :func:`_validate_urdf` before Pinocchio (for URDF files given by path); otherwise
    they run only to explain a file that Pinocchio rejects.

    Raises:
        RobotDescriptionError: If the file cannot be read, is not well-formed XML, describes an
            impossible robot (the message names each offending link or joint), fails the
            structural checks, or Pinocchio cannot build a model from it.

    """
    path = path.resolve()
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise RobotDescriptionError(f"Cannot read the URDF file {path}: {exc}") from exc
    root = _parse_xml(path, text)
    problems, tolerated = _physics_problems(root, strict=not _is_curated(path))
    if problems:
        raise RobotDescriptionError(f"{path} describes an impossible robot:{_listed(problems)}")
    for problem in tolerated:
        _logger.debug("%s (tolerated in a curated example-robot-data file): %s", path, problem)
    if validate:
        _validate_urdf(path, text)
    if floating_base is None:
        floating_base = _guess_floating_base(root, path.stem)

    try:
        if floating_base:
            model = pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer())
        else:
            model = pin.buildModelFromUrdf(str(path))
    except Exception as exc:  # Pinocchio raises ValueError or RuntimeError on URDFs it rejects
        if not validate:
            _validate_urdf(path, text)  # raises with a precise message when it finds the problem
        raise RobotDescriptionError(
            f"Pinocchio could not build a model from {path}: {exc}"
        ) from exc

    srdf = _find_srdf(path)
    configurations = _reference_configurations(model, srdf)
    return Robot(
        name=name,
        model=model,
        urdf_path=path,
        urdf_string=text,
        package_dirs=package_dirs,
        floating_base=floating_base,
        reference_configurations=configurations,
        default_pose=_default_pose(configurations),
        passive_joints=_passive_joints(model, srdf),
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


def _is_curated(path: Path) -> bool:
    """Whether ``path`` (resolved) is one of the URDF files shipped by example-robot-data."""
    index = _example_robot_data()
    if index.share is None:
        return False
    return path.is_relative_to(index.share / "example-robot-data" / "robots")


def _guess_floating_base(root: ET.Element, stem: str = "") -> bool:
    """Guess whether a URDF describes a legged or flying robot (see the module documentation).

    Args:
        root: The ``<robot>`` element of the URDF.
        stem: The URDF file stem, whose words count as well.

    Returns:
        True for a floating base, False for a fixed one.

    """
    links = [link.get("name", "") for link in root.iter("link")]
    joints = root.findall("joint")
    children = {child.get("link") for joint in joints for child in joint.iter("child")}
    roots = [link for link in links if link not in children]
    if roots == ["world"]:
        return False
    names = [*links, *(joint.get("name", "") for joint in joints), root.get("name", ""), stem]
    words = {word.lower() for name in names for word in _WORD.findall(name)}
    return bool(words & (_LEG_WORDS | _FLYING_WORDS))


# ---------------------------------------------------------------------------------------------
# SRDF poses


def _find_srdf(urdf: Path) -> Path | None:
    """Return the SRDF that goes with a URDF (same stem, else the longest stem prefix), or None."""
    folders = [urdf.parent, urdf.parent / "srdf", urdf.parent.parent / "srdf"]
    folders = [folder for folder in folders if folder.is_dir()]
    for folder in folders:
        exact = folder / f"{urdf.stem}.srdf"
        if exact.is_file():
            return exact
    best: Path | None = None
    for folder in folders:
        for candidate in sorted(folder.glob("*.srdf")):
            if urdf.stem.startswith(candidate.stem) and (
                best is None or len(candidate.stem) > len(best.stem)
            ):
                best = candidate
    return best


def _reference_configurations(model: pin.Model, srdf: Path | None) -> dict[str, np.ndarray]:
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


def _passive_joints(model: pin.Model, srdf: Path | None) -> tuple[str, ...]:
    """Names of the SRDF's ``<passive_joint name="..."/>`` entries that are joints of the model.

    Entries naming no joint of the model are ignored (logged at debug level), as is an SRDF that
    cannot be read. The order is the model's joint order.
    """
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


def _default_pose(configurations: Mapping[str, np.ndarray]) -> str | None:
    """Pick the pose that :meth:`Robot.neutral` returns."""
    for name in DEFAULT_POSE_NAMES:
        if name in configurations:
            return name
    return next(iter(configurations), None)


# ---------------------------------------------------------------------------------------------
# URDF validation


def _parse_xml(path: Path, text: str) -> ET.Element:
    """Parse the URDF text and check that its root is a ``<robot>``."""
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        line, column = exc.position
        reason = str(exc).split(":")[0]
        raise RobotDescriptionError(
            f"{path} is not well-formed XML: {reason} at line {line}, column {column + 1}."
        ) from exc
    if root.tag != "robot":
        raise RobotDescriptionError(
            f"{path} is not a URDF: its root element is <{root.tag}>, not <robot>."
        )
    return root


def _listed(problems: list[str]) -> str:
    """The first problems as an indented list, with how many more were left out."""
    shown = problems[:_MAX_PROBLEMS]
    more = len(problems) - len(shown)
    tail = f"\n  ... and {more} more" if more else ""
    return "".join(f"\n  - {problem}" for problem in shown) + tail


def _validate_urdf(path: Path, text: str) -> ET.Element:
    """Check a URDF thoroughly and return its root element.

    Raises:
        RobotDescriptionError: If the file is not well-formed XML or not a valid URDF; the message
            names the file and lists what is wrong.

    """
    root = _parse_xml(path, text)
    problems = _element_problems(root)
    if not problems:
        problems = _yourdfpy_problems(path)
    if problems:
        raise RobotDescriptionError(f"{path} is not a valid URDF:{_listed(problems)}")
    return root


def _element_problems(root: ET.Element) -> list[str]:
    """Problems that would make yourdfpy fail with an unhelpful error (missing names, tags)."""
    problems = []
    if any(element.tag.startswith("{http://wiki.ros.org/xacro}") for element in root.iter()):
        problems.append("it contains xacro elements: expand it with xacro first")
    if not root.get("name"):
        problems.append("the <robot> element has no 'name' attribute")
    links = root.findall("link")
    if not links:
        problems.append("it declares no <link>")
    for number, link in enumerate(links, start=1):
        if not link.get("name"):
            problems.append(f"link number {number} has no 'name' attribute")
            continue
        for kind in ("visual", "collision"):
            for element in link.findall(kind):
                geometry = element.find("geometry")
                shapes = [] if geometry is None else list(geometry)
                if len(shapes) != 1:
                    problems.append(
                        f"a <{kind}> of link {link.get('name')!r} needs a <geometry> with exactly "
                        "one <box>, <cylinder>, <sphere> or <mesh>"
                    )
    for number, joint in enumerate(root.findall("joint"), start=1):
        name = joint.get("name")
        label = f"joint {name!r}" if name else f"joint number {number}"
        if not name:
            problems.append(f"{label} has no 'name' attribute")
        if joint.get("type") not in _JOINT_TYPES:
            problems.append(
                f"{label} has type {joint.get('type')!r}; valid types: {', '.join(_JOINT_TYPES)}"
            )
        for tag in ("parent", "child"):
            element = joint.find(tag)
            if element is None or not element.get("link"):
                problems.append(f'{label} has no <{tag} link="..."/>')
    return problems


def _floats(text: str | None, count: int) -> list[float] | None:
    """``count`` numbers from an attribute (None when absent or malformed: yourdfpy says so)."""
    try:
        values = [float(x) for x in (text or "").split()]
    except ValueError:
        return None
    return values if len(values) == count else None


def _inertia_tolerance(largest: float) -> float:
    """How negative a moment of inertia [kg m^2] may be and still count as round-off.

    URDF files print about six significant digits, so a principal moment down to
    ``-1e-6 * largest`` is round-off; so is anything above ``-1e-9`` kg m^2 (tiny links print
    their inertias as ``1e-20``-ish noise).
    """
    return max(_INERTIA_ATOL, _INERTIA_RTOL * abs(largest))


def _link_problems(link: ET.Element) -> tuple[list[str], list[str]]:
    """Problems of one link's ``<inertial>``: (always fatal, fatal unless curated)."""
    fatal: list[str] = []
    lenient: list[str] = []
    inertial = link.find("inertial")
    if inertial is None:
        return fatal, lenient
    name = link.get("name")
    mass = inertial.find("mass")
    text = None if mass is None else mass.get("value")
    value = _floats(text, 1)
    if value is not None and not (math.isfinite(value[0]) and value[0] >= 0.0):
        fatal.append(
            f"link {name!r} has <mass value={text!r}/>; a mass must be a finite number >= 0 kg "
            "(0 is fine for a massless link)"
        )
    inertia = inertial.find("inertia")
    if inertia is None:
        return fatal, lenient
    texts = {key: inertia.get(key, "0") for key in _INERTIA_KEYS}
    try:
        values = {key: float(text) for key, text in texts.items()}
    except ValueError:
        return fatal, lenient  # malformed numbers: yourdfpy (or Pinocchio) reports them
    bad = [f"{key}={texts[key]!r}" for key, number in values.items() if not math.isfinite(number)]
    if bad:
        fatal.append(
            f"link {name!r} has a non-finite inertia ({', '.join(bad)}); ixx, ixy, ixz, iyy, iyz "
            "and izz must be finite numbers in kg m^2"
        )
        return fatal, lenient
    xx, xy, xz, yy, yz, zz = (values[key] for key in _INERTIA_KEYS)
    matrix = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
    eigenvalues = np.linalg.eigvalsh(matrix)
    tolerance = _inertia_tolerance(max(abs(eigenvalues[0]), abs(eigenvalues[-1])))
    negative = [f"{key}={texts[key]}" for key in ("ixx", "iyy", "izz") if values[key] < -tolerance]
    if negative:
        fatal.append(
            f"link {name!r} has a negative moment of inertia ({', '.join(negative)} kg m^2); "
            "ixx, iyy and izz must be >= 0"
        )
    elif eigenvalues[0] < -tolerance:
        shown = " ".join(f"{key}={texts[key]}" for key in _INERTIA_KEYS)
        lenient.append(
            f"link {name!r} has an inertia that is not positive semi-definite ({shown}: "
            f"smallest principal moment {eigenvalues[0]:.3g} kg m^2); the products of inertia "
            "are too large for the moments: a valid inertia has principal moments >= 0"
        )
    return fatal, lenient


def _joint_problems(joint: ET.Element) -> tuple[list[str], list[str]]:
    """Problems of one joint: (always fatal, fatal unless curated)."""
    fatal: list[str] = []
    lenient: list[str] = []
    name, kind = joint.get("name"), joint.get("type")
    axis = joint.find("axis")
    if axis is not None and kind in ("revolute", "continuous", "prismatic", "planar"):
        xyz = _floats(axis.get("xyz"), 3)
        if xyz is not None and not (all(map(math.isfinite, xyz)) and any(xyz)):
            fatal.append(
                f"joint {name!r} ({kind}) has <axis xyz={axis.get('xyz')!r}/>; its axis must be "
                "a finite, nonzero vector such as '0 0 1' (only fixed joints may have a zero axis)"
            )
    limit = joint.find("limit")
    if limit is not None and kind in ("revolute", "prismatic"):
        bounds = {key: _floats(limit.get(key, "0"), 1) for key in ("lower", "upper")}
        lower, upper = bounds["lower"], bounds["upper"]
        nan = [f"{key}={limit.get(key)!r}" for key, v in bounds.items() if v and math.isnan(v[0])]
        if nan:
            fatal.append(
                f"joint {name!r} has a limit that is not a number ({', '.join(nan)}); lower and "
                "upper must be numbers with lower <= upper"
            )
        elif lower is not None and upper is not None and lower[0] > upper[0]:
            missing = [key for key in ("lower", "upper") if limit.get(key) is None]
            note = f" (a missing {' and '.join(missing)} reads as 0)" if missing else ""
            fatal.append(
                f"joint {name!r} has limits lower={lower[0]:g} > upper={upper[0]:g}{note}; the "
                "lower limit must be <= the upper one (swap them; lower == upper is fine)"
            )
    mimic = joint.find("mimic")
    if mimic is not None:
        leader = mimic.get("joint")
        lenient.append(
            f"joint {name!r} mimics joint {leader!r} (<mimic joint={leader!r}/>): mimic joints "
            "are not supported (Pinocchio would load it as an independent joint); remove the "
            "<mimic> tag, and if the two joints must share the effort, declare the design "
            f"constraint EqualTorque({name!r}, {leader!r}) on the actuator"
        )
    return fatal, lenient


def _physics_problems(root: ET.Element, strict: bool = True) -> tuple[list[str], list[str]]:
    """What Pinocchio would load silently but no robot can be.

    Checked on the XML itself, before Pinocchio reads the file (it loads a NaN mass as 0): a
    zero or non-finite axis of a moving joint, a negative or non-finite mass, a non-finite or
    negative moment of inertia (beyond round-off), a limit with lower > upper or a NaN bound,
    an inertia that is not positive semi-definite and a ``<mimic>`` joint. Zero masses, fixed
    joints with any axis, continuous joints without limits and lower == upper are valid.

    Args:
        root: The ``<robot>`` element.
        strict: False for the curated example-robot-data files: several ship gripper fingers
            as mimic joints (loaded as independent joints, as Pinocchio does) and a few ship
            inertias that are not positive semi-definite; these two problems are then tolerated.

    Returns:
        The problems that forbid loading, and those tolerated (empty when ``strict``: they are
        in the first list then).

    """
    problems: list[str] = []
    tolerated: list[str] = []
    checks = [(_link_problems, link) for link in root.findall("link")]
    checks += [(_joint_problems, joint) for joint in root.findall("joint")]
    for check, element in checks:
        fatal, lenient = check(element)
        problems += fatal
        (problems if strict else tolerated).extend(lenient)
    return problems, tolerated


def _yourdfpy_problems(path: Path) -> list[str]:
    """Parse the URDF with yourdfpy (no meshes, no scene graph) and list what is wrong."""
    import yourdfpy  # imported here: it takes half a second (trimesh)

    try:
        urdf = yourdfpy.URDF.load(
            str(path),
            build_scene_graph=False,
            build_collision_scene_graph=False,
            load_meshes=False,
            load_collision_meshes=False,
        )
    except Exception as exc:  # yourdfpy raises ValueError, KeyError... on malformed values
        return [f"yourdfpy cannot parse it: {type(exc).__name__}: {exc}"]

    robot = urdf.robot
    problems = _tree_problems(
        [link.name for link in robot.links],
        [
            (joint.name, joint.type, joint.parent, joint.child, joint.limit)
            for joint in robot.joints
        ],
    )
    try:
        urdf.validate()
        errors = list(urdf.errors)
    except Exception as exc:
        errors = [f"{type(exc).__name__}: {exc}"]
    for error in errors:
        message = str(error)
        # urdfdom (hence Pinocchio) reads a missing lower/upper bound as 0, and limit problems
        # are reported above with the joint's name.
        if "<limit>" in message or "'lower'" in message or "'upper'" in message:
            continue
        if message not in problems:
            problems.append(message)
    return problems


def _tree_problems(links: list[str], joints: list[tuple[str, str, str, str, Any]]) -> list[str]:
    """Check that links and joints form one tree and that joints have the limits they need."""
    problems = []
    link_set = set(links)
    for name in sorted(link for link, count in Counter(links).items() if count > 1):
        problems.append(f"link {name!r} is declared more than once")
    parent_of: dict[str, str] = {}
    joint_names: set[str] = set()
    for name, kind, parent, child, limit in joints:
        if name in joint_names:
            problems.append(f"joint {name!r} is declared more than once")
        joint_names.add(name)
        for role, link in (("parent", parent), ("child", child)):
            if link not in link_set:
                problems.append(
                    f"joint {name!r} names the {role} link {link!r}, which is not declared. "
                    + suggestion(link, links, "links")
                )
        if child in parent_of:
            problems.append(
                f"link {child!r} is the child of two joints ({parent_of[child]!r} and {name!r})"
            )
        parent_of.setdefault(child, name)
        if kind in ("revolute", "prismatic") and limit is None:
            problems.append(f"joint {name!r} ({kind}) has no <limit> element")
        elif limit is not None and (limit.effort is None or limit.velocity is None):
            problems.append(f"the <limit> of joint {name!r} needs 'effort' and 'velocity'")
    roots = [link for link in dict.fromkeys(links) if link not in parent_of]
    parent_link = {child: parent for _, _, parent, child, _ in joints}
    looped = []
    for link in dict.fromkeys(links):
        seen = {link}
        while link in parent_link and parent_link[link] in link_set:
            link = parent_link[link]
            if link in seen:
                looped.append(link)
                break
            seen.add(link)
    if looped:
        problems.append(
            "its joints form a loop (through links "
            + ", ".join(repr(link) for link in dict.fromkeys(looped))
            + "): a URDF must be a tree"
        )
    elif len(roots) > 1:
        problems.append(
            "its links do not form a single tree: several links have no parent joint ("
            + ", ".join(repr(link) for link in roots[:8])
            + ")"
        )
    return problems
